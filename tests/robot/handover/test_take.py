"""Feeling the object taken while presenting it, in physical terms: the wrist's force sensor,
the palm pulled off its command, the fingers' opening, the hand seen at the object, and where
the camera sees an object that has left the fingers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import Percepts
from hsr_handover.robot.handover.take import Emptied, TakeDetector

PALM = np.array([1.0, 0.0, 1.0])
PERSON = np.array([1.6, 0.0, 1.2])  # the receiving shoulder, ahead of the palm and above it
HANGING = np.array([0.0, 0.0, -8.0])  # N: the hand and the object on the wrist, as carried
WIDTH = 0.06  # m: the fingers closed on a 6 cm object
STOOD = np.array([0.8, 0.0, 0.76])  # where the object stood on the table
TICK = 0.1  # s between decisions


def _toward_person(newtons: float, off_deg: float = 0.0) -> np.ndarray:
    """A force of `newtons`, turned `off_deg` degrees sideways (about the vertical) from the
    direction from the palm to the person."""
    toward = (PERSON - PALM) / np.linalg.norm(PERSON - PALM)
    side = np.cross(toward, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side)
    angle = math.radians(off_deg)
    return newtons * (math.cos(angle) * toward + math.sin(angle) * side)


def _across(newtons: float) -> np.ndarray:
    """A horizontal force of `newtons` square to the way to the person."""
    return _toward_person(newtons, 90.0)


def _percepts(time: float = 0.0, force: np.ndarray | None = None, **changes) -> Percepts:
    """Percepts at `time` of the object held out at PALM, `force` (N) more on the wrist than
    as carried."""
    change = np.zeros(3) if force is None else force
    fields = {"opening": WIDTH, "palm": PALM, "person": PERSON, "wrist_force": HANGING + change}
    fields.update(changes)
    return Percepts(time, np.zeros(3), **fields)


def _detector() -> TakeDetector:
    return TakeDetector(HANGING.copy(), WIDTH, CycleParams())


def _feel_twice(force: np.ndarray) -> list[bool]:
    """Whether the object was felt held at each of two decisions with `force` on it."""
    detector = _detector()
    return [detector.feel(_percepts(t, force), PERSON).held for t in (0.0, TICK)]


# A tug toward the person ---------------------------------------------------------------------


def test_a_gentle_5_n_tug_toward_the_person_is_a_hold_once_felt_twice_in_a_row():
    """People tug at 5-15 N to take an object."""
    assert _detector().tug(_percepts(force=_toward_person(5.0)), PERSON) == pytest.approx(5.0)
    assert _feel_twice(_toward_person(5.0)) == [False, True]


def test_a_2_n_sway_of_the_arm_is_no_tug():
    """The arm's own accelerations while presenting move a few hundred grams: twice that is
    still no hold."""
    assert _feel_twice(_toward_person(2.0)) == [False, False]


def test_a_knock_felt_at_one_decision_only_is_no_hold():
    detector = _detector()
    knock, rest = _toward_person(10.0), np.zeros(3)
    felt = [detector.feel(_percepts(t * TICK, f), PERSON).held for t, f in
            enumerate((knock, rest, knock, rest))]  # fmt: skip
    assert felt == [False] * 4


def test_a_10_n_pull_30_degrees_off_the_person_is_a_tug():
    """A hand closing on the object a little from the side still draws it toward the person."""
    assert _feel_twice(_toward_person(10.0, off_deg=30.0)) == [False, True]


def test_a_10_n_push_60_degrees_off_the_person_is_no_tug():
    """A hand closing on the object from the side pushes it sideways."""
    assert _detector().tug(_percepts(force=_toward_person(10.0, off_deg=60.0)), PERSON) == 0.0
    assert _feel_twice(_toward_person(10.0, off_deg=60.0)) == [False, False]


def test_a_pull_across_held_for_0_3_s_is_a_hold_and_a_shorter_one_is_not():
    """A person can draw the object in sideways, their hand beside the robot's fingers: never a
    tug toward the shoulder, but held."""
    pull = _toward_person(6.0, off_deg=65.0)
    detector = _detector()
    felt = [detector.feel(_percepts(t * TICK, pull), PERSON).held for t in range(4)]
    assert felt == [False, False, False, True]
    detector, rest = _detector(), np.zeros(3)
    felt = [detector.feel(_percepts(t * TICK, f), PERSON).held for t, f in
            enumerate((pull, pull, pull, rest, pull, pull))]  # fmt: skip
    assert felt == [False] * 6  # let up between: each pull is timed afresh


def test_a_load_that_lightens_as_the_object_slips_is_no_tug():
    """The object's weight going from the fingers is a change straight up: not toward the
    person, however heavy the object."""
    assert _feel_twice(np.array([0.0, 0.0, 6.0])) == [False, False]


def test_without_the_sensor_or_a_person_seen_nothing_is_felt():
    assert TakeDetector(None, WIDTH, CycleParams()).tug(_percepts(), PERSON) == 0.0
    assert _detector().tug(_percepts(force=_toward_person(10.0)), None) == 0.0


# The palm pulled off its command --------------------------------------------------------------


def test_the_palm_pulled_2_cm_off_its_command_is_a_hold():
    assert _detector().feel(_percepts(pull=0.02), PERSON).held


def test_the_arms_own_5_mm_sag_is_no_hold():
    assert not _detector().feel(_percepts(pull=0.005), PERSON).held


# Fingers forced open ------------------------------------------------------------------------


def test_fingers_forced_3_cm_wider_than_the_object_is_a_take():
    """The person draws the object out between the fingers: the gripper yields before the
    arm."""
    assert _detector().feel(_percepts(opening=WIDTH + 0.03), PERSON).taken


def test_fingers_giving_1_cm_as_the_object_is_held_out_is_no_take():
    assert not _detector().feel(_percepts(opening=WIDTH + 0.01), PERSON).taken


def test_fingers_forced_open_by_a_5_n_knock_across_is_no_take():
    """A hand striking the object on its way in forces the fingers open too."""
    knocked = _percepts(opening=WIDTH + 0.03, force=_across(5.0))
    assert _detector().knocked(knocked, PERSON)
    assert not _detector().feel(knocked, PERSON).taken


def test_fingers_forced_open_with_2_n_across_is_a_take():
    """Less than a knock: the object drawn out of the fingers, a little sideways."""
    drawn = _percepts(opening=WIDTH + 0.03, force=_across(2.0))
    assert not _detector().knocked(drawn, PERSON)
    assert _detector().feel(drawn, PERSON).taken


# Fingers closing on nothing ------------------------------------------------------------------


def _emptied_after(seconds: float, before: Percepts, opening: float = 0.0) -> bool:
    """Whether fingers closing to `opening`, `seconds` after the decision `before`, are a
    take."""
    detector = _detector()
    detector.feel(before, PERSON)
    return detector.feel(_percepts(seconds, opening=opening), PERSON).taken


def test_fingers_emptied_half_a_second_after_a_hand_was_at_the_object_is_a_take():
    """The wrist keypoint sits about 27 cm from an object the person closes a hand on."""
    hand = PALM + [0.27, 0.0, 0.0]
    assert _emptied_after(0.5, _percepts(hand=hand))


def test_fingers_emptied_after_a_hand_50_cm_off_is_no_take():
    """A hand held out half a metre off has not closed on the object."""
    assert not _emptied_after(0.5, _percepts(hand=PALM + [0.5, 0.0, 0.0]))


def test_fingers_emptied_2_s_after_a_hand_was_at_the_object_is_no_take():
    assert not _emptied_after(2.0, _percepts(hand=PALM + [0.27, 0.0, 0.0]))


def test_fingers_emptied_soon_after_a_7_n_pull_across_is_a_take():
    """A hand the robot's arm hides draws the object out sideways: something other than
    gravity had hold of it, at one decision only, the fingers still holding."""
    assert _emptied_after(0.5, _percepts(force=_across(7.0)))


def test_fingers_emptied_soon_after_a_2_n_pull_across_is_no_take():
    assert not _emptied_after(0.5, _percepts(force=_across(2.0)))


def test_fingers_closed_to_5_mm_are_empty():
    """Closed on nothing, the fingers read a few mm at most."""
    assert _emptied_after(0.5, _percepts(hand=PALM + [0.27, 0.0, 0.0]), opening=0.005)


def test_fingers_closed_on_a_2_cm_object_hold_it():
    """A thin object held: neither drawn out nor dropped."""
    before = _percepts(hand=PALM + [0.27, 0.0, 0.0])
    assert not _emptied_after(0.5, before, opening=0.02)


# Where the object went, fingers empty with no hand seen -------------------------------------


def _verdicts(times: tuple[float, ...], seen: np.ndarray | None) -> list[Emptied]:
    detector = _detector()
    return [detector.emptied(_percepts(t, opening=0.0, object_seen=seen), STOOD) for t in times]


def test_empty_fingers_stand_still_and_look_before_judging():
    """A dropped object falls from the presenting height to the table in about 0.25 s: the
    robot judges after half a second, not sooner."""
    verdicts = _verdicts((0.0, 0.3, 0.7), STOOD)
    assert verdicts == [Emptied.JUST_NOW, Emptied.LOOKING, Emptied.DROPPED]


def test_an_object_seen_15_cm_above_where_it_stood_was_taken():
    """Held out in the person's hand, it is 15-30 cm up."""
    assert _verdicts((0.0, 0.7), STOOD + [0.3, 0.0, 0.15])[-1] is Emptied.TAKEN


def test_an_object_seen_4_cm_above_where_it_stood_was_dropped():
    """Fallen back and lying against another object, it is a few cm up."""
    assert _verdicts((0.0, 0.7), STOOD + [0.1, 0.0, 0.04])[-1] is Emptied.DROPPED


def test_an_object_out_of_sight_is_unseen_not_yet_dropped():
    """Nowhere in the camera's view: the robot's own hand may hide it in the person's."""
    assert _verdicts((0.0, 0.7), None)[-1] is Emptied.UNSEEN


def test_fingers_that_hold_again_restart_the_wait():
    detector = _detector()
    assert detector.emptied(_percepts(0.0, opening=0.0), STOOD) is Emptied.JUST_NOW
    detector.feel(_percepts(0.3), PERSON)  # holding again: a glitch of the opening's sensor
    assert detector.emptied(_percepts(0.6, opening=0.0), STOOD) is Emptied.JUST_NOW
