"""What the robot keeps of a scene it looks away from."""

from __future__ import annotations

import numpy as np

from hsr_handover.handover.perceived_planner import remember
from hsr_handover.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.perception.table_fit import TableEstimate
from hsr_handover.planning.perceived_scene import Capsule, PerceivedScene

TABLE = TableEstimate(0.72, np.array([0.85, 0.0]), np.array([0.6, 1.0]), 0.0, 5000)


def _cup(label: str, x: float) -> ObjectShape:
    return ObjectShape(label, CYLINDER, np.array([x, 0.0]), np.array([0.07, 0.07]), 0.0,
                       0.72, 0.1)  # fmt: skip


def _capsules(count: int) -> tuple[Capsule, ...]:
    return tuple(Capsule(np.array([1.7, 0.1 * k, 0.5]), np.array([1.7, 0.1 * k, 1.0]), 0.1)
                 for k in range(count))  # fmt: skip


def test_what_is_out_of_view_is_kept_as_last_seen():
    last = PerceivedScene(TABLE, (_cup("red", 0.8), _cup("blue", 0.9)), _capsules(9))
    now = PerceivedScene(None, (_cup("red", 1.2),), _capsules(2))  # looking at the hand
    kept = remember(last, now)
    assert kept.table is TABLE
    assert {shape.label: shape.center[0] for shape in kept.objects} == {"red": 1.2, "blue": 0.9}
    assert kept.person == last.person  # a partial view does not shrink the person


def test_a_whole_view_replaces_the_memory():
    last = PerceivedScene(TABLE, (_cup("red", 0.8),), _capsules(9))
    now = PerceivedScene(TABLE, (_cup("red", 0.8),), _capsules(9)[::-1])
    assert remember(last, now).person == now.person
    assert remember(None, now) is now
