"""Plan from what the robot perceives. A grasp: its configurations by
inverse kinematics (base placed by the arm's effectivity map), the move to the pre-grasp by
trajectory optimisation, the approach along a straight line in joint space when it is clear
(optimised otherwise). A handover: the pose in the mutual area, the carry there optimised.
Each path is timed by toppra within the joints' limits.

Every stage's wall time is kept, so the planning benchmark reports where the time goes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import BASE_JOINTS, GRIPPER_JOINT, GRIPPER_MIMIC_JOINT, PALM_FRAME
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.planning.base_route import route_around
from hsr_handover.robot.planning.grasp_configurations import grasp_configurations
from hsr_handover.robot.planning.handover_pose import (
    HandoverPose,
    plan_handover_pose,
    unseeded_handover_pose,
)
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.planning_scene import PERSON, PlanningScene
from hsr_handover.robot.planning.timing import JointLimits, TimedPath, time_path
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    COLLISION_SAMPLES,
    CONTROL_POINTS,
    STOWED,
    StartContact,
    Target,
    approached_target,
    optimize_path,
    route_guess,
    start_contact,
    straight_guess,
)

STAGES = ("ik", "optimisation", "timing")
HANDOVER = "handover"  # a handover plan's target
RETREAT = "retreat"  # a retreat plan's target and motion
POSTURE = "posture"  # a plan to a posture given joint by joint: its target and motion
BACK_OFF = "back off"  # a retreat's first leg when it starts at the person's hand
PUT_BACK = "put back"  # a put-back plan's target, and its move back over the object's place
LOWER = "lower"  # a put-back's last leg: the lift, backwards
STRAIGHT_LEGS = (
    "approach",
    "lift",
    BACK_OFF,
    LOWER,
)  # short moves of the hand: straight when clear
AT_POSTURE = 0.01  # rad or m: every joint this near a posture is at it (no move to plan)
STOW_BACK_UPS = (0.0, 0.15, 0.3)  # m the base may back up to stow the arm
STOWED_HOLDING = {"arm_lift_joint": 0.3, "torso_lift_joint": 0.15}
"""Stowed with an object still in the hand (a handover nobody took), the arm raised 30 cm: at
STOWED's height the object rests on the base's front, which levered a cup out of the fingers
2 s after the retreat."""
BACK_OFF_M = 0.20
"""m the palm first backs straight out, against its approach, when a retreat starts within the
collision bound of the person: after letting go, the hand that took the object is at the
fingers, and no path from inside the person's perceived capsules is feasible."""
CHECK_STEP = 0.01  # s between clearance checks of a timed trajectory
VERIFY_PER_SAMPLE = 4  # an optimised path is checked at this many times its optimiser's samples
DIP_ALLOWANCE = COLLISION_BOUND - 0.01
"""m a path may come nearer between its samples than at them: 1 cm clear where the
optimiser kept COLLISION_BOUND."""
MAX_SAMPLES = 4 * COLLISION_SAMPLES
"""A path that dips between its samples is optimised again from itself at twice the samples,
up to this many. (A 22 s carry round the table at 30 samples swept the held cup 16 cm into
the perceived table between two of them.)"""


@dataclasses.dataclass(frozen=True)
class Motion:
    """One timed segment: `name` ("move" to the pre-grasp, "approach" to the grasp, "lift" off
    the table, "carry" to the handover), the obstacles it may touch (`ignore`), and the timed
    path."""

    name: str
    ignore: tuple[str, ...]
    timed: TimedPath


class Leg(NamedTuple):
    """A path to plan: its `name`, the obstacles it may touch (`ignore`), its ends, and the one
    of them it closes the hand on (`target`, kept as far as the end keeps it: `Target`)."""

    name: str
    ignore: tuple[str, ...]
    q_from: np.ndarray
    q_to: np.ndarray
    target: str = ""


@dataclasses.dataclass(frozen=True)
class Held:
    """An object in the hand: its perceived `label`, the configuration `q_grasp` (plant
    positions) in which the hand closed on it and its `shape` as perceived then, standing on
    the table (lifted, the camera sees it as a column from the table up to its top)."""

    label: str
    q_grasp: np.ndarray
    shape: ObjectShape | None = None


def holding(scene: PlanningScene, held: Held | None, q_now: np.ndarray):
    """`scene.holding` for the object `held` as grasped, with the HSR now at `q_now` (nothing
    for None)."""
    if held is None:
        return contextlib.nullcontext()
    return scene.holding(held.label, held.q_grasp, held.shape, q_now)


