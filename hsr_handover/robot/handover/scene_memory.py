"""What the robot keeps of the scenes it has seen (`remember`): the camera turns away, the
robot's arm passes in front of things, and things do not vanish meanwhile."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.robot.perception.depth_view import DepthView
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.planning.perceived_scene import ARM_PARTS, Capsule, PerceivedScene

STILL_M = 0.02
"""m: an object seen this near where it was (its footprint's centre and its top) has not moved;
the centre of a part of it seen past an arm shifts by about 1 cm."""
SIGHT_SAMPLES = 5  # points along a remembered capsule's axis checked against the view
ARM_MEMORY_S = 2.0
"""s an arm's part is remembered unseen while the rest of the person is seen: long enough for
the robot's arm to pass in front of it; a person's arm moves within that (a pointing gesture
ends and the arm comes to rest in 2 to 3 s)."""


def remember(last: PerceivedScene | None, scene: PerceivedScene) -> PerceivedScene:
    """The `scene` now, with what the camera has turned away from as it was `last` seen: the
    table, objects out of view, an object that has not moved as whole as it was seen, and each
    part of the person not seen now (things do not vanish, or shrink, or people lose limbs,
    when something passes in front of them or the robot looks at its hand). A part seen now is
    taken as seen now: while the whole person was kept until a view showed as many parts as the
    last, a view that lacked a hip's bone kept the person pointing, and the carry was planned
    into the arm that had come to rest on the table.
    A part not seen now is forgotten where the camera now sees through its place
    (`_seen_through`), and an arm's part unseen for ARM_MEMORY_S while the rest of the person
    is seen and its place is in sight (`_stale`): a pointing arm lowered out of sight below
    the table's edge was kept pointing, and the object it had pointed at stayed unreachable
    behind it for the rest of the handover (its wrist had been lifted onto the object, so the
    camera saw the object, not through it, where the arm had been). An arm out of view, or
    behind something nearer, is kept: a hand held out toward the robot, out of view while the
    camera watched its own grasp, was forgotten, and the carry was planned through it."""
    if last is None:
        return scene
    then = {shape.label: shape for shape in last.objects}
    now = tuple(_fuller(shape, then.get(shape.label)) for shape in scene.objects)
    seen = {shape.label for shape in scene.objects}
    parts = {capsule.part for capsule in scene.person}
    time = max((capsule.seen_at for capsule in scene.person), default=math.nan)
    kept = (
        capsule
        for capsule in last.person
        if capsule.part not in parts
        and not _stale(capsule, time, scene.view)
        and not _seen_through(capsule, scene.view)
    )
    return dataclasses.replace(
        scene,
        table=scene.table if scene.table is not None else last.table,
        objects=(*now, *(shape for label, shape in then.items() if label not in seen)),
        person=(*scene.person, *kept),
    )


def _stale(capsule: Capsule, time: float, view: DepthView | None) -> bool:
    """Whether `capsule` is an arm's part last seen ARM_MEMORY_S or longer before `time` (s;
    NaN, the person not seen now, when nothing is stale) whose place the `view` shows (no view
    kept: taken as shown)."""
    unseen_long = capsule.part in ARM_PARTS and time - capsule.seen_at >= ARM_MEMORY_S
    return unseen_long and (view is None or _in_sight(capsule, view))


def _axis_depths_past(capsule: Capsule, view: DepthView) -> np.ndarray:
    """`view.depth_past` at SIGHT_SAMPLES points along the capsule's axis, the measured ones
    (+inf: nothing in range behind)."""
    axis = np.linspace(0.0, 1.0, SIGHT_SAMPLES)[:, None] * (capsule.end - capsule.start)
    past = view.depth_past(capsule.start + axis)
    return past[~np.isnan(past)]


def _in_sight(capsule: Capsule, view: DepthView) -> bool:
    """Whether the camera sees where `capsule` is: at most of the points along its axis, a
    surface is measured no nearer than the capsule's radius in front of it (not out of view,
    not hidden by something nearer)."""
    past = _axis_depths_past(capsule, view)
    return np.count_nonzero(past >= -capsule.radius) > SIGHT_SAMPLES / 2


def _seen_through(capsule: Capsule, view: DepthView | None) -> bool:
    """Whether the camera sees past where `capsule` is: at most of the points along its axis
    that the `view` measures, the surface seen lies farther behind than the capsule's radius
    (a part hidden by something nearer, or out of view, is not seen through)."""
    if view is None:
        return False
    measured = _axis_depths_past(capsule, view)
    return measured.size > 0 and np.count_nonzero(measured > capsule.radius) > measured.size / 2


def _fuller(now: ObjectShape, then: ObjectShape | None) -> ObjectShape:
    """The object as seen `now`, unless it stands where it was seen `then` (its footprint's
    centre and its top within STILL_M) and shows less of itself now: an arm in front of it
    hides part of it, which shrinks its footprint and turns its yaw (a 7 cm box seen 5.7 cm
    long and 9.6 degrees off as a pointing arm lowered over it, and the fingers approaching
    along that struck it)."""
    if then is None or then.kind != now.kind:
        return now
    top_moved = abs((now.bottom + now.height) - (then.bottom + then.height))
    moved = max(float(np.linalg.norm(now.center - then.center)), top_moved) > STILL_M
    return now if moved or np.prod(now.size) >= np.prod(then.size) else then
