"""The perceiving-acting cycle as a plain state machine (paper 3.3): watch, recognise
the request, plan, approach, grasp, lift, carry to the handover point, wait for the person's
hand, release when the person holds the object, retreat. Failures end it with a reason.

It decides from percepts only (`Percepts`: the joint sensors, the gripper's measured opening,
the intent estimator's target, the object as the camera sees it, the person's hand from the
skeleton) and asks a `CyclePlanner` for motions. A person who asks for another object while the
robot lifts or carries one (the intent estimator's correction) has that object put back where
it stood and the other fetched, once. It knows nothing of Drake systems: the
`HandoverSupervisor` steps it and follows the motion it gives.
"""

from __future__ import annotations

import copy
import dataclasses
import enum
import math
from collections.abc import Callable
from typing import Protocol

import numpy as np

from hsr_handover.robot.handover.plan_view import PlanView


class Phase(enum.Enum):
    WATCH = "watch"
    APPROACH = "approach"  # to the pre-grasp, then along the approach
    GRASP = "grasp"  # the gripper closing
    LIFT = "lift"
    CARRY = "carry"  # to the handover point
    PUT_BACK = "put_back"  # the person asked for another object: the one lifted goes back
    PRESENT = "present"  # waiting for the person's hand
    RELEASE = "release"  # the gripper opening
    RETREAT = "retreat"
    DONE = "done"
    FAILED = "failed"


class Failure(enum.Enum):
    """Why a cycle failed (HandoverSim's classes and ours)."""

    UNREACHABLE = "unreachable"
    GRASP_MISSED = "grasp missed"
    DROPPED = "dropped"
    PERSON_WITHDREW = "person withdrew"
    TIMEOUT = "timeout"


