"""The handover cycle as a state machine, on percepts and a planner of straight-line motions."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest

from hsr_handover.robot.handover.cycle import HandoverCycle
from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import (
    TERMINAL_PHASES,
    CycleRecord,
    Failure,
    Percepts,
    Phase,
)
from hsr_handover.robot.planning.plan import Motion, Plan

PARAMS = CycleParams()
TICK = 0.1
OBJECT = np.array([0.8, 0.0, 0.76])
PALM = np.array([1.2, 0.2, 0.95])  # where the object is held out
WEIGHT = 8.0  # N of hand and object on the wrist's sensor


class Line:
    """A straight motion from `start` to `end` over `duration` s."""

    def __init__(self, start, end, duration=1.0):
        self.start, self.end, self.duration = np.asarray(start), np.asarray(end), duration

    def state(self, time):
        s = float(np.clip(time / self.duration, 0.0, 1.0))
        return self.start + s * (self.end - self.start), (self.end - self.start) / self.duration


def _planned(*, ok: bool, reason: str, seconds: float, motions=(), **fields) -> Plan:
    """A plan of the named `motions` ((name, trajectory) pairs) that took `seconds`."""
    motions = tuple(Motion(name=name, trajectory=line) for name, line in motions)
    return Plan(ok=ok, reason=reason, motions=motions, seconds={"all": seconds}, **fields)


@dataclasses.dataclass
class Planner:
    """Plans straight lines between fixed configurations; records what it was asked."""

    grasp_ok: bool = True
    grasp_failures: int = 0  # grasps that find no way before one does
    carry_failures: int = 0  # carries planned again that find no way before one does
    back_off_ok: bool = True
    follow_reach: float = np.inf  # m from where the object is held out that a follow reaches
    in_the_way: list = dataclasses.field(default_factory=list)  # clearances to the person, m
    standing_in: list = dataclasses.field(default_factory=list)  # the same, where it stands
    person_reach: float = 0.0  # m round PALM the person reaches
    asked: list = dataclasses.field(default_factory=list)
    checked: list = dataclasses.field(default_factory=list)  # the paths checked, and within

    def person_clearance(self, path, held, within):
        """The next of `in_the_way` (inf when none is left), for the path checked; for the one
        configuration the robot stands in, the next of `standing_in`."""
        if len(path) == 1:
            return self.standing_in.pop(0) if self.standing_in else np.inf
        self.checked.append((path, held, within))
        return self.in_the_way.pop(0) if self.in_the_way else np.inf

    def person_reaches(self, point):
        return bool(np.linalg.norm(point - PALM) <= self.person_reach)

    def grasp(self, label, q):
        self.asked.append(("grasp", label))
        if not self.grasp_ok or len(self.asked) <= self.grasp_failures:
            return _planned(ok=False, reason="unreachable: no base pose reaches it", seconds=0.2)
        motions = (("move", Line(q, q + 1)), ("approach", Line(q + 1, q + 2)),
                   ("lift", Line(q + 2, q + 3)))  # fmt: skip
        return _planned(ok=True, reason="ok", motions=motions, seconds=0.3, held="the grasp")

    def carry(self, q, held):
        self.asked.append(("carry", held))
        carries = sum(ask[0] == "carry" for ask in self.asked)
        if 1 < carries <= 1 + self.carry_failures:
            return _planned(ok=False, reason="no way round the person", seconds=0.2)
        return _planned(
            ok=True, reason="ok", motions=(("carry", Line(q, q + 1, 2.0)),), seconds=0.5
        )

    def follow(self, q, v, hand, held):
        self.asked.append(("follow", tuple(hand)))
        if np.linalg.norm(hand - PALM) > self.follow_reach:
            return _planned(ok=False, reason="no IK solution", seconds=0.05)
        return _planned(
            ok=True, reason="ok", motions=(("follow", Line(q, q + 0.5, 0.5)),), seconds=0.01
        )

    def retreat(self, q, held, let_go=None):
        self.asked.append(("retreat", held, let_go))
        return _planned(
            ok=True, reason="ok", motions=(("retreat", Line(q, np.zeros_like(q))),), seconds=0.1
        )

    def back_off(self, q, let_go):
        self.asked.append(("back off", let_go))
        if not self.back_off_ok:
            return _planned(ok=False, reason="no way back from the object let go of", seconds=0.05)
        return _planned(
            ok=True, reason="ok", motions=(("back off", Line(q, q - 0.5, 0.5)),), seconds=0.05
        )

    def put_back(self, q, held, lifted, came):
        self.asked.append(("put back", held, tuple(lifted), len(came)))
        motions = (("put back", Line(q, lifted)), ("lower", Line(lifted, lifted - 1)))
        return _planned(ok=True, reason="ok", motions=motions, seconds=0.2)


class World:
    """Ticks a cycle: the joints follow the command exactly; the rest is set per test."""

    def __init__(self, planner=None):
        self.planner = planner or Planner()
        self.machine = HandoverCycle(self.planner)
        self.time, self.q = 0.0, np.zeros(3)
        self.opening, self.target, self.seen = 0.1, None, OBJECT.copy()
        self.hand = None
        self.palm = PALM.copy()
        self.palm_moves = False  # whether the palm follows the joints (else it stays at `palm`)
        self.person, self.pull = np.array([1.7, 0.2, 1.2]), 0.0
        self.face = None
        self.correction = None
        self.wrist_force = np.array([0.0, 0.0, -WEIGHT])  # N: the hand and its load hang

    def tick(self, seconds: float = TICK):
        end = self.time + seconds
        while self.time < end - 1e-9:
            self.time = round(self.time + TICK, 9)
            q, _, _ = self.machine.command(self.time)
            self.q = self.q if q is None else q
            if self.palm_moves:
                self.palm = PALM + 0.1 * self.q
            percepts = Percepts(self.time, self.q, self.opening, self.target, self.seen,
                                self.hand, self.palm, self.person, self.pull,
                                self.wrist_force, self.face, self.correction)  # fmt: skip
            record = self.machine.step(percepts)
        return record

    def until(self, phase: Phase, limit: float = 30.0):
        start = self.time
        while self.machine.record.phase is not phase:
            assert self.time - start < limit, f"stuck in {self.machine.record.phase}"
            self.tick()
        return self.machine.record


def _closed_on(opening: float, planner: Planner | None = None) -> World:
    """A world whose robot recognised the request and closed its gripper to `opening`."""
    world = World(planner)
    world.target = "yellow"
    world.until(Phase.GRASP)
    world.opening = opening
    return world


def _presenting(planner: Planner | None = None) -> World:
    """A world whose robot holds the object out, lifted and carried."""
    world = _closed_on(0.06, planner)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.08]  # it rises with the hand
    world.until(Phase.PRESENT)
    return world


def _followed(world: World, offset) -> None:
    """The person holds a hand out `offset` (m) from the object and waits: the robot gives them
    `offer_first_s` to reach for it where it is, then sets off toward the hand."""
    world.hand = world.palm + offset
    world.tick(PARAMS.offer_first_s)
    assert world.planner.asked[-1][0] != "follow"
    world.tick()
    assert world.planner.asked[-1][0] == "follow"


def test_it_watches_until_a_target_is_recognised():
    world = World()
    record = world.tick(2.0)
    assert record.phase is Phase.WATCH and world.planner.asked == []
    assert world.machine.command(world.time)[0] is None and world.machine.gaze() is None


def test_a_whole_handover_runs_through_every_phase_in_order():
    world = _presenting()
    assert world.machine.command(world.time)[2] == 0.0  # closed: the fingers stop on the object
    world.hand = world.palm + [0.15, 0.0, 0.0]  # the person's hand at the object
    world.tick(2.0)
    assert world.machine.record.phase is Phase.PRESENT  # a hand at the object is not yet a hold
    world.pull = 0.02  # the person draws it in: the arm gives
    world.until(Phase.RELEASE)
    # 3 cm wider than the 6 cm object: no wider, not to sweep a finger into the person's hand
    assert world.machine.command(world.time)[2] == pytest.approx(0.09)
    record = world.until(Phase.DONE)
    assert record.failure is None and record.target == "yellow"
    assert list(record.phase_times) == ["approach", "grasp", "lift", "carry", "present",
                                        "release", "retreat", "done"]  # fmt: skip
    times = record.phase_times
    assert times["grasp"] - times["approach"] == pytest.approx(2.0, abs=0.21)  # two 1 s moves
    assert times["release"] - times["present"] >= 2.0
    assert record.planning_s == pytest.approx(0.3 + 0.5 + 0.1)
    assert [ask[0] for ask in world.planner.asked] == ["grasp", "carry", "retreat"]
    assert world.planner.asked[1] == ("carry", "the grasp")  # the grasp's hold, carried
    assert world.planner.asked[2] == ("retreat", None, "the grasp")  # let go: empty-handed


def test_a_request_waits_to_be_planned_for_until_the_robot_stops_moving_on_another_command():
    world = World()
    world.machine.wait_until(1.0)  # the supervisor's raise ends then
    world.tick(0.5)
    world.target = "yellow"
    world.tick(0.2)
    assert world.machine.record.recognised_time == pytest.approx(0.6)
    assert world.planner.asked == [] and world.machine.record.phase is Phase.WATCH
    world.tick(0.4)
    assert world.planner.asked == [("grasp", "yellow")]


def test_the_gripper_closes_only_once_the_approach_is_done():
    world = World()
    world.target = "yellow"
    world.tick(0.5)
    assert world.machine.record.phase is Phase.APPROACH
    assert world.machine.command(world.time)[2] == 0.1  # opened 10 cm to approach
    np.testing.assert_allclose(world.machine.gaze(), OBJECT)  # it watches its hand's work
    world.until(Phase.GRASP)
    assert world.machine.command(world.time)[2] == 0.0


def test_lifted_it_looks_at_the_person_before_planning_the_carry():
    world = _closed_on(0.06)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.08]
    world.tick(1.05)  # the lift's 1 s motion done
    assert world.machine.record.phase is Phase.LIFT
    np.testing.assert_allclose(world.machine.gaze(), [1.7, 0.2, 1.2])  # the person's shoulder
    assert [ask[0] for ask in world.planner.asked] == ["grasp"]
    record = world.until(Phase.CARRY)
    # The lift's 1 s motion from the next decision, then 0.8 s looking at the person.
    looked = record.phase_times["carry"] - record.phase_times["lift"]
    assert TICK + 1.0 + 0.8 - 1e-9 <= looked <= TICK + 1.0 + 0.8 + TICK + 1e-9


def test_an_object_that_rose_only_2_cm_with_the_hand_is_a_missed_grasp():
    world = _closed_on(0.06)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.02]  # the fingers slid up it
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.GRASP_MISSED and "rose 2.0 cm" in record.reason


def test_an_object_that_rose_5_cm_with_the_hand_is_lifted():
    world = _closed_on(0.06)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.05]
    assert world.until(Phase.CARRY).failure is None


def test_a_request_for_an_object_out_of_view_is_planned_unseen_after_1_5_s():
    """Watching a standing person's face, the table is below the camera's view: the head turns
    to the object (0.6 rad at 0.8 rad/s) before the grasp is planned without it."""
    world = World()
    world.seen = None
    world.target = "yellow"
    world.tick(TICK)
    assert world.machine.seeing() == "yellow"
    world.tick(1.0)
    assert world.planner.asked == []  # still looking for it
    world.tick(1.0)
    assert world.planner.asked == [("grasp", "yellow")]


def test_an_unreachable_target_fails_with_the_planners_reason_once_patience_runs_out():
    world = World(Planner(grasp_ok=False))
    world.target = "yellow"
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.UNREACHABLE and "no base pose" in record.reason
    waited = record.phase_times["retreat"] - record.recognised_time
    assert 6.0 <= waited < 6.0 + 1.0 + TICK  # 6 s of patience, a try each second
    tries = len(world.planner.asked) - 1  # the last ask is the retreat
    assert tries == pytest.approx(6 / 1 + 1, abs=1)


def test_a_grasp_blocked_for_a_while_is_tried_again_and_fetched_though_the_intent_moved_on():
    world = World(Planner(grasp_failures=2))
    world.target = "yellow"
    world.tick(TICK)
    world.target = None  # the estimator no longer reports it: the request stands
    record = world.until(Phase.APPROACH)
    assert record.target == "yellow" and record.failure is None
    assert world.planner.asked == [("grasp", "yellow")] * 3
    # Tried again each second.
    assert record.phase_times["approach"] - record.recognised_time == pytest.approx(
        2.0, abs=TICK + 1e-9
    )


def test_a_blocked_grasp_looks_at_the_object_while_it_waits():
    """Watching, the head is the watcher's; once a grasp finds no way, the robot looks at the
    object, so the table before it comes into view for the next try."""
    world = World(Planner(grasp_failures=1))
    world.tick(1.0)
    assert world.machine.gaze() is None
    world.target = "yellow"
    world.tick(TICK)
    assert world.machine.record.phase is Phase.WATCH
    np.testing.assert_allclose(world.machine.gaze(), OBJECT)


def test_a_gripper_closed_on_nothing_is_a_missed_grasp():
    world = _closed_on(0.0)
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.GRASP_MISSED
    # Judged once the gripper has had 0.8 s to close.
    judged = record.phase_times["retreat"] - record.phase_times["grasp"]
    assert judged == pytest.approx(0.8, abs=TICK + 1e-9)


def test_an_object_that_stays_on_the_table_is_a_missed_grasp():
    world = _closed_on(0.06)
    record = world.until(Phase.FAILED)  # the camera still sees it where it stood
    assert record.failure is Failure.GRASP_MISSED and "rose 0.0 cm" in record.reason


def test_an_object_that_slips_out_during_the_carry_is_dropped():
    world = _carrying()
    world.opening = 0.002
    world.seen = OBJECT.copy()  # fallen back onto the table
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.DROPPED


def test_an_object_taken_from_the_fingers_during_the_carry_is_handed_over():
    """A hand held out beside the carry's slow end takes the cup: the robot, still carrying,
    stands still and looks rather than calling it dropped."""
    world = _carrying()
    world.opening = 0.0
    world.seen = OBJECT + [0.3, 0.0, PARAMS.still_up + 0.1]  # up, in the person's hand
    world.tick(PARAMS.empty_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT  # it stands still and looks first
    np.testing.assert_array_equal(world.machine.command(world.time)[1], 0.0)
    record = world.until(Phase.DONE)
    assert record.failure is None and Phase.RELEASE.value in record.phase_times


def test_no_hand_in_time_fails_by_timeout_and_the_robot_keeps_the_object():
    world = _presenting()
    world.hand = world.palm + [0.5, 0.0, 0.0]  # in view, never near
    record = world.until(Phase.FAILED, limit=20.0)
    assert record.failure is Failure.TIMEOUT and "holding it" in record.reason
    presented = record.phase_times["retreat"] - record.phase_times["present"]
    assert presented == pytest.approx(12.0, abs=TICK + 1e-9)  # HandoverSim allows 13 s
    assert world.machine.command(world.time)[2] == 0.0
    assert world.planner.asked[-1] == ("retreat", "the grasp", None)


def test_a_person_out_of_sight_while_presenting_withdrew():
    world = _presenting()
    world.hand = None
    world.tick(PARAMS.lost_s + 0.5)
    assert world.machine.record.phase is Phase.PRESENT  # the hand hidden, the person in view
    world.person = None
    last_seen = world.time
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.PERSON_WITHDREW
    unseen = record.phase_times["retreat"] - last_seen
    assert unseen == pytest.approx(2.0, abs=TICK + 1e-9)  # out of sight for 2 s


def test_a_hand_in_view_at_the_object_is_a_person_in_view_though_the_shoulders_are_hidden():
    world = _presenting()
    world.person = None
    world.hand = world.palm + [0.5, 0.0, 0.0]  # in view, never near
    world.tick(PARAMS.lost_s + 1.0)
    assert world.machine.record.phase is Phase.PRESENT
    world.hand = None
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.PERSON_WITHDREW


def test_a_face_over_the_object_is_a_person_in_view_though_the_body_is_hidden():
    """Presenting to a standing person at their chest, the arm and the object hide the torso
    and the hand: only the eyes show over them."""
    world = _presenting()
    world.person, world.hand = None, None
    world.face = np.array([1.7, 0.2, 1.65])
    world.tick(PARAMS.lost_s + 1.0)
    assert world.machine.record.phase is Phase.PRESENT
    world.face = None
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.PERSON_WITHDREW


def test_a_tug_at_the_object_makes_the_robot_let_go_though_the_hand_is_hidden():
    world = _presenting()
    world.pull = 0.005  # the arm's own sag
    world.tick(1.0)
    assert world.machine.record.phase is Phase.PRESENT
    world.pull = 0.02
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE
    assert world.machine.command(world.time)[2] == pytest.approx(world.opening + 0.03)


def _toward_person(world: World, newtons: float) -> np.ndarray:
    direction = world.person - world.palm
    return newtons * direction / np.linalg.norm(direction)


def test_a_tug_felt_at_the_wrist_makes_the_robot_let_go_though_the_arm_does_not_give():
    world = _presenting()
    world.wrist_force = world.wrist_force - _toward_person(world, PARAMS.tug)  # a hand pushing in
    world.tick(1.0)
    assert world.machine.record.phase is Phase.PRESENT
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, PARAMS.tug / 2)
    world.tick(1.0)  # the arm's own sway
    assert world.machine.record.phase is Phase.PRESENT
    sideways = np.cross(_toward_person(world, 1.0), [0.0, 0.0, 1.0])
    hanging = np.array([0.0, 0.0, -WEIGHT])
    world.wrist_force = hanging + _toward_person(world, PARAMS.tug + 1) + 2 * PARAMS.tug * sideways
    world.tick(2 * TICK)  # a hand closing from the side pushes the object across
    assert world.machine.record.phase is Phase.PRESENT
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, 2 * PARAMS.tug)
    world.tick()  # one knock of a hand on its way in is not a hold
    assert world.machine.record.phase is Phase.PRESENT
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT])
    world.tick()
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, 2 * PARAMS.tug)
    world.tick(2 * TICK)  # pulled and still pulled
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_fingers_closing_soon_after_a_tug_with_the_hand_hidden_is_a_handover_not_a_drop():
    world = _presenting()
    _followed(world, [0.0, 0.5, 0.0])  # held out elsewhere: the robot follows it
    world.hand = None  # hidden behind the robot's own arm from here on
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, 2 * PARAMS.tug)
    world.tick(2 * TICK)  # taken hold of on the way: the arm stops to feel again
    assert world.machine.record.phase is Phase.PRESENT
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT])  # the fingers slip off the object
    world.tick(PARAMS.taken_s - 2 * TICK)
    world.opening = 0.0  # drawn out of the fingers before the robot had let go
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_a_hand_held_out_elsewhere_is_followed():
    world = _presenting()
    _followed(world, [0.0, 0.5, 0.0])
    _, goal = world.planner.asked[-1]
    # The object is brought in front of the fingers, not into the wrist.
    np.testing.assert_allclose(goal, world.hand - [0.0, PARAMS.offer, 0.0])
    assert world.machine.command(world.time + 0.25)[0] is not None


def test_a_waiting_hand_the_arm_cannot_reach_gets_the_object_brought_part_way():
    """A hand that waited near the object, where the arm cannot bring it, has it brought as
    near as the arm reaches: any way nearer the hand is nearer the person's reach."""
    world = _presenting(Planner(follow_reach=0.06))
    world.hand = world.palm + [0.3, 0.0, 0.1]  # held out 32 cm off, waiting
    world.tick(PARAMS.nudge_s + 3 * TICK)
    follows = [goal for name, goal in world.planner.asked if name == "follow"]
    assert len(follows) == 2  # at the hand, then half way there, which the arm reaches
    offer = world.hand + PARAMS.offer * (world.palm - world.hand) / np.linalg.norm([0.3, 0.1])
    np.testing.assert_allclose(follows[1], world.palm + 0.5 * (offer - world.palm))
    assert world.machine.command(world.time + 0.25)[0] is not None  # on its way


