"""The handover trial's scoring rules (TrialWatch) on plain observations."""

import math

import pytest

from hsr_handover.experiments.handover.scoring import DROPPED, LIFTED, TrialWatch
from hsr_handover.experiments.true_clearance import HAND, PERSON, ROBOT, TABLE

START = {"cup": 0.77, "box": 0.78}
HELD = [(ROBOT, "cup")]  # the fingers on the cup


def _carried() -> TrialWatch:
    watch = TrialWatch("cup")
    watch.observe(0.0, dict(START), [], "")
    watch.observe(1.0, START | {"cup": START["cup"] + 2 * LIFTED}, HELD, "")
    assert watch.score.lifted == {"cup": 1.0} and watch.carrying()
    return watch


def test_an_object_held_out_low_by_the_robot_has_not_dropped():
    watch = _carried()
    watch.observe(2.0, START | {"cup": START["cup"]}, HELD, "")
    assert math.isnan(watch.score.dropped) and watch.carrying()


def test_an_object_down_low_touching_nothing_of_the_robot_has_dropped():
    watch = _carried()
    watch.observe(2.0, START | {"cup": START["cup"] + DROPPED / 2}, [("cup", TABLE)], "")
    assert watch.score.dropped == 2.0 and not watch.carrying()
    assert math.isnan(watch.score.table_contact)  # the object dropped, not carried to the table


def test_an_object_the_person_holds_is_taken_not_dropped():
    watch = _carried()
    watch.observe(2.0, START | {"cup": 0.9}, HELD + [("cup", HAND)], "cup")
    watch.observe(3.0, START | {"cup": START["cup"]}, [("cup", HAND)], "cup")
    assert watch.score.gripped == 2.0 and math.isnan(watch.score.dropped)


@pytest.mark.parametrize(
    ("pair", "field"),
    [
        ((ROBOT, TABLE), "table_contact"),
        (("cup", TABLE), "table_contact"),
        ((PERSON, ROBOT), "person_contact"),
        ((ROBOT, HAND), "person_contact"),
        (("cup", PERSON), "person_contact"),
    ],
)
def test_the_robot_or_what_it_carries_touching_the_table_or_person_is_counted(pair, field):
    watch = _carried()
    watch.observe(2.0, START | {"cup": 0.9}, HELD + [pair], "")
    watch.observe(3.0, START | {"cup": 0.9}, HELD + [pair], "")
    assert getattr(watch.score, field) == 2.0  # the first time


def test_the_carried_object_in_the_persons_hand_and_other_objects_knocked():
    watch = _carried()
    watch.observe(2.0, START | {"cup": 0.9}, HELD + [("cup", HAND), (ROBOT, "box")], "")
    assert math.isnan(watch.score.person_contact)  # the hand is there to take it
    assert watch.score.knocked == {"box": 2.0}


def test_the_table_touched_by_an_object_not_yet_lifted_is_not_the_robots_contact():
    watch = TrialWatch("cup")
    watch.observe(0.0, dict(START), [("cup", TABLE), ("box", TABLE)], "")
    assert math.isnan(watch.score.table_contact) and not watch.carrying()


def test_the_person_touching_an_object_before_the_robot_lifts_it_is_the_persons_knock():
    """The world's doing, counted apart from the robot's (moved seed 2 trial 57: a pointing
    hand pushed the box asked for over)."""
    watch = TrialWatch("cup")
    watch.observe(0.0, dict(START), [], "")
    watch.observe(0.5, dict(START), [(HAND, "cup"), ("box", PERSON)], "")
    assert watch.score.person_knocked == {"cup": 0.5, "box": 0.5}
    assert watch.score.knocked == {} and math.isnan(watch.score.person_contact)
    taken = _carried()
    taken.observe(2.0, START | {"cup": 0.9}, HELD + [("cup", HAND)], "cup")  # the handover
    assert taken.score.person_knocked == {}


def test_an_object_lifted_by_mistake_is_the_robots_load_until_it_is_set_down_again():
    """The box lifted first (the request misread) and carried back: its touching the person,
    or the table while still up, is the robot's contact; set down on the table it is not, and
    `set_down` says how far from where it stood it ended."""
    watch = TrialWatch("cup")
    watch.observe(0.0, dict(START), [], "")
    up = START | {"box": START["box"] + 2 * LIFTED}
    watch.observe(1.0, up, [(ROBOT, "box")], "")
    assert watch.score.lifted == {"box": 1.0} and not watch.carrying()
    watch.observe(2.0, up, [(ROBOT, "box"), ("box", HAND)], "")
    assert watch.score.person_contact == 2.0
    watch.observe(3.0, up, [(ROBOT, "box"), ("box", TABLE)], "")
    assert watch.score.table_contact == 3.0
    put_back = TrialWatch("cup")
    put_back.observe(0.0, dict(START), [], "")
    put_back.observe(1.0, up, [(ROBOT, "box")], "")
    put_back.observe(2.0, START | {"box": START["box"] + 0.002}, [("box", TABLE)], "")
    assert math.isnan(put_back.score.table_contact)
    assert put_back.score.set_down == {"box": pytest.approx(0.002)}
    fallen = START | {"box": START["box"] - 0.03}  # down on its side
    put_back.observe(3.0, fallen, [("box", TABLE)], "")
    assert put_back.score.set_down == {"box": pytest.approx(-0.03)}


def test_the_target_put_back_on_the_table_is_placed_not_carried_into_it():
    """Told it has the wrong object, the robot sets the target down where it stood: its
    touching the table there, still in the fingers, is the placing; touching the table while
    still up (an edge caught on the way down) is a contact."""
    watch = _carried()
    set_down = START | {"cup": START["cup"] + DROPPED / 4}
    watch.observe(2.0, set_down, HELD + [("cup", TABLE)], "")
    assert math.isnan(watch.score.table_contact) and math.isnan(watch.score.dropped)
    caught = _carried()
    caught.observe(2.0, START | {"cup": START["cup"] + 0.03}, HELD + [("cup", TABLE)], "")
    assert caught.score.table_contact == 2.0


def test_the_target_tilts_count_only_while_the_robot_carries_it():
    watch = TrialWatch("cup")
    watch.observe(0.0, dict(START), [], "", tilt=80.0)  # knocked over by the person, say
    watch = _carried()
    watch.observe(2.0, START | {"cup": 0.9}, HELD, "", tilt=15.0)
    watch.observe(3.0, START | {"cup": 0.9}, HELD, "", tilt=9.0)
    assert watch.score.held_tilt == 15.0  # the most while carried
    watch.observe(4.0, START | {"cup": 0.9}, HELD + [("cup", HAND)], "cup", tilt=10.0)
    watch.observe(5.0, START | {"cup": 0.9}, [("cup", HAND)], "cup", tilt=60.0)
    assert watch.score.held_tilt == 15.0  # the person's to tilt once they hold it