@dataclasses.dataclass(frozen=True, kw_only=True)
class Plan(Outcome):
    """`ok` with the `motions` ending at the configuration `goal`, or not with the `reason`;
    the wall `seconds` of each of STAGES and the IK solves tried; for a grasp, the object as
    it will be `held`; for a handover, the `pose` chosen (the maps and the point, for the
    replay)."""

    target: str
    motions: tuple[Motion, ...] = ()
    seconds: dict[str, float] = dataclasses.field(default_factory=dict)
    ik_solves: int = 0
    goal: np.ndarray | None = None
    held: Held | None = None
    pose: HandoverPose | None = None

    @property
    def duration(self) -> float:
        """s the motions take, end to end."""
        return sum(motion.timed.duration for motion in self.motions)

    @property
    def plan_seconds(self) -> float:
        return sum(self.seconds.values())


def plan_grasp(
    scene: PlanningScene,
    arm_map: ArmEffectivity | None,
    label: str,
    q_now: np.ndarray,
    limits: JointLimits,
) -> Plan:
    """Plan the robot from `q_now` (plant positions) to grasping the perceived object `label`:
    a move to the pre-grasp, the approach, and (the gripper closed) the lift. With `arm_map`
    None the base and the arm are not seeded by the effectivity map (the benchmark's
    baseline). Never raises for a target it cannot reach: `reason` says why."""
    found = grasp_configurations(scene, arm_map, label, q_now)
    seconds = dict.fromkeys(STAGES, 0.0) | {"ik": found.seconds}
    if not found.ok:
        return Plan(
            ok=False, reason=found.reason, target=label, seconds=seconds, ik_solves=found.ik_solves
        )
    closed = _fingers_as(scene, found.q_grasp, found.q_lifted)  # it closes between the legs
    # The robot opens the gripper at once as it sets off (to 10 cm, within 1 cm of the
    # pre-grasp's width and GRIP_CLEARANCE), so the move is planned open from its start: a move
    # planned opening gradually had the open fingers cut 2 cm into the table (the standing
    # layout's trial 7, seed 1).
    opened = _fingers_as(scene, q_now, found.q_pregrasp)
    legs = (Leg("move", (), opened, found.q_pregrasp),
            Leg("approach", (label,), found.q_pregrasp, found.q_grasp, target=label),
            Leg("lift", (label,), closed, found.q_lifted))  # fmt: skip
    plan = _plan_legs(scene, label, legs, limits, seconds, found.ik_solves)
    if not plan.ok:
        return plan
    held = Held(label, closed, scene.scene.object_named(label))
    return dataclasses.replace(plan, held=held)


def _fingers_as(scene: PlanningScene, q: np.ndarray, like: np.ndarray) -> np.ndarray:
    """`q` with the fingers as they are in `like`."""
    q = q.copy()
    for joint in (GRIPPER_JOINT, GRIPPER_MIMIC_JOINT):
        q[scene.index(joint)] = like[scene.index(joint)]
    return q


def plan_handover(
    scene: PlanningScene,
    arm_map: ArmEffectivity | None,
    person: PersonEffectivity,
    q_now: np.ndarray,
    limits: JointLimits,
    held: Held | None = None,
) -> Plan:
    """Plan the robot from `q_now`, with the object `held` (a grasp plan's) moving with the
    hand and kept clear like the hand, to handing it over in the mutual area. With `arm_map`
    None (the baseline) the hand goes to the rule's ideal point, IK starting from the arm as
    it is. Never raises: an unreachable person gives `reason`."""
    if held is None:
        return _plan_handover(scene, arm_map, person, q_now, limits, ())
    with holding(scene, held, q_now):
        return _plan_handover(scene, arm_map, person, q_now, limits, (held.label,))


def plan_retreat(
    scene: PlanningScene,
    q_now: np.ndarray,
    limits: JointLimits,
    held: Held | None = None,
    released: str = "",
) -> Plan:
    """Plan the arm from `q_now` back to STOWED over the base (backed up from where it stands
    if the arm cannot stow there), with the object `held` (if any) moving with the hand; the
    object `released` (its label: just let go of, or missed, and still between the fingers)
    is backed away from and then ignored. Never raises: `reason` says why there is none."""
    seconds = dict.fromkeys(STAGES, 0.0)
    if held is None:
        ignore = (released,) if released else ()
        q_stowed = _stowed(scene, q_now, ignore)
        legs = (Leg(RETREAT, ignore, q_now, q_stowed),)
        q_back = _backed_off(scene, q_now, (PERSON, *ignore))
        if q_back is not None:
            legs = (
                Leg(BACK_OFF, (PERSON, *ignore), q_now, q_back),
                Leg(RETREAT, ignore, q_back, q_stowed),
            )
        return _plan_legs(scene, RETREAT, legs, limits, seconds, 0)
    with holding(scene, held, q_now):
        q_stowed = _stowed(scene, q_now, (held.label,), STOWED | STOWED_HOLDING)
        leg = Leg(RETREAT, (held.label,), q_now, q_stowed)
        return _plan_legs(scene, RETREAT, (leg,), limits, seconds, 0)