def test_a_hand_held_out_short_of_the_object_and_waiting_gets_the_object_brought_to_it():
    world = _presenting()
    world.hand = world.palm + [0.3, 0.0, 0.1]  # held out 32 cm off, below the shoulder
    world.tick(PARAMS.nudge_s - TICK)
    assert world.planner.asked[-1][0] == "carry"  # a hand this near may be reaching
    world.tick(2 * TICK)
    name, goal = world.planner.asked[-1]
    assert name == "follow"
    np.testing.assert_allclose(np.linalg.norm(goal - world.hand), PARAMS.offer)


def test_a_hand_seen_on_its_way_out_waits_from_where_it_stops():
    world = _presenting()
    for k in range(10):  # coming out over a second, nearer than follow_beyond, then still
        world.hand = world.palm + [0.42 - 0.015 * k, 0.0, 0.1]
        world.tick()
    world.tick(PARAMS.nudge_s - TICK)
    assert world.planner.asked[-1][0] == "carry"  # still for less than nudge_s
    world.tick(3 * TICK)  # at rest from the median of the readings, a decision later
    assert world.planner.asked[-1][0] == "follow"


def test_a_hand_that_moves_is_not_followed_however_long_it_takes():
    world = _presenting()
    for k in range(int(2 * PARAMS.nudge_s / TICK)):
        world.hand = world.palm + [0.3 - 0.01 * k, 0, 0.1]  # reaching for the object
        world.tick()
    assert world.planner.asked[-1][0] == "carry"