HELD_OPENING = 0.01
"""m: a gripper closed on an object reads at least this (closed on nothing it reads ~0)."""
OPEN = 0.1
"""m of opening to approach with; the move is planned at the plan's own opening (the object's
width and 3 cm, `planner.plan_grasp`), up to 1 cm off this."""
LET_GO = 0.03
"""m the fingers open beyond the object's width to let go: no wider, so the finger on the
person's side does not sweep into the hand that has just taken the object."""
CLOSED = 0.0  # m commanded to grasp: the fingers stop on the object
SETTLE_S = 0.8  # s the gripper is given to close or open
RISE = 0.03  # m the object must rise with the hand, seen by the camera, for a grasp to count
LOOK_S = 0.8  # s the robot looks at the person before it plans the way to them
REACH = 0.32
"""m: the person's hand this near the palm counts as at the object: the wrist keypoint sits
about 27 cm from the centre of an object the person closes a hand on (a hand's length behind
fingertips a few cm short of it), plus the skeleton's few cm of error."""
OFFER = 0.2
"""m from a hand held out elsewhere that the robot aims to bring the object to: in front of the
fingers, for the person to close them on (the wrist itself is inside the person's hand). Along
the forearm's line that point lies inside the perceived forearm's capsule, so the planner holds
the object out at the nearest point beside the hand where it fits (`planning.offer`): every
follow of the reference run's trial 53 found no IK solution at the point itself."""
FOLLOW_BEYOND = 0.45
"""m: a hand held out farther than this from the palm is followed; a nearer one is reaching
for the object, and the robot holds still for it (following a hand that had just closed on the
object pushed the gripper into it)."""
NUDGE_S = 3.0
"""s a hand may stay still nearer than FOLLOW_BEYOND before the robot brings the object to it
all the same: the person judges it out of their reach (the reference run's trial 53 waited 12 s
with a wrist held out 32 cm off). A hand that reaches for the object moves. Held out or resting
makes no difference: the skeleton cannot tell them apart (the seated person's forearm rests
level, its wrist about 29 cm below the shoulder; trial 53's held-out wrist was 30 cm below),
and a person who does not take the object has it brought nearer, then kept."""
COMING = 0.02
"""m a followed hand comes toward the palm, from where it was as the robot set off toward it,
that means it reaches for the object (the wrist's keypoint wanders under 1 cm along that line
in a decision or two; a reaching hand is hidden by the robot's own arm within 0.2 s of
moving 3 cm)."""
HAND_STILL = 0.04
"""m: a hand that stays within this of where it came to rest is waiting (the skeleton's wrist
wanders 1-2 cm); one that moves farther comes to rest again where it is now."""
PULL = 0.01
"""m the palm may be pulled off its commanded point, still, before the robot lets go: the
person has hold of the object and draws it in (the arm's own sag is under 3 mm). Pulled so far
while it moves toward the hand, the robot stops there and feels again."""
SPREAD = 0.015
"""m the fingers may be forced open beyond the object's width, while presenting, before the
robot lets go: the person draws the object out between them (the gripper yields before the
arm does, so the palm is not pulled). Not when the wrist feels the object knocked across
(`_knocked`): a hand striking it on its way in forces them open too."""
TUG = 3.0
"""N: the wrist's sensor feeling the load pulled this much harder toward the person than while
it was carried, at two decisions in a row (0.1 s apart), means the person has hold of it.
People tug at 5-15 N to take an object; the arm's own accelerations while presenting move a
few hundred grams, under 1 N; a hand knocking the object on its way in is felt at one decision
only (3-5 N for a step in the reference run, which let go of 3 objects before the hand closed).
The pull must also point within TUG_CONE_DEG of the person: a hand closing on the object from
the side pushes it sideways and up (7 N across, 4 N toward the person in trial 44)."""
TUG_CONE_DEG = 45.0
TAKEN_S = 1.0
"""s after a hand was last seen at the object, or the object felt held, within which fingers
that close on nothing mean the person drew it out (the wrist is soon farther off than REACH as
the arm draws it in, and the robot's own arm often hides the hand from its camera). Held is a
tug, or a load pulled across by over TUG while the fingers still hold, whichever way and if
only at one decision: gravity pulls a slipping object only down (a hand the arm hides can draw
the cup out with 9 N across, 63 degrees off the person, over a second, or yank it out across
and up within 0.1 s; read as drops, both would be failures). A knock across that shook the
object loose would be read as a take too: the fingers are empty by then, so letting go changes
only what the robot reports."""
PATIENCE_S = 6.0
"""s the robot keeps trying a plan that finds no way, on fresh percepts, before it gives up: a
pointing arm held over the object blocks every grasp until the person lowers it (6 of the
reference run's 7 unreachable trials planned while the person still pointed)."""
EMPTY_S = 0.5
"""s the robot holds still after its fingers close on nothing while carrying or presenting, with
no hand seen at the object nor tug felt, before it looks where the object went: a dropped object
falls from the presenting height to the table in about 0.25 s."""
STILL_UP = 0.08
"""m above where the object stood on the table that the camera must see it, EMPTY_S after the
fingers closed on nothing, to count it taken rather than dropped: a hand the robot's own arm
hid from its camera drew it out (the reference run's trials 17 and 28: the wrist unseen for
the whole presentation, the tug pointing down and away). Held out, it is 15-30 cm up."""
SEEK_S = 1.5
"""s the robot looks for the object asked for before it plans the grasp without having seen it
since the request: the head's turn down from a standing person's face (0.6 rad at 0.8 rad/s)
and a few decisions."""
RETRY_EVERY_S = 1.0  # s between those tries
FOLLOW_EVERY_S = 1.0  # s between tries to follow the hand (a hand out of reach fails each)
WAIT_S = 12.0  # s the robot presents the object before it gives up (HandoverSim's 13 s limit)
LOST_S = 2.0
"""s while presenting without seeing any of the person (the neck, a shoulder, the face) or their
receiving hand: the person withdrew. The robot's own arm often hides a shoulder while the hand
takes the object (the reference run's trial 46 gave up on a person pulling at the object, wrist
in view); presenting to a standing person at their chest, the arm and the object can hide the
whole torso, and only the eyes show over them (the standing layout's trial 9 of seed 1)."""


