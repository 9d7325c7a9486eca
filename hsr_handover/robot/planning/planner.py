"""Plan from what the robot perceives. A grasp: its configurations by
inverse kinematics (base placed by the arm's effectivity map), the move to the pre-grasp by
trajectory optimisation, the approach along a straight line in joint space when it is clear
(optimised otherwise). A handover: the pose in the mutual area, the carry there optimised.
Each path is timed by toppra within the joints' limits.

Every stage's wall time is kept (`Stopwatch`), so the planning benchmark reports where the
time goes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import (
    ARM_JOINTS,
    GRIPPER_JOINT,
    GRIPPER_MIMIC_JOINT,
    PALM_FRAME,
)
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.planning.base_placement import with_arm
from hsr_handover.robot.planning.grasp_configurations import grasp_configurations
from hsr_handover.robot.planning.handover_pose import (
    plan_handover_pose,
    unseeded_handover_pose,
)
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, palm_goal, solve_palm_ik
from hsr_handover.robot.planning.paths import RETRY, search_path
from hsr_handover.robot.planning.plan import Motion, Plan
from hsr_handover.robot.planning.planning_scene import NEAR, PERSON, PlanningScene
from hsr_handover.robot.planning.stopwatch import Stopwatch
from hsr_handover.robot.planning.stowing import stowed, stowed_posture
from hsr_handover.robot.planning.timing import JointLimits, time_path
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    COLLISION_SAMPLES,
    approached_target,
    start_contact,
)
from hsr_handover.robot.planning.upright import (
    keeps_upright,
)
from hsr_handover.robot.planning.verification import verified

STAGES = ("ik", "optimisation", "timing", RETRY)
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
CARRY = "carry"  # a handover plan's drive to the handover pose, holding the object
SHORTENED_LEGS = (CARRY,)  # long drives with the arm: the shortened stowed way first
AT_POSTURE = 0.01  # rad or m: every joint this near a posture is at it (no move to plan)
AS_HELD = "the arm as it holds the object"  # the handover pose again, on the arm's own turn
BACK_OFF_M = 0.20
"""m the palm first backs straight out, against its approach, when a retreat starts within the
collision bound of the person: after letting go, the hand that took the object is at the
fingers, and no path from inside the person's perceived capsules is feasible."""


class Leg(NamedTuple):
    """A path to plan: its `name`, the obstacles it may touch (`ignore`), its ends, the one
    of them it closes the hand on (`target`, kept as far as the end keeps it: `Target`), and
    first guesses to try before the planner's own (`first`: (name, control points))."""

    name: str
    ignore: tuple[str, ...]
    q_from: np.ndarray
    q_to: np.ndarray
    target: str = ""
    first: tuple[tuple[str, np.ndarray], ...] = ()


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
    watch = Stopwatch(STAGES)
    with watch.stage("ik"):
        found = grasp_configurations(scene, arm_map, label, q_now)
    if not found.ok:
        return Plan(ok=False, reason=found.reason, target=label, seconds=watch.snapshot(),
                    ik_solves=found.ik_solves)  # fmt: skip
    closed = _fingers_as(scene, found.q_grasp, found.q_lifted)  # it closes between the legs
    # The robot opens the gripper at once as it sets off (to 10 cm, within 1 cm of the
    # pre-grasp's width and GRIP_CLEARANCE), so the move is planned open from its start: a move
    # planned opening gradually had the open fingers cut 2 cm into the table (the standing
    # layout's trial 7, seed 1).
    opened = _fingers_as(scene, q_now, found.q_pregrasp)
    legs = (Leg("move", (), opened, found.q_pregrasp),
            Leg("approach", (label,), found.q_pregrasp, found.q_grasp, target=label),
            Leg("lift", (label,), closed, found.q_lifted))  # fmt: skip
    plan = _plan_legs(scene, label, legs, limits, watch, found.ik_solves)
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