def test_a_followed_hand_that_comes_for_the_object_stops_the_arm_where_it_is():
    world = _presenting()
    held_out = world.palm + [0.0, 0.5, 0.0]
    _followed(world, [0.0, 0.5, 0.0])
    world.hand = held_out + [0.01, -PARAMS.coming / 2, 0.0]  # the wrist's keypoint wanders
    world.tick()
    assert world.machine.command(world.time + 0.3)[0] is not None  # still on its way
    world.hand = held_out + [0.0, -1.5 * PARAMS.coming, 0.0]  # the person reaches for it
    world.tick()
    assert world.machine.command(world.time + 0.3)[0] is not None  # one reading: an outlier?
    world.tick()  # two of the last three: the hand comes
    q = world.q.copy()
    np.testing.assert_allclose(world.machine.command(world.time + 0.3)[0], q)  # stopped there
    world.hand = None  # hidden by the robot's own arm: it stays stopped
    world.tick(0.5)
    np.testing.assert_allclose(world.machine.command(world.time)[0], q)
    assert world.machine.record.phase is Phase.PRESENT


def test_a_tug_while_following_the_hand_stops_the_arm_and_then_it_lets_go():
    world = _presenting()
    _followed(world, [0.0, 0.5, 0.0])
    world.pull = 0.02  # taken hold of on the way
    world.tick()
    assert world.machine.record.phase is Phase.PRESENT
    q = world.q.copy()
    np.testing.assert_allclose(world.machine.command(world.time + 0.3)[0], q)  # stopped there
    world.tick()  # still pulled, standing still
    assert world.machine.record.phase is Phase.RELEASE


