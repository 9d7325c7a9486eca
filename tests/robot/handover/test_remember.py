"""What the robot keeps of a scene it looks away from."""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.handover.scene_memory import ARM_MEMORY_S, STILL_M, remember
from hsr_handover.robot.perception.depth_view import DepthView
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.perceived_scene import BODY_PART, Capsule, PerceivedScene

TABLE = TableEstimate(0.72, np.array([0.85, 0.0]), np.array([0.6, 1.0]), 0.0, 5000)


def _cup(label: str, x: float) -> ObjectShape:
    return ObjectShape(label, CYLINDER, np.array([x, 0.0]), np.array([0.07, 0.07]), 0.0,
                       0.72, 0.1)  # fmt: skip


def _capsules(count: int, x: float = 1.7) -> tuple[Capsule, ...]:
    return tuple(Capsule(np.array([x, 0.1 * k, 0.5]), np.array([x, 0.1 * k, 1.0]), 0.1, f"{k}")
                 for k in range(count))  # fmt: skip


def test_what_is_out_of_view_is_kept_as_last_seen():
    last = PerceivedScene(TABLE, (_cup("red", 0.8), _cup("blue", 0.9)), _capsules(9))
    now = PerceivedScene(None, (_cup("red", 1.2),), _capsules(2))  # looking at the hand
    kept = remember(last, now)
    assert kept.table is TABLE
    assert {shape.label: shape.center[0] for shape in kept.objects} == {"red": 1.2, "blue": 0.9}
    # A partial view does not shrink the person: the parts not seen are kept as last seen.
    assert sorted(capsule.part for capsule in kept.person) == sorted(str(k) for k in range(9))
    assert kept.person[:2] == now.person


def test_the_parts_seen_now_replace_their_memory_though_others_are_unseen():
    last = PerceivedScene(TABLE, (_cup("red", 0.8),), _capsules(9))
    now = PerceivedScene(TABLE, (_cup("red", 0.8),), _capsules(8, x=1.5))  # an arm came down
    kept = remember(last, now).person
    assert len(kept) == 9
    assert [capsule.start[0] for capsule in kept] == [1.5] * 8 + [1.7]
    assert remember(None, now) is now


def _box(center, size, yaw: float, height: float = 0.1) -> ObjectShape:
    return ObjectShape("purple", BOX, np.array(center), np.array(size), yaw, 0.76, height)


def test_an_object_partly_hidden_where_it_stood_is_kept_as_seen_whole():
    """A box seen whole, then past a pointing arm 1 cm off, 5.7 cm long rather than 7 and
    turned 9.6 degrees."""
    whole = _box([0.7996, 0.2015], [0.0499, 0.0697], -1.173)
    hidden = _box([0.7918, 0.1949], [0.0484, 0.0574], -1.336)
    last = PerceivedScene(TABLE, (whole,), ())
    assert remember(last, PerceivedScene(TABLE, (hidden,), ())).objects == (whole,)
    fuller = _box([0.80, 0.20], [0.050, 0.071], -1.17)  # seen whole again: the newer view
    assert remember(last, PerceivedScene(TABLE, (fuller,), ())).objects == (fuller,)


def test_an_object_that_moved_is_taken_as_seen_now_however_little_shows():
    whole = _box([0.80, 0.20], [0.05, 0.07], -1.17)
    last = PerceivedScene(TABLE, (whole,), ())
    pushed = _box([0.80 + 1.5 * STILL_M, 0.20], [0.04, 0.05], -1.17)
    lifted = _box([0.80, 0.20], [0.04, 0.05], -1.17, height=0.1 + 1.5 * STILL_M)
    for now in (pushed, lifted):
        assert remember(last, PerceivedScene(TABLE, (now,), ())).objects == (now,)


