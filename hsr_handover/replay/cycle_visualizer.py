"""CycleVisualizer: what the robot thinks, drawn in Meshcat over the run, from the robot's
outputs only: the pointing and gaze rays while it watches for a request, the recognised
target (where its camera sees it, or in its hand while it holds it), the palm's planned path,
the arm's effectivity nodes at the handover base, the person's reachable range, the mutual area
in red (paper fig. 14) and the handover point. Each is an overlay (`replay.overlays`): a
parent path under OVERLAYS that the viewer's controls switch, and below it what is drawn.

A recording replays transforms and properties, not new objects: the rays, the target's mark
and the handover point are drawn once and moved and shown by recorded keyframes on their
`mark` child; a new path or new maps are new snapshots whose visibility the recording animates
(`meshcat_recording.Snapshots`). Only children are animated, so a user's untick holds.
"""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import Cylinder, Meshcat, Sphere
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.framework import Context, LeafSystem

from hsr_handover.hsr import ARM_JOINTS, BASE_JOINTS, COMMANDED_JOINTS
from hsr_handover.kinematics.hsr_arm import palm_pose
from hsr_handover.replay.meshcat_recording import Snapshots, set_pose, set_visible
from hsr_handover.replay.overlays import (
    ARM_MAP,
    GAZE_RAY,
    HANDOVER_POINT,
    HANDOVER_POINT_RADIUS,
    MUTUAL_AREA,
    PALM_PATH,
    PERSON_RANGE,
    POINTING_RAY,
    TARGET,
    Overlay,
    draw_points,
)
from hsr_handover.robot.handover.cycle_types import CycleRecord, Phase
from hsr_handover.robot.intent import IntentState
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.plan_view import PlanView
from hsr_handover.robot.systems.watching import declare_watching_input, is_watching

RAY_LENGTH = 1.2  # m drawn of each ray from its origin
RAY_RADIUS = 0.006  # m
RAYS = (POINTING_RAY, GAZE_RAY)
TARGET_RADIUS = 0.08  # m: a halo round the object recognised
PATH_WIDTH = 3.0
MAPS = (ARM_MAP, PERSON_RANGE, MUTUAL_AREA)
KEEP = 60  # snapshots kept of each changing layer (a cycle plans a handful of times)
IN_HAND = frozenset({Phase.GRASP, Phase.LIFT, Phase.CARRY, Phase.PUT_BACK, Phase.PRESENT,
                     Phase.RELEASE})  # fmt: skip
"""The phases in which the robot believes it has the target between its fingers."""
ON_THE_TABLE = frozenset({Phase.WATCH, Phase.APPROACH})
"""The phases before it grasps: the target stays where it was last seen while out of view."""
_BASE = [COMMANDED_JOINTS.index(joint) for joint in BASE_JOINTS]
_ARM = [COMMANDED_JOINTS.index(joint) for joint in ARM_JOINTS]