def test_an_object_drawn_out_of_the_fingers_by_a_hand_at_it_is_handed_over_not_dropped():
    world = _presenting()
    world.hand = world.palm + [0.0, 0.0, PARAMS.reach - 0.02]
    world.tick()
    world.hand = world.palm + [0.0, 0.0, PARAMS.reach + 0.2]  # the arm draws it in
    world.tick(PARAMS.taken_s - 2 * TICK)
    world.opening = 0.0  # pulled out before the robot had let go
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_fingers_forced_apart_by_the_object_drawn_through_them_make_it_let_go():
    world = _presenting()  # closed on 6 cm
    world.opening = 0.06 + PARAMS.spread / 2  # the pads give a little as it is held out
    world.tick(1.0)
    assert world.machine.record.phase is Phase.PRESENT
    world.opening = 0.06 + 2 * PARAMS.spread
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_fingers_forced_apart_by_a_knock_across_do_not_make_it_let_go():
    """A hand striking the object on its way in forces the fingers open too, with a load felt
    across (18 N sideways): the robot holds on; drawn toward the person, or
    forced open with no load felt, it lets go."""
    world = _presenting()
    sideways = np.cross(_toward_person(world, 1.0), [0.0, 0.0, 1.0])
    world.opening = 0.06 + 2 * PARAMS.spread
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + 3 * PARAMS.tug * sideways
    world.tick(0.5)
    assert world.machine.record.phase is Phase.PRESENT
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, 3 * PARAMS.tug)
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_fingers_closing_with_no_hand_at_the_object_lately_is_a_drop():
    world = _presenting()
    world.hand = world.palm + [0.0, 0.0, PARAMS.reach - 0.02]
    world.tick()
    world.hand = world.palm + [0.0, 0.0, PARAMS.reach + 0.2]
    world.tick(PARAMS.taken_s + TICK)
    world.opening = 0.0
    world.seen = OBJECT.copy()  # fallen back onto the table
    world.tick(PARAMS.empty_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT  # it looks where the object went first
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.DROPPED


def test_fingers_emptied_by_a_pull_across_with_the_hand_and_object_unseen_is_a_handover():
    """A hand the robot's arm hides closes on the cup and draws it out with 9 N across, 63
    degrees off the person (no tug), the object out of the camera's view, or yanks it out across
    and up within one decision. The robot lets go rather than calling it dropped."""
    world = _presenting()
    across = np.cross(_toward_person(world, 1.0), [0.0, 0.0, 1.0])
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + 3 * PARAMS.tug * across
    world.tick(TICK)  # pulled across, long before the fingers empty
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT])
    world.tick(PARAMS.taken_s + TICK)
    world.opening = 0.0
    world.tick(PARAMS.empty_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT  # too long ago: it looks first
    world.opening = 0.06
    world.tick()
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT + 2 * PARAMS.tug]) + 2 * PARAMS.tug * across
    world.tick()  # yanked across and up
    world.opening = 0.0
    world.tick()
    assert world.machine.record.phase is Phase.RELEASE and world.machine.record.failure is None