def plan_put_back(
    scene: PlanningScene,
    q_now: np.ndarray,
    held: Held,
    q_lifted: np.ndarray,
    limits: JointLimits,
    came: Sequence[np.ndarray] = (),
) -> Plan:
    """Plan the object `held` back to where it was grasped: from `q_now` to `q_lifted` (where
    the grasp plan lifted it to) with the object moving with the hand, first along the way it
    came (`came`: configurations from `q_lifted` to `q_now`, the optimiser's first guess),
    then the lift backwards, straight down to `held.q_grasp`, the object standing where it
    stood (ignored there, as on the way up). Never raises: `reason` says why there is none."""
    seconds = dict.fromkeys(STAGES, 0.0)
    ignore = (held.label,)
    back: tuple[Motion, ...] = ()
    if np.abs(q_now - q_lifted).max() > AT_POSTURE:
        with holding(scene, held, q_now):
            plan = _way_back(scene, q_now, q_lifted, came, ignore, limits, seconds)
        if not plan.ok:
            return plan
        back = plan.motions
    leg = Leg(LOWER, ignore, q_lifted, held.q_grasp)
    plan = _plan_legs(scene, PUT_BACK, (leg,), limits, seconds, 0)
    return dataclasses.replace(plan, motions=back + plan.motions) if plan.ok else plan


def _way_back(scene, q_now, q_to, came, ignore, limits, seconds) -> Plan:
    """From `q_now` to `q_to` the way it `came` (reversed) when that keeps clear as a path
    checked between its samples must, else as any leg. From part way along a carry the line
    back to its start and the stowed round both failed (the moved layout's trial 12 of seed 2),
    and so did the optimiser started from the way it came, which passed a cup 1.2 cm off:
    inside the optimiser's bound at its samples, clear as a verified path must be."""
    if len(came) >= 2:
        started = time.perf_counter()
        points = np.array(came[::-1], dtype=float).T
        points[:, 0], points[:, -1] = q_now, q_to
        path = BsplineTrajectory(BsplineBasis(4, points.shape[1]), points)
        contact = start_contact(scene, q_now, ignore)
        dips = path_dips(scene, path, ignore, contact, VERIFY_PER_SAMPLE * COLLISION_SAMPLES)
        seconds["optimisation"] += time.perf_counter() - started
        if dips.max() <= DIP_ALLOWANCE:
            started = time.perf_counter()
            timed = time_path(path, limits)
            seconds["timing"] += time.perf_counter() - started
            if timed.ok:
                motion = Motion(PUT_BACK, ignore, timed)
                return Plan(
                    ok=True,
                    reason="ok",
                    target=PUT_BACK,
                    motions=(motion,),
                    seconds=seconds,
                    ik_solves=0,
                    goal=q_to,
                )
    leg = Leg(PUT_BACK, ignore, q_now, q_to)
    return _plan_legs(scene, PUT_BACK, (leg,), limits, seconds, 0)


def plan_back_off(
    scene: PlanningScene, q_now: np.ndarray, limits: JointLimits, released: str
) -> Plan:
    """The palm BACK_OFF_M straight back from the object `released` (just let go of, still
    between the fingers), the rest of the robot where it is: where the next grasp is planned
    from after an object is put back, rather than from the arm stowed. No motion when the hand
    is clear of it already; not ok when there is no such configuration clear of the rest."""
    seconds = dict.fromkeys(STAGES, 0.0)
    distance = scene.clearances_at(q_now).get(released, math.inf)
    if distance >= COLLISION_BOUND:
        return Plan(
            ok=True,
            reason="ok",
            target=BACK_OFF,
            motions=(),
            seconds=seconds,
            ik_solves=0,
            goal=q_now,
        )
    q_back = _backed_off(scene, q_now, (released,))
    if q_back is None:
        return Plan(
            ok=False,
            reason="no way back from the object let go of",
            target=BACK_OFF,
            seconds=seconds,
        )
    return _plan_legs(scene, BACK_OFF, (Leg(BACK_OFF, (released,), q_now, q_back),), limits,
                      seconds, 0)  # fmt: skip


