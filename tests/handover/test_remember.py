"""What the robot keeps of a scene it looks away from."""

from __future__ import annotations

import numpy as np

from hsr_handover.handover.perceived_planner import STILL_M, remember
from hsr_handover.perception.object_shapes import BOX, CYLINDER, ObjectShape
from hsr_handover.perception.table_fit import TableEstimate
from hsr_handover.planning.perceived_scene import Capsule, PerceivedScene

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
    """The standing layout's trial 8 of seed 2: the box seen whole, then past a pointing arm
    1 cm off, 5.7 cm long rather than 7 and turned 9.6 degrees."""
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