def test_a_heavy_object_slipping_out_is_dropped_though_its_weight_is_over_a_tug():
    world = _presenting()
    # Its weight going from the fingers, still held.
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT + 2 * PARAMS.tug])
    world.tick(3 * TICK)
    world.opening = 0.0
    world.seen = OBJECT.copy()  # fallen back onto the table
    record = world.until(Phase.FAILED)
    assert record.failure is Failure.DROPPED


def test_fingers_closing_with_the_object_still_up_and_the_hand_unseen_is_a_handover():
    """A hand hidden by the robot's own arm drew the object out, its tug pointing away from
    the person: the camera sees the object still up, in the person's hand."""
    world = _presenting()
    world.opening = 0.0
    world.seen = OBJECT + [0.3, 0.0, PARAMS.still_up + 0.1]
    world.tick(PARAMS.empty_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT
    np.testing.assert_array_equal(world.machine.command(world.time)[1], 0.0)  # standing still
    record = world.until(Phase.DONE)
    assert record.failure is None and Phase.RELEASE.value in record.phase_times


def test_fingers_emptied_with_the_object_unseen_withdraw_then_judge_what_the_camera_sees():
    """The person took the object as the carry slowed, their hand and the object hidden by the
    robot's own: unseen, the robot withdraws, and the camera then tells. Seen up in the
    person's hand on the way back: a handover (released, done); not seen: dropped."""

    def emptied_unseen() -> World:
        world = _presenting()
        world.opening = 0.0
        world.seen = None
        world.tick(PARAMS.empty_s + TICK)
        assert world.machine.record.phase is Phase.RETREAT  # withdrawing to look
        return world

    world = emptied_unseen()
    world.seen = OBJECT + [0.3, 0.0, PARAMS.still_up + 0.1]
    record = world.until(Phase.DONE)
    assert record.failure is None and Phase.RELEASE.value in record.phase_times
    record = emptied_unseen().until(Phase.FAILED)
    assert record.failure is Failure.DROPPED


def test_a_copy_steps_on_its_own():
    """Drake copies the state with each context: a copy must not share the record."""
    world = World()
    world.target = "yellow"
    world.tick()
    clone = copy.deepcopy(world.machine)
    world.until(Phase.GRASP)
    assert clone.record.phase is Phase.APPROACH
    assert "grasp" not in clone.record.phase_times


def test_a_copy_presenting_feels_and_moves_on_its_own():
    """A copy made while presenting keeps its own memory of tugs and of the arm's motions: the
    original feeling a tug and stopping leaves the copy following the hand."""
    world = _presenting()
    _followed(world, [0.0, 0.5, 0.0])  # it sets off toward the hand
    clone = copy.deepcopy(world.machine)
    world.wrist_force = np.array([0.0, 0.0, -WEIGHT]) + _toward_person(world, 10.0)
    world.tick(3 * TICK)  # a tug felt twice stops the arm; felt again standing, it lets go
    assert world.machine.record.phase is Phase.RELEASE
    assert clone.record.phase is Phase.PRESENT
    assert clone.command(world.time)[0] is not None and clone.command(world.time)[1].any()


def test_every_phase_but_those_it_ends_in_has_one_handler():
    handled = HandoverCycle.handled_phases()
    for phase in Phase:
        assert (phase in handled) is (phase not in TERMINAL_PHASES), phase
        assert CycleRecord(phase).over is (phase in TERMINAL_PHASES)
    assert TERMINAL_PHASES == {Phase.DONE, Phase.FAILED}


def test_fingers_that_hold_again_restart_the_wait_before_judging_them_empty():
    world = _presenting()
    world.opening, world.seen = 0.0, OBJECT.copy()  # a glitch: empty for a moment
    world.tick(PARAMS.empty_s - 2 * TICK)
    world.opening = 0.06  # holding again
    world.tick(1.0)
    world.opening = 0.0  # now empty for good
    world.tick(PARAMS.empty_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT  # waited afresh, not judged at once
    assert world.until(Phase.FAILED).failure is Failure.DROPPED


def _carrying(planner: Planner | None = None) -> World:
    """A world whose robot carries the object it lifted (the yellow one) toward the person."""
    world = _closed_on(0.06, planner)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.08]  # it rises with the hand
    world.until(Phase.CARRY)
    world.tick(0.5)  # part way: the carry takes 2 s
    return world


def test_a_carry_is_checked_against_the_person_as_it_goes_and_runs_on_while_clear():
    world = _closed_on(0.06)
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0, 0, 0.08]
    world.until(Phase.CARRY)
    carried_from = world.q.copy()
    world.until(Phase.PRESENT)
    assert [ask[0] for ask in world.planner.asked] == ["grasp", "carry"]
    # The 2 s carry (set off at the decision after it was planned) checked every 0.5 s: what
    # is still to go, from where the robot is.
    checks = world.planner.checked
    assert len(checks) == 4
    for path, held, within in checks:
        assert held == "the grasp" and within == PARAMS.carry_clear
        np.testing.assert_allclose(path[-1], carried_from + 1)  # to the carry's end
    np.testing.assert_allclose(checks[0][0][0], carried_from + 0.2)  # 0.4 s of 2 s along
    assert len(checks[0][0]) > len(checks[-1][0]) >= 2