def plan_posture(
    scene: PlanningScene, q_now: np.ndarray, q_goal: np.ndarray, limits: JointLimits
) -> Plan:
    """Plan from `q_now` to the posture `q_goal` (plant positions), clear of everything the
    robot perceives. Never raises: `reason` says why there is none."""
    seconds = dict.fromkeys(STAGES, 0.0)
    leg = Leg(POSTURE, (), q_now, q_goal)
    return _plan_legs(scene, POSTURE, (leg,), limits, seconds, 0)


def _stowed(
    scene: PlanningScene, q_now: np.ndarray, ignore: tuple[str, ...], posture=STOWED
) -> np.ndarray:
    """`q_now` with the arm in `posture`, the base backed up by the first of STOW_BACK_UPS
    that clears the collision bound (the last if none does): a base that came up to the table
    to present an object has no room there to fold the arm."""
    x, y, yaw = (scene.index(joint) for joint in BASE_JOINTS)
    for back in STOW_BACK_UPS:
        q_stowed = q_now.copy()
        for joint, value in posture.items():
            q_stowed[scene.index(joint)] = value
        q_stowed[[x, y]] -= back * np.array([np.cos(q_now[yaw]), np.sin(q_now[yaw])])
        if scene.clearance_at(q_stowed, ignore) >= COLLISION_BOUND:
            break
    return q_stowed


def _backed_off(scene: PlanningScene, q_now: np.ndarray, near: tuple[str, ...]):
    """The configuration with the palm BACK_OFF_M straight back from where it is (base still),
    when `q_now` is within the collision bound of one of the obstacles named in `near` (the
    person, the object let go of); None when it is not, or when no such configuration clears
    everything else."""
    plant, context = scene.plant, scene.plant_context
    plant.SetPositions(context, q_now)
    distance, nearest = scene.clearance()
    if distance >= COLLISION_BOUND or nearest not in near:
        return None
    palm = plant.GetFrameByName(PALM_FRAME, scene.robot).CalcPoseInWorld(context)
    approach, closing = palm.rotation().matrix()[:, 2], palm.rotation().matrix()[:, 1]
    opening = 2 * q_now[scene.index(GRIPPER_JOINT)]
    goal = PalmGoal(palm.translation() - BACK_OFF_M * approach, approach, closing, opening)
    found = solve_palm_ik(scene, goal, q_now, ignore=near, base_fixed=True)
    return found.q if found.ok else None


def _plan_handover(scene, arm_map, person, q_now, limits, ignore: tuple[str, ...]) -> Plan:
    start = time.perf_counter()
    if arm_map is None:
        pose = unseeded_handover_pose(scene, person, q_now, ignore)
    else:
        pose = plan_handover_pose(scene, arm_map, person, q_now, ignore)
    seconds = dict.fromkeys(STAGES, 0.0) | {"ik": time.perf_counter() - start}
    if not pose.ok:
        return Plan(ok=False, reason=pose.reason, target=HANDOVER, seconds=seconds)
    leg = Leg("carry", ignore, q_now, pose.q)
    plan = _plan_legs(scene, HANDOVER, (leg,), limits, seconds, 1)
    return dataclasses.replace(plan, pose=pose) if plan.ok else plan


def _plan_legs(scene, target, legs: tuple[Leg, ...], limits, seconds, ik_solves) -> Plan:
    """Path and timing for each leg in turn."""
    motions = []
    for name, ignore, q_from, q_to, closes_on in legs:
        start = time.perf_counter()
        approached = approached_target(scene, q_to, closes_on) if closes_on else None
        path, reason = _path(scene, q_from, q_to, ignore, name in STRAIGHT_LEGS, approached)
        seconds["optimisation"] += time.perf_counter() - start
        if path is None:
            return Plan(
                ok=False,
                reason=f"{name}: {reason}",
                target=target,
                seconds=seconds,
                ik_solves=ik_solves,
            )
        start = time.perf_counter()
        timed = time_path(path, limits)
        seconds["timing"] += time.perf_counter() - start
        if not timed.ok:
            return Plan(ok=False, reason=f"{name}: {timed.reason}", target=target, seconds=seconds,
                        ik_solves=ik_solves)  # fmt: skip
        motions.append(Motion(name, ignore, timed))
    return Plan(
        ok=True,
        reason="ok",
        target=target,
        motions=tuple(motions),
        seconds=seconds,
        ik_solves=ik_solves,
        goal=legs[-1].q_to,
    )