class CycleVisualizer(LeafSystem):
    """Inputs, all robot outputs: `intent` (IntentState), `intent_rays` ((pointing, gaze)
    Rays or None), `detections` (DetectionResult), `plan_view` (PlanView), and optionally
    `watching` (1 while the intent estimator judges frames; unconnected, always), `cycle`
    (CycleRecord: the target fetched and the phase) and `hsr_desired_state` (the commanded
    joints: where the hand holding the target is). Draws them every `publish_period` s.

    The rays show while the robot watches (at rest, the estimator's last rays are stale);
    the target's mark from its recognition: at its detection, or where last seen while still
    on the table, or between the commanded finger pads while the robot holds it, and after
    the handover only where seen. Like Drake's MeshcatVisualizer, what has been drawn is kept
    in the system: publish events cannot change the Context."""

    def __init__(self, meshcat: Meshcat, publish_period: float = 0.1):
        super().__init__()
        if not publish_period > 0:
            raise ValueError(f"publish_period: expected a positive period, got {publish_period}")
        self._meshcat = meshcat
        self._intent = self.DeclareAbstractInputPort("intent", AbstractValue.Make(IntentState()))
        self._rays = self.DeclareAbstractInputPort("intent_rays", AbstractValue.Make((None, None)))
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self._plan = self.DeclareAbstractInputPort("plan_view", AbstractValue.Make(PlanView()))
        self._watching = declare_watching_input(self)
        self._cycle = self.DeclareAbstractInputPort("cycle", AbstractValue.Make(CycleRecord()))
        self._command = self.DeclareVectorInputPort("hsr_desired_state", 2 * len(COMMANDED_JOINTS))
        self._path = Snapshots(meshcat, PALM_PATH.path, KEEP)
        self._maps = {overlay.name: Snapshots(meshcat, overlay.path, KEEP) for overlay in MAPS}
        self._drawn: PlanView | None = None
        self._visible: dict[str, bool] = {}
        self._target: tuple[str | None, np.ndarray | None] = (None, None)  # label, last place
        self.DeclareInitializationPublishEvent(self._draw_fixed)
        self.DeclarePeriodicPublishEvent(publish_period, 0.0, self._publish)
        self.DeclareForcedPublishEvent(self._publish)

    def _draw_fixed(self, context: Context) -> None:
        """The marks that only move: drawn once, hidden until there is something to show."""
        for overlay in (*RAYS, TARGET, HANDOVER_POINT):
            self._meshcat.Delete(overlay.path)
        self._drawn, self._visible, self._target = None, {}, (None, None)
        for snapshots in (self._path, *self._maps.values()):
            snapshots.clear()
        for overlay in RAYS:
            self._meshcat.SetObject(overlay.mark, Cylinder(RAY_RADIUS, RAY_LENGTH), overlay.rgba)
        self._meshcat.SetObject(TARGET.mark, Sphere(TARGET_RADIUS), TARGET.rgba)
        self._meshcat.SetObject(
            HANDOVER_POINT.mark, Sphere(HANDOVER_POINT_RADIUS), HANDOVER_POINT.rgba
        )
        for overlay in (*RAYS, TARGET, HANDOVER_POINT):
            self._show(overlay, False, context.get_time())

    def _publish(self, context: Context) -> None:
        time = context.get_time()
        watching = is_watching(self._watching, context)
        for overlay, ray in zip(RAYS, self._rays.Eval(context), strict=True):
            self._place(overlay, _ray_pose(ray) if watching and ray is not None else None, time)
        place = self._target_place(context)
        self._place(TARGET, None if place is None else RigidTransform(place), time)
        view: PlanView = self._plan.Eval(context)
        self._draw_plan(view, time)
        self._drawn = view

    def _target_place(self, context: Context) -> np.ndarray | None:
        """Where the robot believes the target is now (m, world), None if it has none."""
        record = self._cycle.Eval(context) if self._cycle.HasValue(context) else CycleRecord()
        label = record.target or self._intent.Eval(context).target
        last = self._target[1] if self._target[0] == label else None
        place = None if label is None else self._believed(context, record.phase, label, last)
        self._target = (label, place if place is not None else last)
        return place

    def _believed(
        self, context: Context, phase: Phase, label: str, last: np.ndarray | None
    ) -> np.ndarray | None:
        """The target `label` between the commanded pads while the robot holds it, else where
        seen now, else (still on the table) where `last` placed."""
        if phase in IN_HAND and self._command.HasValue(context):
            return pads_in_world(self._command.Eval(context))
        seen = self._detections.Eval(context).seen(label)
        return last if seen is None and phase in ON_THE_TABLE else seen

    def _draw_plan(self, view: PlanView, time: float) -> None:
        """New snapshots of what changed (values compared: ports hand out copies)."""
        drawn = self._drawn
        if drawn is None or not np.array_equal(view.palm_path, drawn.palm_path):
            if len(view.palm_path) > 1:
                self._path.show(lambda path: self._line(path, view.palm_path), time)
            else:
                self._path.hide(time)
        if drawn is not None and _same_point(view.handover_point, drawn.handover_point):
            return
        layers = ((ARM_MAP, view.arm_nodes[~view.mutual]), (PERSON_RANGE, view.person_nodes),
                  (MUTUAL_AREA, view.arm_nodes[view.mutual]))  # fmt: skip
        for overlay, points in layers:
            self._draw_map(overlay, points, time)
        point = view.handover_point
        self._place(HANDOVER_POINT, None if point is None else RigidTransform(point), time)

    def _draw_map(self, overlay: Overlay, points: np.ndarray, time: float) -> None:
        """A new snapshot of the map's `points` shown from `time` (none: the old one hidden)."""
        snapshots = self._maps[overlay.name]
        if len(points):
            snapshots.show(
                lambda path: draw_points(self._meshcat, path, points, overlay.rgba), time
            )
        else:
            snapshots.hide(time)

    def _place(self, overlay: Overlay, pose: RigidTransform | None, time: float) -> None:
        if pose is not None:
            set_pose(self._meshcat, overlay.mark, pose, time)
        self._show(overlay, pose is not None, time)

    def _show(self, overlay: Overlay, visible: bool, time: float) -> None:
        if self._visible.get(overlay.name) != visible:  # a keyframe only where it changes
            set_visible(self._meshcat, overlay.mark, visible, time)
            self._visible[overlay.name] = visible

    def _line(self, path: str, points: np.ndarray) -> None:
        self._meshcat.SetLine(path, np.asfortranarray(points.T), PATH_WIDTH, PALM_PATH.rgba)


def pads_in_world(command: np.ndarray) -> np.ndarray:
    """The centre between the finger pads (m, world) where the robot commands its hand: the
    arm's forward kinematics at the commanded base and arm joints of `command` ([q; v] or q of
    COMMANDED_JOINTS)."""
    command = np.asarray(command, dtype=float)
    x, y, yaw = command[_BASE]
    position, rotation = palm_pose(command[_ARM])
    pads = position + rotation @ np.array([0.0, 0.0, PAD_OFFSET])
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([x + c * pads[0] - s * pads[1], y + s * pads[0] + c * pads[1], pads[2]])


def _same_point(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    return (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))


def _ray_pose(ray) -> RigidTransform:
    """The pose of a RAY_LENGTH cylinder (along its z, centred) lying along `ray`."""
    direction = np.asarray(ray.direction, dtype=float)
    rotation = RotationMatrix.MakeFromOneVector(direction, 2)
    return RigidTransform(rotation, np.asarray(ray.origin) + RAY_LENGTH / 2 * direction)