def test_a_carry_that_would_come_into_the_person_stops_and_is_planned_again_from_there():
    world = _carrying(Planner(in_the_way=[np.inf, -0.1]))  # in the way at the second check
    world.tick(0.5)
    stopped_at = world.q.copy()
    assert world.machine.record.phase is Phase.CARRY
    assert np.all((3.3 < stopped_at) & (stopped_at < 3.7))  # half way along the 3 -> 4 carry
    world.tick()
    np.testing.assert_allclose(world.q, stopped_at)  # it stood still to plan
    assert [ask[0] for ask in world.planner.asked] == ["grasp", "carry", "carry"]
    record = world.until(Phase.PRESENT)
    assert record.failure is None
    np.testing.assert_allclose(world.q, stopped_at + 1)  # the second carry, from where it stopped


def test_a_carry_standing_in_the_percept_runs_on_while_the_way_comes_no_deeper():
    """The object carried past the camera hides the person's hands, whose keypoints are lifted
    onto it: the robot stands 10 cm "inside" the person. A way no deeper than that, less
    carry_clear_slack, runs on; one that comes deeper stops."""
    planner = Planner(in_the_way=[-0.1, -0.11], standing_in=[-0.1, -0.1])
    world = _carrying(planner)
    record = world.until(Phase.PRESENT)
    assert record.failure is None
    assert [ask[0] for ask in planner.asked] == ["grasp", "carry"]  # never stopped
    assert all(within == pytest.approx(-0.1 - PARAMS.carry_clear_slack)
               for _, _, within in planner.checked[:2])  # fmt: skip

    deeper = Planner(in_the_way=[np.inf, -0.15], standing_in=[-0.1, -0.1])
    world = _carrying(deeper)
    world.tick(0.5)
    world.tick()
    assert [ask[0] for ask in deeper.asked] == ["grasp", "carry", "carry"]  # stopped, replanned


