"""A collision-free path between two configurations: Drake's
KinematicTrajectoryOptimization over every position of the HSR (base included), a cubic
B-spline (C2, as toppra needs), shortest in duration and length, within the joints' position
and velocity limits, the torso and the right finger coupled on every control point, the head
held, and at least COLLISION_BOUND from every obstacle not ignored at COLLISION_SAMPLES points.

The bound is larger than the planner's true margin: between samples a short path may dip by up
to about 11 mm (docs/design.md §6); a long one (a carry round the table, the object held far
out from the joints) by much more, so the planner checks each path between its samples (planner.py).

A start that the perceived scene already puts nearer than the bound to some obstacles
(perception errs toward bulk: a table's unseen end runs on, a person's unseen body is a column
to the floor; a lift starts with the object on the table) would make every path infeasible;
over the first ESCAPE_SHARE of such a path each of *those* parts of the HSR need only keep from
each of *those* obstacles a bound that rises from the start's distance, less ESCAPE_SLACK, to
COLLISION_BOUND (`StartContact`): the path must get out, not merely stay no deeper (held to the
start's depth all the way, fingers that began 5 cm inside the perceived table's block slid
along it at that depth, 3.6 cm into the true table). Every other pair keeps the bound all the
way: a start in contact never licenses touching another obstacle (a carry that starts 7 cm
inside the held box's second detection, under one allowance for every obstacle, could pass the
box 7 cm through a neighbouring cup) or the same obstacle with another part (fingers started
inside the perceived table's block license neither the palm nor the base to come that near
it).

An object held keeps its top up at the samples too (`upright.path_bound`).

A grasp's approach may touch the object it closes on, but only as its goal does (`Target`): no
nearer to it anywhere on the way than the pads straddling it at the end.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np
from pydrake.geometry import GeometryId
from pydrake.multibody.inverse_kinematics import (
    AngleBetweenVectorsConstraint,
    MinimumDistanceLowerBoundConstraint,
)
from pydrake.planning import KinematicTrajectoryOptimization
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import BASE_JOINTS, GRIPPER_JOINT, GRIPPER_MIMIC_JOINT, HEAD_JOINTS
from hsr_handover.robot.planning import solving
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.solving import solve, solved
from hsr_handover.robot.planning.upright import path_bound

CONTROL_POINTS = 10
ROUTE_CONTROL_POINTS = 16  # for a way round the table
STOWED = {"arm_lift_joint": 0.0, "torso_lift_joint": 0.0, "arm_flex_joint": 0.0,
          "arm_roll_joint": 0.0, "wrist_flex_joint": -1.57, "wrist_roll_joint": 0.0}  # fmt: skip
"""The arm folded over the base, the hand tucked (the ready posture): how the base drives."""
COLLISION_SAMPLES = 30
COLLISION_BOUND = 0.013  # m at the samples: about 1 cm everywhere between them
INFLUENCE = 0.05  # m beyond the bound where distances start to count
ESCAPE_SHARE = 0.3  # of the path over which a start within the bound must get out to it
ESCAPE_SLACK = 0.005  # m nearer than the start it may come meanwhile
MAX_DURATION = 30.0  # s of the path's nominal time (toppra retimes it)
FREE_POSITION = 20.0  # m: stands in for the base's unbounded x and y


@dataclasses.dataclass(frozen=True, kw_only=True)
class PathResult(Outcome):
    """`ok` with the `path` (a B-spline over plant positions, on its own time scale), or not
    with the `reason` and the solver's `last` control points (nq, n; None if it gave none),
    from which a solve stopped short of a verdict may go on."""

    path: BsplineTrajectory | None
    last: np.ndarray | None = None


Pair = tuple[GeometryId, str]  # (one of PlanningScene.moving_parts, an obstacle's name)


@dataclasses.dataclass(frozen=True)
class StartContact:
    """The (part, obstacle) pairs a path's start lies nearer than COLLISION_BOUND (none for a
    clear start), each with its clearance (m) there."""

    pairs: Mapping[Pair, float] = dataclasses.field(default_factory=dict)

    @property
    def clearance(self) -> float:
        """The least clearance (m) over the pairs touched (COLLISION_BOUND for none)."""
        return min(self.pairs.values(), default=COLLISION_BOUND)

    @property
    def names(self) -> tuple[str, ...]:
        """The obstacles touched, sorted."""
        return tuple(sorted({name for _, name in self.pairs}))

    def bound(self, pair: Pair, spot: float) -> float:
        """The least distance (m) to keep between the (part, obstacle) `pair` at `spot` (0 to
        1) along the path: COLLISION_BOUND, or for a pair the start touches, over the first
        ESCAPE_SHARE, a bound rising linearly from the pair's own clearance at the start less
        ESCAPE_SLACK to COLLISION_BOUND."""
        if pair not in self.pairs or spot >= ESCAPE_SHARE:
            return COLLISION_BOUND
        start = self.pairs[pair] - ESCAPE_SLACK
        return start + (COLLISION_BOUND - start) * max(spot, 0.0) / ESCAPE_SHARE

    def dip(self, clearances: dict[Pair, float], spot: float) -> float:
        """How far (m) the clearances by (part, obstacle) at `spot` come inside their bounds
        (negative when all keep clear of them)."""
        dips = (self.bound(pair, spot) - d for pair, d in clearances.items())
        return max(dips, default=-math.inf)


@dataclasses.dataclass(frozen=True)
class Target:
    """The obstacle `name` that a path's goal closes the hand on (left out of the obstacles to
    keep COLLISION_BOUND from) and the least distance (m) kept from it all the way, `bound`:
    the goal's own, where the pads straddle it, less ESCAPE_SLACK, and no more than
    COLLISION_BOUND. Left out altogether, an approach that the optimiser bent round a
    neighbour can sweep a pad 3 cm into the box it is going to grasp and knock it over."""

    name: str
    bound: float


def approached_target(scene: PlanningScene, q_goal: np.ndarray, name: str) -> Target:
    """The `Target` for a path to `q_goal` that closes the hand on the obstacle `name`."""
    at_goal = scene.clearances_at(q_goal).get(name, math.inf)
    return Target(name, min(COLLISION_BOUND, at_goal - ESCAPE_SLACK))


def start_contact(
    scene: PlanningScene, q_start: np.ndarray, ignore: tuple[str, ...] = ()
) -> StartContact:
    """The (part, obstacle) pairs (but obstacles in `ignore`) that the HSR at `q_start` has
    within COLLISION_BOUND of each other."""
    clearances = scene.part_clearances_at(q_start, ignore, COLLISION_BOUND)
    return StartContact({pair: d for pair, d in clearances.items() if d < COLLISION_BOUND})


def straight_guess(q_start: np.ndarray, q_goal: np.ndarray, count: int = CONTROL_POINTS):
    """Control points (nq, count) on the straight line in joint space."""
    return np.linspace(q_start, q_goal, count).T


def route_guess(
    scene: PlanningScene,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    route: np.ndarray,
    count: int = ROUTE_CONTROL_POINTS,
) -> np.ndarray:
    """Control points (nq, count) that fold the arm, drive the base through the `route`'s
    points (k, 2) and unfold the arm at the goal, evenly spaced along that way in joint space."""
    stowed_start, stowed_goal = q_start.copy(), q_goal.copy()
    for q in (stowed_start, stowed_goal):
        for joint, value in STOWED.items():
            q[scene.index(joint)] = value
    return through([q_start, *driven(scene, stowed_start, stowed_goal, route), q_goal], count)


def through(keys, count: int = CONTROL_POINTS) -> np.ndarray:
    """Control points (nq, count) evenly spaced in joint space along the polyline `keys`."""
    keys = np.array(keys, dtype=float)
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(keys, axis=0), axis=1))])
    spots = np.linspace(0.0, along[-1], count)
    return np.array([np.interp(spots, along, keys[:, i]) for i in range(keys.shape[1])])


def driven(
    scene: PlanningScene, stowed_start: np.ndarray, stowed_goal: np.ndarray, route: np.ndarray
) -> list[np.ndarray]:
    """The configurations at the base `route`'s points (k, 2; its ends those of the two
    configurations), from `stowed_start` to `stowed_goal`, every other joint changing evenly
    along the route's points."""
    x, y = (scene.index(joint) for joint in BASE_JOINTS[:2])
    keys = [stowed_start]
    for k, point in enumerate(route[1:-1], start=1):
        q = stowed_start + (stowed_goal - stowed_start) * k / (len(route) - 1)
        q[[x, y]] = point
        keys.append(q)
    return [*keys, stowed_goal]


