"""A collision-free path between two configurations (issue 9, part 7): Drake's
KinematicTrajectoryOptimization over every position of the HSR (base included), a cubic
B-spline (C2, as toppra needs), shortest in duration and length, within the joints' position
and velocity limits, the torso and the right finger coupled on every control point, the head
held, and at least COLLISION_BOUND from every obstacle not ignored at COLLISION_SAMPLES points.

The bound is larger than the planner's true margin: between samples a short path may dip by up
to about 11 mm (DESIGN §6); a long one (a carry round the table, the object held far out from
the joints) by much more, so the planner checks each path between its samples (planner.py).

A start that the perceived scene already puts nearer than the bound (perception errs toward
bulk: a table's unseen end runs on, a person's unseen body is a column to the floor) would make
every path infeasible; over the first ESCAPE_SHARE of such a path the samples need only stay as
far as the start was, less ESCAPE_SLACK.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from pydrake.multibody.inverse_kinematics import MinimumDistanceLowerBoundConstraint
from pydrake.planning import KinematicTrajectoryOptimization
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import BASE_JOINTS, HEAD_JOINTS
from hsr_handover.planning.planning_scene import PlanningScene
from hsr_handover.planning.solving import solve, solved

CONTROL_POINTS = 10
ROUTE_CONTROL_POINTS = 16  # for a way round the table
STOWED = {"arm_lift_joint": 0.0, "torso_lift_joint": 0.0, "arm_flex_joint": 0.0,
          "arm_roll_joint": 0.0, "wrist_flex_joint": -1.57, "wrist_roll_joint": 0.0}  # fmt: skip
"""The arm folded over the base, the hand tucked (the ready posture): how the base drives."""
COLLISION_SAMPLES = 30
COLLISION_BOUND = 0.013  # m at the samples: about 1 cm everywhere between them
INFLUENCE = 0.05  # m beyond the bound where distances start to count
ESCAPE_SHARE = 0.3  # of the path over which a start within the bound may stay that near
ESCAPE_SLACK = 0.005  # m nearer than the start it may come meanwhile
MAX_DURATION = 30.0  # s of the path's nominal time (toppra retimes it)
FREE_POSITION = 20.0  # m: stands in for the base's unbounded x and y


@dataclasses.dataclass(frozen=True)
class PathResult:
    """`ok` with the `path` (a B-spline over plant positions, on its own time scale), or not
    with the `reason`; `seconds` spent."""

    ok: bool
    reason: str
    path: BsplineTrajectory | None
    seconds: float


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
    x, y, yaw = (scene.index(joint) for joint in BASE_JOINTS)
    keys = [q_start, stowed_start]
    for k, point in enumerate(route[1:-1], start=1):
        q = stowed_start + (stowed_goal - stowed_start) * k / (len(route) - 1)
        q[x], q[y] = point
        keys.append(q)
    keys += [stowed_goal, q_goal]
    keys = np.array(keys)
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(keys, axis=0), axis=1))])
    spots = np.linspace(0.0, along[-1], count)
    return np.array([np.interp(spots, along, keys[:, i]) for i in range(keys.shape[1])])


def optimize_path(
    scene: PlanningScene,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    guess: np.ndarray | None = None,
    ignore: tuple[str, ...] = (),
    samples: int = COLLISION_SAMPLES,
) -> PathResult:
    """The path from `q_start` to `q_goal` (plant positions), starting from the control points
    `guess` (nq, any count; the straight line through CONTROL_POINTS when None), kept clear at
    `samples` evenly spaced points. Never raises for an infeasible problem: `ok` is False and
    `reason` says why."""
    start = time.perf_counter()
    guess = straight_guess(q_start, q_goal) if guess is None else guess
    bounds = sample_bounds(scene.clearance_at(q_start, ignore), samples)
    with scene.ignoring(ignore):
        trajopt, constraints = _build(scene, q_start, q_goal, guess.shape[1], bounds)
        trajopt.SetInitialGuess(BsplineTrajectory(trajopt.basis(), guess * 1.0))
        result = solve(trajopt.prog())
        usable = solved(trajopt.prog(), result)
        del constraints  # the solve is done; the constraints held the plant context
    seconds = time.perf_counter() - start
    if not usable:
        reason = f"no path ({result.get_solver_id().name()} {result.get_solution_result().name})"
        return PathResult(False, reason, None, seconds)
    return PathResult(True, "ok", trajopt.ReconstructTrajectory(result), seconds)


def sample_bounds(start_clearance: float, samples: int = COLLISION_SAMPLES) -> np.ndarray:
    """The least distance (m) to keep at each of `samples` points evenly spaced over the path:
    COLLISION_BOUND, or for a start already nearer, the start's own clearance less
    ESCAPE_SLACK over the first ESCAPE_SHARE."""
    spots = np.linspace(0.0, 1.0, samples)
    bounds = np.full(samples, COLLISION_BOUND)
    if start_clearance < COLLISION_BOUND:
        bounds[spots <= ESCAPE_SHARE] = start_clearance - ESCAPE_SLACK
    return bounds


def _build(
    scene: PlanningScene,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    control_points: int,
    bounds: np.ndarray,
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
    held = [scene.index(joint) for joint in HEAD_JOINTS]
    for j in range(points.shape[1]):
        prog.AddLinearEqualityConstraint(A, b, points[:, j])
        prog.AddBoundingBoxConstraint(q_start[held], q_start[held], points[held, j])
    constraints = {
        bound: MinimumDistanceLowerBoundConstraint(
            plant, bound, scene.plant_context, None, INFLUENCE
        )
        for bound in set(bounds.tolist())
    }
    for s, bound in zip(np.linspace(0, 1, len(bounds)), bounds, strict=True):
        trajopt.AddPathPositionConstraint(constraints[float(bound)], s)
    return trajopt, constraints