def _path(scene, q_from, q_to, ignore, straight: bool, target: Target | None = None):
    """A straight line when asked for and clear (of the `target` by its bound), else an
    optimised path from the guesses in turn (`_guesses`); (None, why) if none."""
    if straight:
        line = BsplineTrajectory(BsplineBasis(4, CONTROL_POINTS), straight_guess(q_from, q_to))
        if path_dips(scene, line, ignore, StartContact(), COLLISION_SAMPLES, target).max() <= 0:
            return line, "ok"
    reasons = []
    for name, guess in _guesses(scene, q_from, q_to):
        path, reason = _verified_path(scene, q_from, q_to, guess, ignore, target)
        if path is not None:
            return path, reason
        reasons.append(f"{name}: {reason}")
    return None, "; ".join(reasons)


def _verified_path(scene, q_from, q_to, guess, ignore, target: Target | None):
    """An optimised path from `guess` that comes no more than DIP_ALLOWANCE inside its
    samples' bounds between them too, its samples doubled while it does (up to MAX_SAMPLES);
    (None, why) if none."""
    samples, contact = COLLISION_SAMPLES, start_contact(scene, q_from, ignore)
    while True:
        result = optimize_path(scene, q_from, q_to, guess, ignore, samples, target)
        if not result.ok:
            return None, result.reason
        dips = path_dips(scene, result.path, ignore, contact, VERIFY_PER_SAMPLE * samples,
                         target)  # fmt: skip
        if dips.max() <= DIP_ALLOWANCE:
            return result.path, result.reason
        if samples * 2 > MAX_SAMPLES:
            worst = 100 * dips.max()
            return None, f"dips {worst:.1f} cm inside its bounds between {samples} samples"
        samples *= 2
        guess = np.hstack(result.path.control_points())


def _guesses(scene, q_from, q_to):
    """(name, control points) to start the optimiser from: the straight line and the arm stowed
    while the base drives (round the table if its straight line crosses it). The stowed way
    goes first when the base's line crosses the table: from a line through the table SNOPT
    takes seconds, up to half a minute, to give up."""
    base = [scene.index(joint) for joint in BASE_JOINTS[:2]]
    route = route_around(q_from[base], q_to[base], scene.scene.table)
    line = ("straight", straight_guess(q_from, q_to))
    stowed = ("round", route_guess(scene, q_from, q_to, route))
    return [line, stowed] if len(route) == 2 else [stowed, line]


def path_clearances(
    scene: PlanningScene, path, ignore: tuple[str, ...], samples: int
) -> np.ndarray:
    """The clearance (m) at `samples` evenly spaced times along a path or trajectory with
    `value(t)` and `start_time()`, `end_time()`."""
    times = np.linspace(path.start_time(), path.end_time(), samples)
    return np.array([scene.clearance_at(path.value(t).ravel(), ignore) for t in times])


def path_dips(
    scene: PlanningScene,
    path,
    ignore: tuple[str, ...],
    contact: StartContact,
    samples: int,
    target: Target | None = None,
) -> np.ndarray:
    """How far (m) a path (`value(t)`, `start_time()`, `end_time()`) from a start touching
    `contact` comes inside its bounds (StartContact.bound, by obstacle; the `target`'s own,
    though it is one of `ignore`) at `samples` evenly spaced times; negative where it keeps
    clear of them all."""
    name = "" if target is None else target.name
    seen = tuple(other for other in ignore if other != name)
    times = np.linspace(path.start_time(), path.end_time(), samples)
    spots = np.linspace(0.0, 1.0, samples)
    dips = []
    for t, spot in zip(times, spots, strict=True):
        clearances = scene.clearances_at(path.value(t).ravel(), seen)
        to_target = clearances.pop(name, math.inf)
        dip = contact.dip(clearances, spot)
        dips.append(dip if target is None else max(dip, target.bound - to_target))
    return np.array(dips)


def timed_clearance(scene: PlanningScene, motion: Motion, step: float = CHECK_STEP) -> float:
    """The least clearance (m) of a timed motion checked every `step` s (docs/design.md §6: the
    optimiser's samples alone let the path dip between them)."""
    times, positions = motion.timed.sample(step)
    return min(scene.clearance_at(q, motion.ignore) for q in positions)