def optimize_path(
    scene: PlanningScene,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    guess: np.ndarray | None = None,
    ignore: tuple[str, ...] = (),
    samples: int = COLLISION_SAMPLES,
    target: Target | None = None,
) -> PathResult:
    """The path from `q_start` to `q_goal` (plant positions), starting from the control points
    `guess` (nq, any count; the straight line through CONTROL_POINTS when None), kept clear at
    `samples` evenly spaced points, and of the `target` (one of `ignore`) by its bound. Never
    raises for an infeasible problem: `ok` is False and `reason` says why. The head stays
    where it starts (gaze aims it, not plans), so a goal's head is taken as the start's: a
    goal kept from an earlier plan (the lift's end, put back to) has the head of its time,
    which no path holding the head could reach."""
    head = [scene.index(joint) for joint in HEAD_JOINTS]
    q_goal = q_goal.copy()
    q_goal[head] = q_start[head]
    guess = straight_guess(q_start, q_goal) if guess is None else guess.copy()
    guess[head] = q_start[head, None]
    contact = start_contact(scene, q_start, ignore)
    # A context that sees the target alone, made before the target is ignored with the rest.
    alone = None if target is None else scene.ignoring_context(scene.obstacles_but((target.name,)))
    with scene.ignoring(ignore):
        trajopt = _build(scene, q_start, q_goal, guess.shape[1], head)
        constraints = _keep_clear(trajopt, scene, contact, samples)
        if alone is not None:
            root, context = alone
            constraints += [root, context, _keep_clear_of(trajopt, scene, target, context, samples)]
        if scene.upright is not None:
            bound = path_bound(scene, q_start, q_goal)
            constraints.append(_keep_up(trajopt, scene, bound, samples))
        trajopt.SetInitialGuess(BsplineTrajectory(trajopt.basis(), guess * 1.0))
        result = solve(trajopt.prog(), effort=solving.PATH_EFFORT)
        usable = solved(trajopt.prog(), result)
        del constraints  # the solve is done; the constraints held the plant contexts
    if not usable:
        reason = f"no path ({result.get_solver_id().name()} {result.get_solution_result().name})"
        last = np.hstack(trajopt.ReconstructTrajectory(result).control_points())
        return PathResult(ok=False, reason=reason, path=None, last=last)
    return PathResult(ok=True, reason="ok", path=trajopt.ReconstructTrajectory(result))