def _view_from_above(depth_value: float) -> DepthView:
    """A camera 3 m up looking straight down over (1.2, 0), seeing `depth_value` m everywhere
    (its image spans about 2.2 x 1.6 m at the table's height)."""
    camera = PinholeCamera.from_fov_x(80, 60, 1.2)
    X_WC = RigidTransform(RollPitchYaw(np.pi, 0, 0), [1.2, 0.0, 3.0]).GetAsMatrix4()
    return DepthView(camera, X_WC, np.full((60, 80), depth_value, np.float32))


def test_a_part_not_seen_is_forgotten_where_the_camera_now_sees_through_its_place():
    """A pointing forearm lowered under the table's edge is not planned around where it
    pointed for the rest of the handover."""
    forearm = Capsule(np.array([1.3, -0.1, 0.86]), np.array([0.9, -0.1, 0.9]), 0.095, "fore")
    last = PerceivedScene(TABLE, (), (forearm, *_capsules(1)))
    table_seen = 3.0 - 0.72  # the camera sees the table's top past where the arm was
    now = PerceivedScene(TABLE, (), _capsules(1), _view_from_above(table_seen))
    assert [capsule.part for capsule in remember(last, now).person] == ["0"]
    # Something nearer than the arm where it was (the robot's own arm) hides it: kept.
    hidden = dataclasses.replace(now, view=_view_from_above(3.0 - 1.2))
    assert [capsule.part for capsule in remember(last, hidden).person] == ["0", "fore"]
    # Seen through only near its elbow (at most 2 of the 5 points along it): kept.
    hand_hidden = _view_from_above(table_seen)
    hand_hidden.depth[:, :40] = 3.0 - 1.2  # the image's left half: the world's x < 1.2
    partly = dataclasses.replace(now, view=hand_hidden)
    assert [capsule.part for capsule in remember(last, partly).person] == ["0", "fore"]
    # Out of the camera's view (it looks at its hand), or no view kept: kept.
    away = PerceivedScene(TABLE, (), _capsules(1), _view_from_above(np.nan))
    for scene in (away, dataclasses.replace(now, view=None)):
        assert len(remember(last, scene).person) == 2


def test_an_arm_unseen_for_a_while_is_forgotten_while_the_person_is_seen():
    """Its wrist lifted onto the object it pointed at, the lowered arm lay along the camera's
    line of sight through the object: no view saw through it."""
    arm = ("r_shoulder-r_elbow", "r_elbow-r_wrist")
    parts_then = (*arm, "neck-nose")
    seen_then = tuple(dataclasses.replace(capsule, part=part, seen_at=6.0)
                      for capsule, part in zip(_capsules(3), parts_then, strict=True))  # fmt: skip
    last = PerceivedScene(TABLE, (), seen_then)
    body = dataclasses.replace(_capsules(1)[0], part=BODY_PART)

    def parts(time: float, view: DepthView | None = None) -> set[str]:
        now = PerceivedScene(TABLE, (), (dataclasses.replace(body, seen_at=time),), view)
        return {capsule.part for capsule in remember(last, now).person}

    assert parts(6.0 + ARM_MEMORY_S - 0.1) == {*arm, "neck-nose", BODY_PART}
    assert parts(6.0 + ARM_MEMORY_S) == {"neck-nose", BODY_PART}  # a head does not move off
    # The camera sees a surface where the arm was (the object its wrist was lifted onto).
    at_the_arm = _view_from_above(3.0 - 0.75)
    assert parts(6.0 + ARM_MEMORY_S, at_the_arm) == {"neck-nose", BODY_PART}
    # Its place out of view, or behind something nearer (the robot's own arm), it is kept: a
    # hand held out while the camera watched the grasp (the carry was planned through it).
    for unseen in (_view_from_above(np.nan), _view_from_above(3.0 - 1.2)):
        assert parts(6.0 + ARM_MEMORY_S, unseen) == {*arm, "neck-nose", BODY_PART}
    # The person out of view (the robot looks at its hand): nothing is forgotten.
    assert len(remember(last, PerceivedScene(TABLE)).person) == 3