def person_clearance(
    scene: PlanningScene,
    path: Sequence[np.ndarray],
    held: Held | None = None,
    within: float = NEAR,
) -> float:
    """The least signed distance (m) between the HSR, with the object `held` in the hand, and
    the person's perceived capsules over the configurations `path` (plant positions); inf when
    none comes within `within` of them, or the path is empty."""
    if not len(path):
        return math.inf
    with holding(scene, held, path[0]):
        return min(scene.clearances_at(q, within=within).get(PERSON, math.inf) for q in path)


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
    watch = Stopwatch(STAGES)
    if held is None:
        ignore = (released,) if released else ()
        q_stowed = stowed(scene, q_now, ignore)
        legs = (Leg(RETREAT, ignore, q_now, q_stowed),)
        q_back = _backed_off(scene, q_now, (PERSON, *ignore))
        if q_back is not None:
            legs = (
                Leg(BACK_OFF, (PERSON, *ignore), q_now, q_back),
                Leg(RETREAT, ignore, q_back, q_stowed),
            )
        return _plan_legs(scene, RETREAT, legs, limits, watch)
    with holding(scene, held, q_now):
        q_stowed = stowed(scene, q_now, (held.label,), stowed_posture(scene))
        leg = Leg(RETREAT, (held.label,), q_now, q_stowed)
        return _plan_legs(scene, RETREAT, (leg,), limits, watch)


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
    stood (ignored there, as on the way up, with whatever is remembered of it there:
    `PlanningScene.seen_where_it_stood`). Never raises: `reason` says why there is none."""
    watch = Stopwatch(STAGES)
    stood = () if held.shape is None else scene.seen_where_it_stood(held.shape)
    ignore = (held.label, *stood)
    back: tuple[Motion, ...] = ()
    retried: tuple[str, ...] = ()
    if np.abs(q_now - q_lifted).max() > AT_POSTURE:
        with holding(scene, held, q_now):
            plan = _way_back(scene, q_now, q_lifted, came, ignore, limits, watch)
        if not plan.ok:
            return plan
        back, retried = plan.motions, plan.retried
    leg = Leg(LOWER, ignore, q_lifted, held.q_grasp)
    plan = _plan_legs(scene, PUT_BACK, (leg,), limits, watch)
    if not plan.ok:
        return dataclasses.replace(plan, retried=retried + plan.retried)
    return dataclasses.replace(plan, motions=back + plan.motions, retried=retried + plan.retried)


def _way_back(scene, q_now, q_to, came, ignore, limits, watch: Stopwatch) -> Plan:
    """From `q_now` to `q_to` the way it `came` (reversed) when that keeps clear as a path
    checked between its samples must, else as any leg, the optimiser started first from the
    way it came (the carry's own path, feasible when it was planned). From part way along a
    carry the line back to its start and the stowed round both failed (the moved layout's
    trial 12 of seed 2); the way it came, taken as it is, passed a cup 1.2 cm off: inside the
    optimiser's bound at its samples, clear as a verified path must be."""
    first: tuple[tuple[str, np.ndarray], ...] = ()
    if len(came) >= 2:
        with watch.stage("optimisation"):
            points = np.array(came[::-1], dtype=float).T
            points[:, 0], points[:, -1] = q_now, q_to
            first = (("came", points),)
            path = BsplineTrajectory(BsplineBasis(4, points.shape[1]), points)
            clear = verified(scene, path, ignore, start_contact(scene, q_now, ignore))
        if clear:
            with watch.stage("timing"):
                timed = time_path(path, limits)
            if timed.ok:
                motion = Motion(name=PUT_BACK, trajectory=timed, ignore=ignore)
                return Plan(ok=True, reason="ok", target=PUT_BACK, motions=(motion,),
                            seconds=watch.snapshot(), goal=q_to)  # fmt: skip
    leg = Leg(PUT_BACK, ignore, q_now, q_to, first=first)
    return _plan_legs(scene, PUT_BACK, (leg,), limits, watch)


def plan_back_off(
    scene: PlanningScene, q_now: np.ndarray, limits: JointLimits, released: str
) -> Plan:
    """The palm BACK_OFF_M straight back from the object `released` (just let go of, still
    between the fingers), the rest of the robot where it is: where the next grasp is planned
    from after an object is put back, rather than from the arm stowed. No motion when the hand
    is clear of it already; not ok when there is no such configuration clear of the rest."""
    watch = Stopwatch(STAGES)
    distance = scene.clearances_at(q_now).get(released, math.inf)
    if distance >= COLLISION_BOUND:
        return Plan(ok=True, reason="ok", target=BACK_OFF, seconds=watch.snapshot(), goal=q_now)
    with watch.stage("ik"):
        q_back = _backed_off(scene, q_now, (released,))
    if q_back is None:
        return Plan(ok=False, reason="no way back from the object let go of", target=BACK_OFF,
                    seconds=watch.snapshot())  # fmt: skip
    leg = Leg(BACK_OFF, (released,), q_now, q_back)
    return _plan_legs(scene, BACK_OFF, (leg,), limits, watch)


def plan_posture(
    scene: PlanningScene, q_now: np.ndarray, q_goal: np.ndarray, limits: JointLimits
) -> Plan:
    """Plan from `q_now` to the posture `q_goal` (plant positions), clear of everything the
    robot perceives. Never raises: `reason` says why there is none."""
    leg = Leg(POSTURE, (), q_now, q_goal)
    return _plan_legs(scene, POSTURE, (leg,), limits, Stopwatch(STAGES))


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
    watch = Stopwatch(STAGES)
    with watch.stage("ik"):
        if arm_map is None:
            pose = unseeded_handover_pose(scene, person, q_now, ignore)
        else:
            pose = plan_handover_pose(scene, arm_map, person, q_now, ignore)
    if not pose.ok:
        return Plan(ok=False, reason=pose.reason, target=HANDOVER, seconds=watch.snapshot())
    retried = (f"handover pose: {pose.found_by}",) if pose.found_by else ()
    plan = None
    for q_goal, found_by in _carry_goals(scene, pose.q, q_now, ignore, watch):
        leg = Leg(CARRY, ignore, q_now, q_goal)
        tried = _plan_legs(scene, HANDOVER, (leg,), limits, watch, ik_solves=1 + bool(found_by))
        plan = tried if plan is None or tried.ok else plan  # failing all, the first reason
        if tried.ok:
            pose = dataclasses.replace(pose, q=q_goal)
            retried += (f"handover pose: {found_by}",) if found_by else ()
            break
    plan = dataclasses.replace(plan, retried=retried + plan.retried)
    return dataclasses.replace(plan, pose=pose) if plan.ok else plan


def _carry_goals(scene: PlanningScene, q_pose, q_now, ignore, watch: Stopwatch):
    """(configuration, the retry that found it or "") to carry the object to, in turn: the
    handover pose `q_pose` and the same hand pose on the arm's own turn (`_as_held`), the latter
    first when the straight way to `q_pose` would tilt the object held past its bound (a sign
    that the two are on different turns: SNOPT then spent seconds finding no upright way)."""
    line = np.linspace(q_now, q_pose, COLLISION_SAMPLES)
    level = keeps_upright(scene, line)
    if level:
        yield q_pose, ""
    with watch.stage(RETRY):
        q_held = _as_held(scene, q_pose, q_now, ignore)
    if q_held is not None:
        yield q_held, AS_HELD
    if not level:
        yield q_pose, ""


def _as_held(scene: PlanningScene, q_pose: np.ndarray, q_now: np.ndarray, ignore):
    """The hand as at `q_pose`, the base there too, reached from the arm as it holds the object
    at `q_now` (IK seeded by it), when that is another configuration; else None. The arm's map
    seeds the pose on one turn of the arm's and the wrist's rolls, and an object grasped on
    the other turn has no way there that keeps it up: rolled over at the wrist, as a grasp from
    the side at the table's far edge can be, the way to the map's turn swings it 130 degrees."""
    seed = with_arm(scene, q_pose, q_now[[scene.index(joint) for joint in ARM_JOINTS]])
    found = solve_palm_ik(scene, palm_goal(scene, q_pose), seed, ignore=ignore, base_fixed=True)
    if not found.ok or np.abs(found.q - q_pose).max() <= AT_POSTURE:
        return None
    return found.q


def _plan_legs(
    scene: PlanningScene,
    target: str,
    legs: tuple[Leg, ...],
    limits: JointLimits,
    watch: Stopwatch,
    ik_solves: int = 0,
) -> Plan:
    """Path and timing for each leg in turn, timed on `watch`."""
    motions, retried = [], []
    for name, ignore, q_from, q_to, closes_on, first in legs:
        with watch.stage("optimisation"):
            approached = approached_target(scene, q_to, closes_on) if closes_on else None
        straight = name in STRAIGHT_LEGS
        found = search_path(scene, q_from, q_to, ignore, straight, watch, approached, first,
                            stowed_first=name in SHORTENED_LEGS)  # fmt: skip
        reason = found.reason
        if found.ok:
            with watch.stage("timing"):
                timed = time_path(found.path, limits)
            reason = timed.reason
        if not found.ok or not timed.ok:
            return Plan(ok=False, reason=f"{name}: {reason}", target=target,
                        seconds=watch.snapshot(), ik_solves=ik_solves,
                        retried=tuple(retried))  # fmt: skip
        if found.retried:
            retried.append(f"{name}: {found.found_by}")
        motions.append(Motion(name=name, trajectory=timed, ignore=ignore))
    return Plan(ok=True, reason="ok", target=target, motions=tuple(motions),
                seconds=watch.snapshot(), ik_solves=ik_solves, goal=legs[-1].q_to,
                retried=tuple(retried))  # fmt: skip