def _build(
    scene: PlanningScene,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    control_points: int,
    head: list[int],
):
    plant = scene.plant
    nq = plant.num_positions()
    trajopt = KinematicTrajectoryOptimization(nq, control_points)
    prog = trajopt.get_mutable_prog()
    trajopt.AddDurationCost(1.0)
    trajopt.AddPathLengthCost(1.0)
    lower = np.maximum(plant.GetPositionLowerLimits(), -FREE_POSITION)
    upper = np.minimum(plant.GetPositionUpperLimits(), FREE_POSITION)
    trajopt.AddPositionBounds(lower, upper)
    trajopt.AddVelocityBounds(-plant.GetVelocityUpperLimits(), plant.GetVelocityUpperLimits())
    trajopt.AddDurationConstraint(0.1, MAX_DURATION)
    trajopt.AddPathPositionConstraint(q_start, q_start, 0)
    trajopt.AddPathPositionConstraint(q_goal, q_goal, 1)
    A, b = scene.couplings()
    points = trajopt.control_points()
    # The fingers go where the gripper is commanded, not where a path would have them: left
    # free, the optimiser half shuts them to pass a table's edge that the open fingers then cut
    # 2 cm into. They stay between start and goal.
    fingers = [scene.index(joint) for joint in (GRIPPER_JOINT, GRIPPER_MIMIC_JOINT)]
    low = np.minimum(q_start[fingers], q_goal[fingers])
    high = np.maximum(q_start[fingers], q_goal[fingers])
    for j in range(points.shape[1]):
        prog.AddLinearEqualityConstraint(A, b, points[:, j])
        prog.AddBoundingBoxConstraint(q_start[head], q_start[head], points[head, j])
        prog.AddBoundingBoxConstraint(low, high, points[fingers, j])
    return trajopt