def test_a_carry_stopped_within_the_persons_reach_presents_the_object_there():
    planner = Planner(in_the_way=[np.inf, -0.1], carry_failures=10, person_reach=1.0)
    world = _carrying(planner)
    world.palm_moves = True
    world.tick(0.5)  # stopped for the person, and no new way found yet
    stopped_at = world.q.copy()
    world.tick(0.2)
    assert world.machine.record.phase is Phase.CARRY
    world.tick(0.2)  # still for 0.3 s: it looks held out, and the person reaches it
    assert world.machine.record.phase is Phase.PRESENT
    carries = sum(ask[0] == "carry" for ask in planner.asked)
    world.tick(1.0)
    np.testing.assert_allclose(world.q, stopped_at)  # held out where it stopped
    assert sum(ask[0] == "carry" for ask in planner.asked) == carries  # no carry planned on


def _held_out_at_a_stop() -> tuple[World, Planner]:
    """A world whose carry stopped for the person within their reach and presented there,
    the person's hand seen resting 0.6 m off, where the arm cannot bring the object."""
    planner = Planner(in_the_way=[np.inf, -0.1], carry_failures=1, person_reach=1.0,
                      follow_reach=0.1)  # fmt: skip
    world = _carrying(planner)
    world.palm_moves = True
    world.until(Phase.PRESENT)
    world.hand = world.palm + [0.6, 0.0, 0.0]
    return world, planner


def test_an_object_held_out_at_a_stop_that_no_hand_comes_to_is_carried_on_once():
    world, planner = _held_out_at_a_stop()
    carries = sum(ask[0] == "carry" for ask in planner.asked)
    world.tick(PARAMS.go_on_s - TICK)
    assert world.machine.record.phase is Phase.PRESENT
    world.tick(2 * TICK)
    assert world.machine.record.phase is Phase.CARRY  # on to the handover point
    assert sum(ask[0] == "carry" for ask in planner.asked) == carries + 1
    world.until(Phase.PRESENT)
    world.tick(2 * PARAMS.go_on_s)
    assert world.machine.record.phase is Phase.PRESENT  # at the handover point it waits
    assert sum(ask[0] == "carry" for ask in planner.asked) == carries + 1