class Motion(Protocol):
    """A timed motion over the planning plant's positions."""

    duration: float

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities at `time` s from its start (held at its ends)."""


@dataclasses.dataclass(frozen=True)
class Percepts:
    """What the robot knows at `time` s: its measured positions `q` (planning plant order), the
    gripper's measured `opening` (m), the `target` recognised (None until one is), the target
    object's centre as the camera sees it now (`object_seen`, None when not in view), the
    receiving hand from the skeleton (`hand`, None when not seen), the palm's point by forward
    kinematics of `q` (`palm`), a point on the person's body seen now (`person`: the
    receiving shoulder, or else the neck or a shoulder; None when none is in view), how far
    the joint sensors put the palm from where it is commanded (`pull`, m: a person tugging at
    the object held), the force the hand and its load exert on the wrist's sensor
    (`wrist_force`, N, world; None without the sensor) and a point of the person's face seen
    now (`face`: the nose, an eye or an ear; None when none is), and another object the person
    asked for after the target (`correction`, None if none)."""

    time: float
    q: np.ndarray
    opening: float
    target: str | None = None
    object_seen: np.ndarray | None = None
    hand: np.ndarray | None = None
    palm: np.ndarray | None = None
    person: np.ndarray | None = None
    pull: float = 0.0
    wrist_force: np.ndarray | None = None
    face: np.ndarray | None = None
    correction: str | None = None


@dataclasses.dataclass(frozen=True)
class PlannedMotions:
    """A planner's answer: `ok` with the `motions` in order, or not with the `reason`; the
    wall `seconds` it took; a carry's `receiving` side ("r" or "l": the person's arm it
    hands to)."""

    ok: bool
    reason: str
    motions: tuple[tuple[str, Motion], ...] = ()
    seconds: float = 0.0
    held: object = None  # a grasp's: the object as the hand will hold it, for later plans
    view: PlanView | None = None  # what the plan shows in the replay
    receiving: str = ""


class CyclePlanner(Protocol):
    """The motions the cycle asks for, planned from what the robot perceives."""

    def grasp(self, label: str, q: np.ndarray) -> PlannedMotions:
        """To the pre-grasp and along the approach (gripper open), then the lift ("lift",
        gripper closed), as named motions."""

    def carry(self, q: np.ndarray, held: object) -> PlannedMotions:
        """From the lifted object to the handover point, holding the grasp's `held`."""

    def follow(self, q: np.ndarray, v: np.ndarray, aim: np.ndarray, held: object):
        """State to state, to hold the object out at `aim` (m, world: OFFER in front of the
        person's hand), or beside it where the person's perceived hand leaves no room there."""

    def retreat(self, q: np.ndarray, held: object, let_go: object = None) -> PlannedMotions:
        """Back to the ready posture, with the object `held` or (None) without; `let_go` is the
        object just let go of (or missed), still between the fingers, to back away from."""

    def put_back(
        self, q: np.ndarray, held: object, lifted: np.ndarray, came: list[np.ndarray]
    ) -> PlannedMotions:
        """Holding `held`, back to `lifted` (the configuration the grasp's lift ended in) along
        the way it `came` from there (configurations, possibly none), then down to where it
        was grasped."""

    def back_off(self, q: np.ndarray, let_go: object) -> PlannedMotions:
        """The hand straight back from the object just let go of (no motion when it is clear
        of it already)."""


@dataclasses.dataclass
class _Running:
    name: str
    motion: Motion
    start: float


@dataclasses.dataclass
class Cycle:
    """The cycle's record: `phase`, `failure` (None unless failed), `reason`, when each phase
    began (`phase_times`, s), planning wall time (`planning_s`), when the target was
    recognised (`recognised_time`) and which (`target`: the object fetched now), the arm lift
    (m) the robot watched from (`watch_lift`; the supervisor's, 0 for the ready posture), the
    person's arm it hands to (`receiving`, "r" or "l", once the carry is planned) and, once
    the person has asked for another object, the one first fetched (`first_target`) and when
    the correction was seen (`corrected_time`)."""

    phase: Phase = Phase.WATCH
    failure: Failure | None = None
    reason: str = ""
    target: str | None = None
    recognised_time: float = math.nan
    phase_times: dict[str, float] = dataclasses.field(default_factory=dict)
    planning_s: float = 0.0
    watch_lift: float = 0.0
    receiving: str = ""
    first_target: str | None = None
    corrected_time: float = math.nan

    @property
    def over(self) -> bool:
        return self.phase in (Phase.DONE, Phase.FAILED)