def _keep_clear_of(trajopt, scene: PlanningScene, target: Target, context, samples: int):
    """Keep the path at `samples` evenly spaced points `target.bound` from the target, which
    alone the plant `context` sees; the constraint, to keep alive through the solve."""
    bound = MinimumDistanceLowerBoundConstraint(scene.plant, target.bound, context, None, INFLUENCE)
    for spot in np.linspace(0.0, 1.0, samples):
        trajopt.AddPathPositionConstraint(bound, spot)
    return bound


def _keep_up(trajopt, scene: PlanningScene, bound: float, samples: int):
    """Keep the held object within `bound` (rad) of upright at `samples` evenly spaced points;
    the constraint, to keep alive through the solve."""
    plant = scene.plant
    hand = scene.hand().body_frame()
    up = AngleBetweenVectorsConstraint(plant, plant.world_frame(), [0.0, 0.0, 1.0], hand,
                                       scene.upright.up_in_hand, 0.0, bound,
                                       scene.plant_context)  # fmt: skip
    for spot in np.linspace(0.0, 1.0, samples):
        trajopt.AddPathPositionConstraint(up, spot)
    return up


def _keep_clear(trajopt, scene: PlanningScene, contact: StartContact, samples: int) -> list:
    """Keep the path at `samples` evenly spaced points clear of the scene by COLLISION_BOUND,
    and each (part, obstacle) pair its start touches (`contact`) by its StartContact bound at
    each spot (each constraint in a context that sees only its pairs); the objects to keep alive
    through the solve."""
    plant, spots = scene.plant, np.linspace(0.0, 1.0, samples)

    def lower_bound(bound: float, plant_context):
        return MinimumDistanceLowerBoundConstraint(plant, bound, plant_context, None, INFLUENCE)

    everything = lower_bound(COLLISION_BOUND, scene.plant_context)
    alive = [everything]
    escaping = [spot for spot in spots if spot < ESCAPE_SHARE] if contact.pairs else []
    if escaping:
        rest_root, rest = scene.pairs_context(contact.pairs, only=False)
        rest_bound = lower_bound(COLLISION_BOUND, rest)
        alive += [rest_root, rest, rest_bound]
        alone = {pair: scene.pairs_context((pair,), only=True) for pair in contact.pairs}
        alive += [context for contexts in alone.values() for context in contexts]
        for spot in escaping:
            trajopt.AddPathPositionConstraint(rest_bound, spot)
            for pair, (_, context) in alone.items():
                constraint = lower_bound(contact.bound(pair, spot), context)
                trajopt.AddPathPositionConstraint(constraint, spot)
                alive.append(constraint)
    for spot in spots[len(escaping) :]:
        trajopt.AddPathPositionConstraint(everything, spot)
    return alive