@pytest.mark.parametrize("hand", [[0.15, 0.0, 0.0], None], ids=["at the object", "unseen"])
def test_an_object_held_out_at_a_stop_waits_for_a_hand_at_it_or_unseen(hand):
    world, planner = _held_out_at_a_stop()
    world.hand = None if hand is None else world.palm + hand
    carries = sum(ask[0] == "carry" for ask in planner.asked)
    world.tick(2 * PARAMS.go_on_s)
    assert world.machine.record.phase is Phase.PRESENT
    assert sum(ask[0] == "carry" for ask in planner.asked) == carries


def test_a_carry_stopped_beyond_the_persons_reach_is_planned_again():
    planner = Planner(in_the_way=[np.inf, -0.1], carry_failures=10, person_reach=0.1)
    world = _carrying(planner)
    world.palm_moves = True  # the palm 0.3 m or more from PALM: beyond the person's reach
    world.tick(2.0)
    assert world.machine.record.phase is Phase.CARRY
    assert sum(ask[0] == "carry" for ask in planner.asked) == 3  # tried again every second


def test_a_carry_stopped_for_the_person_is_put_back_the_whole_way_it_came():
    world = _carrying(Planner(in_the_way=[-0.1]))  # in the way at the first check
    world.tick(0.4)  # planned again and part way along
    world.correction = "red"
    world.tick(0.2)
    ask = world.planner.asked[-1]
    assert ask[0] == "put back" and ask[3] > 16  # both carries' ways


def test_a_correction_while_carrying_puts_the_object_back_and_fetches_the_one_asked_for():
    world = _carrying()
    carried_to = world.q.copy()
    world.correction = "red"
    world.tick()
    record = world.machine.record
    assert record.phase is Phase.PUT_BACK and record.first_target == "yellow"
    assert record.corrected_time == pytest.approx(world.time)
    assert record.target == "yellow"  # still the one in the hand, until it is back
    world.tick()  # it plans from standing still
    lifted = np.full(3, 3.0)  # where the fake grasp's lift ended
    ask = world.planner.asked[-1]
    assert ask[:3] == ("put back", "the grasp", tuple(lifted)) and ask[3] > 2  # the way it came
    assert world.machine.command(world.time)[2] == 0.0  # it holds the object on the way back
    world.tick(2.5)  # back over its place, then down (two 1 s moves)
    assert np.allclose(world.q, lifted - 1) and world.machine.command(world.time)[2] == 0.1
    assert world.machine.record.phase is Phase.PUT_BACK  # the fingers open before it leaves
    world.opening = 0.1
    world.until(Phase.WATCH)
    assert world.planner.asked[-1] == ("back off", "the grasp")  # off what it let go of
    assert np.allclose(world.q, lifted - 1.5)  # and then it plans from there
    assert world.machine.record.target == "red"
    world.seen = OBJECT + [0.0, 0.2, 0.0]  # the red one, where it stands
    world.until(Phase.APPROACH)  # the estimator's first target stays: it fetches the new one
    assert world.planner.asked[-1] == ("grasp", "red")
    assert not np.allclose(carried_to, world.q) and world.machine.record.failure is None


def test_a_correction_is_heeded_once_and_not_for_the_object_in_hand():
    world = _carrying()
    world.correction = "yellow"  # the object it carries: nothing to correct
    world.tick(0.3)
    assert world.machine.record.phase is Phase.CARRY and world.machine.record.first_target is None
    world.correction = "red"
    world.until(Phase.PUT_BACK)
    world.opening = 0.1
    world.seen = OBJECT + [0.0, 0.2, 0.0]
    world.until(Phase.APPROACH)
    world.until(Phase.GRASP)
    world.opening = 0.06
    world.until(Phase.LIFT)
    world.seen = OBJECT + [0.0, 0.2, 0.08]
    world.correction = "blue"  # a second correction: the robot goes on with the first
    world.until(Phase.CARRY)
    assert world.machine.record.target == "red" and world.machine.record.first_target == "yellow"


def test_a_correction_before_the_lift_is_seen_to_succeed_waits_for_it():
    """While the hand closes (the camera on the object, the person out of its view) the robot
    does not put back: a correction counts from the lift on."""
    world = _closed_on(0.06)
    world.correction = "red"
    world.until(Phase.LIFT)
    assert world.machine.record.first_target is None
    world.seen = OBJECT + [0, 0, 0.08]
    world.until(Phase.PUT_BACK)
    world.tick()
    assert world.planner.asked[-1][0] == "put back"
    assert world.planner.asked[-1][3] == 0  # not carrying yet: no way to come back along


def test_a_put_back_that_drops_the_object_fails_as_dropped():
    world = _carrying()
    world.correction = "red"
    world.tick()
    world.opening = 0.0  # the fingers close on nothing on the way back
    record = world.until(Phase.RETREAT)
    assert record.failure is Failure.DROPPED


def test_with_no_way_straight_off_the_object_put_back_it_retreats_then_fetches_the_other():
    world = _carrying()
    world.planner.back_off_ok = False
    world.correction = "red"
    world.until(Phase.PUT_BACK)
    world.opening = 0.1
    world.until(Phase.RETREAT)
    assert world.planner.asked[-1] == ("retreat", None, "the grasp")
    world.seen = OBJECT + [0.0, 0.2, 0.0]
    world.until(Phase.APPROACH)
    assert world.planner.asked[-1] == ("grasp", "red") and world.machine.record.failure is None