class HandoverCycle:
    """Steps the cycle on percepts; `command(time)` gives what the robot should do then.

    A copy (Drake copies a system's state with each context) shares the planner and the
    motions, which are never changed once made, and copies the rest."""

    def __init__(self, planner: CyclePlanner):
        self._planner = planner
        self._held: object = None
        self.cycle = Cycle()
        self._queue: list[tuple[str, Motion]] = []
        self._running: _Running | None = None
        self._hold: tuple[np.ndarray, np.ndarray] | None = None  # (q, 0) to stand still at
        self._gripper = OPEN
        self._since = 0.0  # when the current wait began
        self._seen_at = 0.0  # when the person was last seen
        self._hand_at_object = -math.inf  # when a hand was last seen at, or tugged, the object
        self._carried_force: np.ndarray | None = None  # on the wrist as it began presenting
        self._tugged = False  # whether the last decision felt a tug
        self._hand_rest: tuple[np.ndarray, float] | None = None  # (where, since when) presenting
        self._held_width = math.inf  # the opening closed on the object
        self._followed_at = -math.inf  # when it last tried to follow the hand
        self._followed_hand: np.ndarray | None = None  # where the hand was, as it was followed
        self._object_start: np.ndarray | None = None
        self._emptied_at: float | None = None  # when the fingers closed on nothing, presenting
        self._after_retreat: tuple[Phase, Failure | None, str] = (Phase.DONE, None, "")
        self._lift_motion: tuple[str, Motion] | None = None
        self._person: np.ndarray | None = None
        self._turned: float | None = None  # when it turned to the person, the object lifted
        self._blocked: float | None = None  # when the plan now wanted first found no way
        self._retry_at = -math.inf  # when to try that plan again
        self._putting = ""  # putting back: "plan", "lower", "open", "leave"; "" otherwise
        self._came: list[np.ndarray] = []  # the way it carried the object it puts back
        self._next_target: str | None = None  # to fetch once the object lifted is back
        self._seek_until: float | None = None  # until when it looks for the object asked for
        self.view = PlanView()  # what the plans so far show in the replay

    def __deepcopy__(self, memo: dict) -> HandoverCycle:
        clone = copy.copy(self)
        clone.cycle = copy.deepcopy(self.cycle, memo)
        clone._queue = list(self._queue)
        return clone

    # What to do now -------------------------------------------------------------------------

    def command(self, time: float) -> tuple[np.ndarray | None, np.ndarray | None, float]:
        """(positions, velocities, gripper opening) to command at `time`; positions None while
        there is nothing to follow (hold where it stands)."""
        if self._running is not None:
            q, v = self._running.motion.state(time - self._running.start)
            return q, v, self._gripper
        if self._hold is not None:
            return self._hold[0], self._hold[1], self._gripper
        return None, None, self._gripper

    @property
    def gripper(self) -> float:
        """The gripper opening (m) to command now."""
        return self._gripper

    def gaze(self) -> np.ndarray | None:
        """Where to look (m, world): the object until it is lifted, then the person; None
        while watching (the head is the watcher's), unless a grasp of the object asked for
        found no way: then the object, so the table before it comes into view (watching a
        standing person, the head is raised and the table's near edge, unseen, runs on toward
        the robot and keeps its base from the object)."""
        if self.cycle.phase is Phase.WATCH:
            return self._object_start if self._blocked is not None else None
        on_object = (Phase.APPROACH, Phase.GRASP, Phase.LIFT)
        if self.cycle.phase in on_object and self._turned is None:
            return self._object_start
        return self._person

    def seeing(self) -> str | None:
        """The object asked for, while the robot has not seen it since (watching a standing
        person's face, the table is below the camera's view): the head turns to where it was
        last seen, and the grasp is planned once the camera shows it, or after SEEK_S without
        (then the cycle goes on without the object's start to check the lift against)."""
        watching = self.cycle.phase is Phase.WATCH and self.cycle.target is not None
        return self.cycle.target if watching and self._object_start is None else None

    # Stepping ---------------------------------------------------------------------------------

    def wait_until(self, time: float) -> None:
        """Plan nothing before `time` (s): the robot is moving on a command that is not the
        cycle's (the supervisor's raise to where it watches from), and a plan starts at rest
        where it stands. A request recognised meanwhile is recorded when it is."""
        self._retry_at = max(self._retry_at, time)

    def step(self, p: Percepts) -> Cycle:
        """Advance on the latest percepts; returns the cycle's record."""
        self._person = p.person if p.person is not None else self._person
        handler: Callable[[Percepts], None] = getattr(self, f"_{self.cycle.phase.value}", None)
        if handler is not None:
            handler(p)
        return self.cycle

    def _watch(self, p: Percepts) -> None:
        if self.cycle.target is None:
            if p.target is None:
                return
            self.cycle.target, self.cycle.recognised_time = p.target, p.time
            self._object_start = p.object_seen
        if p.time < self._retry_at:
            return
        self._object_start = self._object_start if p.object_seen is None else p.object_seen
        if self._object_start is None:  # out of view: the head turns to it first (`seeing`)
            self._seek_until = p.time + SEEK_S if self._seek_until is None else self._seek_until
            if p.time < self._seek_until:
                return
        planned = self._plan(self._planner.grasp(self.cycle.target, p.q), p)
        if planned is None:
            return
        *reach, lift = planned.motions
        self._lift_motion, self._held = lift, planned.held
        self._gripper = OPEN
        self._enter(Phase.APPROACH, p.time)
        self._queue = list(reach)

    def _approach(self, p: Percepts) -> None:
        if self._moving(p.time):
            return
        self._gripper = CLOSED
        self._enter(Phase.GRASP, p.time)

    def _grasp(self, p: Percepts) -> None:
        if p.time - self._since < SETTLE_S:
            return
        if p.opening < HELD_OPENING:
            self._fail_and_retreat(p, Failure.GRASP_MISSED, "the gripper closed on nothing")
            return
        self._held_width = p.opening
        self._enter(Phase.LIFT, p.time)
        self._queue = [self._lift_motion]

    def _lift(self, p: Percepts) -> None:
        if self._dropped(p) or self._moving(p.time):
            return
        if self._turned is None:
            start, seen = self._object_start, p.object_seen
            if start is not None and seen is not None and seen[2] - start[2] < RISE:
                reason = f"the object rose {100 * (seen[2] - start[2]):.1f} cm with the hand"
                self._fail_and_retreat(p, Failure.GRASP_MISSED, reason)
                return
            self._turned = p.time  # the person in view again before planning the way there
        if self._corrected(p):
            return
        if p.time - self._turned < LOOK_S or p.time < self._retry_at:
            return
        planned = self._plan(self._planner.carry(p.q, self._held), p, holding=True)
        if planned is not None:
            self.cycle.receiving = planned.receiving
            self._enter(Phase.CARRY, p.time)
            self._queue = list(planned.motions)

    def _carry(self, p: Percepts) -> None:
        if p.opening < HELD_OPENING:
            # Taken on the way or dropped: presenting, the robot holds still and the camera
            # tells (a hand held out beside the carry's slow end took the cup, and the robot
            # called it dropped: the moved layout's trial 2 of seed 2).
            self._start_presenting(p)
            self._empty_fingers(p)
            return
        if self._corrected(p):
            return
        if not self._moving(p.time):
            self._start_presenting(p)

    def _corrected(self, p: Percepts) -> bool:
        """Whether the person has asked for another object than the one lifted (heeded once
        per cycle): the robot stands still, puts the object back and then fetches that one."""
        asked = p.correction
        if asked is None or asked == self.cycle.target or self.cycle.first_target is not None:
            return False
        self.cycle.first_target, self.cycle.corrected_time = self.cycle.target, p.time
        self._next_target, self._putting = asked, "plan"
        self._came = self._carried_so_far(p.time)
        self._hold_still(p)
        self._enter(Phase.PUT_BACK, p.time)
        return True

    def _carried_so_far(self, time: float, samples: int = 16) -> list[np.ndarray]:
        """Configurations along the carry under way, from its start to `time` (none when it is
        not carrying)."""
        running = self._running
        if running is None or running.name != "carry":
            return []
        elapsed = min(time - running.start, running.motion.duration)
        return [running.motion.state(t)[0] for t in np.linspace(0.0, elapsed, samples)]

    def _put_back(self, p: Percepts) -> None:
        """Back over the object's place and down (`planner.put_back`), open, back off it and
        fetch the object the person asked for."""
        holding = self._putting in ("plan", "lower")
        if (holding and self._dropped(p)) or self._moving(p.time):
            return
        if self._putting == "plan":
            if p.time < self._retry_at:
                return
            lift = self._lift_motion[1]
            lifted = lift.state(lift.duration)[0]
            put_back = self._planner.put_back(p.q, self._held, lifted, self._came)
            planned = self._plan(put_back, p, holding=True)
            if planned is not None:
                self._queue, self._putting = list(planned.motions), "lower"
        elif self._putting == "lower":
            self._gripper, self._putting, self._since = OPEN, "open", p.time
        elif self._putting == "open" and p.time - self._since >= SETTLE_S:
            self._leave(p)
        elif self._putting == "leave":
            self._fetch_next(p.time)

    def _leave(self, p: Percepts) -> None:
        """The object is back where it stood and let go of: the hand backs straight off it
        (the next grasp is planned from there, not from the arm stowed), or, with no way
        straight back, the robot retreats; then it fetches the next object."""
        planned = self._planner.back_off(p.q, self._held)
        self.cycle.planning_s += planned.seconds
        if planned.ok:
            self._queue, self._putting = list(planned.motions), "leave"
            return
        self._retreat_then(p, Phase.WATCH, None, "", holding=False)
        self._fetch_next()

    def _fetch_next(self, watch_from: float | None = None) -> None:
        """Asked for the next object: watch (`_watch` plans its grasp), at once from
        `watch_from` (s), else once the retreat under way is over."""
        self.cycle.target, self._next_target, self._putting = self._next_target, None, ""
        self._held, self._lift_motion, self._turned = None, None, None
        self._held_width, self._object_start, self._seek_until = math.inf, None, None
        if watch_from is not None:
            self._enter(Phase.WATCH, watch_from)

    def _start_presenting(self, p: Percepts) -> None:
        self._enter(Phase.PRESENT, p.time)
        self._seen_at = p.time
        self._carried_force = p.wrist_force

    def _present(self, p: Percepts) -> None:
        if any(point is not None for point in (p.person, p.face, p.hand)):
            self._seen_at = p.time
        if p.hand is not None and _distance(p.hand, p.palm) <= REACH:
            self._hand_at_object = p.time
        felt = self._tug(p) > TUG
        tugged, self._tugged = felt and self._tugged, felt  # felt now and at the last decision
        if tugged or (p.opening >= HELD_OPENING and self._pulled_across(p)):
            self._hand_at_object = p.time
        if p.pull > PULL or tugged:
            if not self._moving(p.time):
                self._let_go(p)
                return
            self._hold_still(p)  # a tug on the way to the hand: feel again standing still
        drawn_out = p.opening < HELD_OPENING and p.time - self._hand_at_object <= TAKEN_S
        forced_open = p.opening > self._held_width + SPREAD and not self._knocked(p)
        if drawn_out or forced_open:
            self._let_go(p)  # the person has it, drawn out of the fingers or through them
            return
        if p.opening < HELD_OPENING:
            self._empty_fingers(p)
            return
        self._emptied_at = None  # holding again (a glitch of the opening's sensor)
        if p.time - self._since > WAIT_S:
            reason = f"no hand came for the object in {WAIT_S:.0f} s; holding it"
            self._fail_and_retreat(p, Failure.TIMEOUT, reason, holding=True)
            return
        if p.time - self._seen_at > LOST_S:
            reason = f"the person was out of sight for {LOST_S:.0f} s; holding the object"
            self._fail_and_retreat(p, Failure.PERSON_WITHDREW, reason, holding=True)
            return
        # A hand near the object is not yet holding it (a hand held out, a person who changes
        # their mind): the robot lets go only when it feels the object taken, above.
        if p.hand is None or p.palm is None:
            return
        self._note_hand_rest(p)
        if self._hand_coming(p):
            self._hold_still(p)  # the person reaches for it: hold it where it is
            return
        if not (_distance(p.hand, p.palm) > FOLLOW_BEYOND or self._waiting_short(p)):
            return
        if p.time - self._followed_at > FOLLOW_EVERY_S and not self._moving(p.time):
            self._follow(p)

    def _note_hand_rest(self, p: Percepts) -> None:
        """Where the hand has rested, and since when: a hand first seen on its way out (the
        reference run's trial 53) rests only once it has stopped."""
        if self._hand_rest is None or _distance(p.hand, self._hand_rest[0]) > HAND_STILL:
            self._hand_rest = (p.hand, p.time)

    def _hand_coming(self, p: Percepts) -> bool:
        """Whether the hand the robot is following has come over COMING toward the palm:
        the person reaches for the object, aimed where it was, and following on would bring
        the fingers into the hand (the standing layout's trial 25: a hand that waited 53 cm off
        reached as the robot set off toward it, and met the fingers 22 cm on)."""
        followed = self._followed_hand
        if followed is None or self._running is None or self._running.name != "follow":
            return False
        toward = (p.palm - followed) / _distance(followed, p.palm)
        return float((p.hand - followed) @ toward) > COMING

    def _waiting_short(self, p: Percepts) -> bool:
        """Whether the hand has waited still for NUDGE_S without coming for an object held
        farther than OFFER from it."""
        waited = p.time - self._hand_rest[1] > NUDGE_S
        return waited and _distance(p.hand, p.palm) > OFFER + HAND_STILL

    def _load_change(self, p: Percepts) -> tuple[np.ndarray, np.ndarray] | None:
        """The change of the load on the wrist (N) since the robot began presenting, and the
        unit direction from the palm to the person; None without the sensor or a person seen."""
        known = (p.wrist_force, self._carried_force, self._person, p.palm)
        if any(value is None for value in known):
            return None
        toward = self._person - p.palm
        distance = float(np.linalg.norm(toward))
        if distance == 0.0:
            return None
        return p.wrist_force - self._carried_force, toward / distance

    def _tug(self, p: Percepts) -> float:
        """N by which the load on the wrist pulls harder toward the person than it did as the
        robot began presenting (0 without the sensor or a person seen, or when the change
        points more than TUG_CONE_DEG away from the person)."""
        felt = self._load_change(p)
        if felt is None:
            return 0.0
        change, toward = felt
        # The force on the wrist points where the load is pulled: toward the person.
        return float(change @ toward) if _toward(change, toward) else 0.0

    def _pulled_across(self, p: Percepts) -> bool:
        """Whether the load on the wrist has changed by over TUG in the horizontal since the
        robot began presenting: something other than gravity has hold of the object."""
        felt = self._load_change(p)
        return felt is not None and float(np.linalg.norm(felt[0][:2])) > TUG

    def _knocked(self, p: Percepts) -> bool:
        """Whether the wrist feels the object knocked rather than drawn: a change of load over
        TUG that points more than TUG_CONE_DEG off the person (a hand striking it on its way
        in forces the fingers open too: the reference run's trial 25, 18 N sideways)."""
        felt = self._load_change(p)
        if felt is None:
            return False
        change, toward = felt
        return float(np.linalg.norm(change)) > TUG and not _toward(change, toward)

    def _empty_fingers(self, p: Percepts) -> None:
        """Fingers closed on nothing with no hand seen at the object nor tug felt: dropped, or
        taken by a hand out of the camera's sight. The robot holds still for EMPTY_S, then the
        camera tells: an object seen STILL_UP above where it stood is in the person's hand."""
        if self._emptied_at is None:
            self._emptied_at = p.time
            self._hold_still(p)
        if p.time - self._emptied_at < EMPTY_S:
            return
        seen, start = p.object_seen, self._object_start
        if seen is not None and start is not None and seen[2] > start[2] + STILL_UP:
            self._let_go(p)
            return
        self._dropped(p)

    def _hold_still(self, p: Percepts) -> None:
        """Drop any motion and stand where the joints are."""
        self._running, self._queue = None, []
        self._hold = (p.q, np.zeros_like(p.q))

    def _let_go(self, p: Percepts) -> None:
        self._gripper = min(OPEN, p.opening + LET_GO)
        self._hold_still(p)
        self._enter(Phase.RELEASE, p.time)

    def _follow(self, p: Percepts) -> None:
        """Re-target state to state (ruckig) to hold the object out at the hand."""
        self._followed_at, self._followed_hand = p.time, p.hand
        toward = (p.palm - p.hand) / _distance(p.hand, p.palm)
        offer = p.hand + OFFER * toward
        planned = self._planner.follow(p.q, np.zeros_like(p.q), offer, self._held)
        self.cycle.planning_s += planned.seconds
        if planned.ok:
            self._queue = list(planned.motions)
            self.view = self.view.updated(planned.view)
            self._moving(p.time)

    def _release(self, p: Percepts) -> None:
        opened = p.opening >= self._gripper - HELD_OPENING
        if p.time - self._since < SETTLE_S or not (opened or p.time - self._since > 3 * SETTLE_S):
            return
        self._retreat_then(p, Phase.DONE, None, "", holding=False)

    def _retreat(self, p: Percepts) -> None:
        if self._moving(p.time):
            return
        phase, failure, reason = self._after_retreat
        self._finish(phase, failure, reason, p.time)

    # Helpers ----------------------------------------------------------------------------------

    def _plan(self, planned: PlannedMotions, p: Percepts, holding: bool = False):
        """The motions planned, or None: to be tried again after RETRY_EVERY_S, or, once the
        plan has found no way for PATIENCE_S, failed as unreachable."""
        self.cycle.planning_s += planned.seconds
        if planned.ok:
            self._blocked = None
            self.view = self.view.updated(planned.view)
            return planned
        self._blocked = p.time if self._blocked is None else self._blocked
        if p.time - self._blocked < PATIENCE_S:
            self._retry_at = p.time + RETRY_EVERY_S
            return None
        reason = f"{planned.reason} (tried for {p.time - self._blocked:.0f} s)"
        self._fail_and_retreat(p, Failure.UNREACHABLE, reason, holding=holding)
        return None

    def _moving(self, time: float) -> bool:
        """Whether a motion is still under way at `time`; starts the next queued one when the
        last has ended."""
        running = self._running
        if running is not None and time - running.start < running.motion.duration:
            return True
        if running is not None:
            end = running.motion.state(running.motion.duration)[0]
            self._hold, self._running = (end, np.zeros_like(end)), None
        if not self._queue:
            return False
        name, motion = self._queue.pop(0)
        if name == "lift":
            self._gripper = CLOSED
        self._running = _Running(name, motion, time)
        return True

    def _dropped(self, p: Percepts) -> bool:
        if p.opening >= HELD_OPENING:
            return False
        self._fail_and_retreat(p, Failure.DROPPED, "the gripper closed: the object slipped out")
        return True

    def _fail_and_retreat(
        self, p: Percepts, failure: Failure, reason: str, holding: bool = False
    ) -> None:
        if not holding:
            self._gripper = OPEN
        self._retreat_then(p, Phase.FAILED, failure, reason, holding)

    def _retreat_then(self, p, phase: Phase, failure, reason: str, holding: bool) -> None:
        """Retreat to the ready posture, then end in `phase`; end there at once if no retreat
        can be planned (the robot then stands where it is)."""
        self._hold_still(p)
        self._after_retreat = (phase, failure, reason)
        # Known now, not only once folded: a run that ends mid-retreat still says why.
        self.cycle.failure, self.cycle.reason = failure, reason
        held, let_go = (self._held, None) if holding else (None, self._held)
        planned = self._planner.retreat(p.q, held, let_go)
        self.cycle.planning_s += planned.seconds
        if not planned.ok:
            self._finish(phase, failure, reason, p.time)
            return
        self._enter(Phase.RETREAT, p.time)
        self._queue = list(planned.motions)
        self.view = self.view.updated(planned.view)

    def _finish(self, phase: Phase, failure, reason: str, time: float) -> None:
        self.cycle.failure, self.cycle.reason = failure, reason
        self._enter(phase, time)

    def _enter(self, phase: Phase, time: float) -> None:
        self.cycle.phase, self._since = phase, time
        self.cycle.phase_times.setdefault(phase.value, time)


def _toward(change: np.ndarray, toward: np.ndarray) -> bool:
    """Whether the force `change` points within TUG_CONE_DEG of the unit direction `toward`."""
    along = float(change @ toward)
    return along >= math.cos(math.radians(TUG_CONE_DEG)) * float(np.linalg.norm(change))


def _distance(hand: np.ndarray, palm: np.ndarray | None) -> float:
    """m from the hand to the palm (infinite when the palm is not known)."""
    return float(np.linalg.norm(hand - palm)) if palm is not None else math.inf
