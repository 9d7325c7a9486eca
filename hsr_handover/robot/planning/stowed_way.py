"""A carry's way without the optimiser: the arm stowed over the base (raised while it holds an
object, `stowing`), the base straight out from the table, round its corners and in
(`base_route.route_out`), and the arm out to the goal; checked densely, then shortened
(`shortcut`) until the arm folds and unfolds while the base drives and the base cuts what it
can, and smoothed. SNOPT spends 0.1-3 s on a carry's way (from a folded arm, a way round the
table takes it tens of iterations); this one takes a few thousand clearance queries, about
0.1 s. It is kept only once verified as an optimised path is (`verification.path_dips`,
`upright.path_keeps_upright`); else the optimiser's guesses follow.
"""

from __future__ import annotations

import numpy as np
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory
from scipy.interpolate import make_lsq_spline

from hsr_handover.hsr import ARM_JOINTS, BASE_JOINTS, HEAD_JOINTS, TORSO_JOINT, TORSO_PER_LIFT
from hsr_handover.robot.planning.base_route import route_out
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.shortcut import resampled, seconds, shorten
from hsr_handover.robot.planning.stowing import stowed, stowed_posture
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    StartContact,
    driven,
    start_contact,
)
from hsr_handover.robot.planning.upright import path_bound, tilt
from hsr_handover.robot.planning.verification import verified

WAY_POINTS = 30  # vertices of the polyline, and control points of the B-spline through them
ATTEMPTS = 400
"""Shortcuts tried. On the planning benchmark's 42 carries the timed carries (smoothed) came
out 1 % shorter than SNOPT's after 200, 2 % after 300 and 4 % after 400, in about 0.1 s."""
DRIVE_INS = (0.3, 0.15)
"""m the base stands back from the goal's to unstow and drive in, tried in turn. Unstowed at
the goal's base, the object swept down in front of a seated person hid them from the camera
as the carry ended, and the robot, presenting, gave up after 2 s without seeing them (the
handover reference's trials 28 and 46)."""
OVER = 0.1  # m the arm is raised over the goal to drive in
SMOOTH_POINTS = 16
"""Control points of the spline fitted to the shortened way (`_smoothed`). On the planning
benchmark's 42 carries, timed: the spline through the 30 vertices 2 % longer than SNOPT's
paths, this one 4 % shorter (12 points: one carry no longer clear)."""
FIT_SAMPLES = 300  # points of the shortened way the smoothed spline is fitted to
CHECK_STEP = 0.03  # m or rad: the most any joint moves between two checks of a stretch


def stowed_way(
    scene: PlanningScene, q_from: np.ndarray, q_to: np.ndarray, ignore: tuple[str, ...]
) -> tuple[BsplineTrajectory | None, str]:
    """The shortened stowed way from `q_from` to `q_to` (plant positions), touching nothing
    but `ignore`, the head held where it starts, and "ok"; or None and why not."""
    if not (np.isfinite(q_from).all() and np.isfinite(q_to).all()):
        return None, "the way's ends are not finite"
    head = [scene.index(joint) for joint in HEAD_JOINTS]
    q_to = q_to.copy()
    q_to[head] = q_from[head]  # as every path holds it (`trajectory.optimize_path`)
    speeds = _speeds(scene)
    check = _Check(scene, ignore, start_contact(scene, q_from, ignore), q_from, q_to)
    for keys in _ways(scene, q_from, q_to, ignore):
        points = resampled(keys, speeds, WAY_POINTS)
        if check(points, 0):
            break
    else:
        return None, "the stowed way is not clear"
    points = shorten(points, speeds, _groups(scene), check, ATTEMPTS)
    through = BsplineTrajectory(BsplineBasis(4, WAY_POINTS), points.T.copy())
    smoothed = (_smoothed(points, speeds),) if seconds(points, speeds) > 0 else ()
    for path in (*smoothed, through):
        if verified(scene, path, ignore, check.contact):
            return path, "ok"
    return None, "the shortened stowed way dips between its checks"


def _smoothed(points: np.ndarray, speeds: np.ndarray) -> BsplineTrajectory:
    """The B-spline of SMOOTH_POINTS control points nearest the polyline `points` (least
    squares at FIT_SAMPLES points evenly spaced in its time at full speed), through its ends.
    toppra slows for each of the polyline's corners that a spline through its vertices keeps."""
    dense = resampled(points, speeds, FIT_SAMPLES)
    steps = np.abs(np.diff(dense, axis=0) / speeds).max(axis=1)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    spots = along / max(along[-1], 1e-12)
    basis = BsplineBasis(4, SMOOTH_POINTS)
    weights = np.ones(FIT_SAMPLES)
    weights[[0, -1]] = 1e4  # the ends held; then set exactly
    spline = make_lsq_spline(spots, dense, np.array(basis.knots()), k=3, w=weights)
    control = spline.c.copy()
    control[[0, -1]] = points[[0, -1]]
    return BsplineTrajectory(basis, control.T.copy())


def _ways(scene, q_from, q_to, ignore):
    """The polylines (k, nq) to try, each stowing, driving the base's route (the stowed arm's
    joints and the base's heading changing evenly along it) and unstowing: first standing
    back from the goal's base by each of DRIVE_INS, the arm unstowed to the goal raised by
    OVER, driven in and lowered; then at the goal's base (backed up as `stowing.stowed` must).
    Unstowed at the handover pose's base, the arm sweeps the object down in front of the
    person, between them and the camera (`DRIVE_INS`)."""
    posture = stowed_posture(scene)
    stowed_from = stowed(scene, q_from, ignore, posture)
    x, y = (scene.index(joint) for joint in BASE_JOINTS[:2])
    over = _raised(scene, q_to, OVER)
    endings = []
    for back in DRIVE_INS:
        stowed_to = stowed(scene, q_to, ignore, posture, (back,))
        backed = over.copy()
        backed[[x, y]] = stowed_to[[x, y]]
        endings.append([stowed_to, backed, over])
    endings.append([stowed(scene, q_to, ignore, posture)])
    for stowed_to, *drive_in in endings:
        route = route_out(stowed_from[[x, y]], stowed_to[[x, y]], scene.scene.table)
        yield np.array([q_from, *driven(scene, stowed_from, stowed_to, route), *drive_in, q_to])


def _raised(scene: PlanningScene, q: np.ndarray, rise: float) -> np.ndarray:
    """`q` with the arm lifted by `rise` (m, within its limit) and the torso with it."""
    lift, torso = scene.index("arm_lift_joint"), scene.index(TORSO_JOINT)
    raised = q.copy()
    raised[lift] = min(scene.plant.GetPositionUpperLimits()[lift], q[lift] + rise)
    raised[torso] = q[torso] + TORSO_PER_LIFT * (raised[lift] - q[lift])
    return raised


def _speeds(scene: PlanningScene) -> np.ndarray:
    """Each position's speed limit; 1 where the model gives none (a joint the way never moves:
    the head, the fingers)."""
    speeds = scene.plant.GetVelocityUpperLimits().copy()
    speeds[~np.isfinite(speeds) | (speeds <= 0)] = 1.0
    return speeds


def _groups(scene: PlanningScene) -> list[list[int]]:
    """The joints a shortcut moves together: all, the base, the arm (with the torso, which
    the arm's lift drives), each base joint, each arm joint (the lift with the torso)."""
    index = scene.index
    lift = [index("arm_lift_joint"), index(TORSO_JOINT)]
    base = [index(joint) for joint in BASE_JOINTS]
    arm = [index(joint) for joint in ARM_JOINTS if joint != "arm_lift_joint"]
    every = list(range(scene.plant.num_positions()))
    return [every, base, [*arm, *lift], *([i] for i in base), *([i] for i in arm), lift]


class _Check:
    """Whether a stretch of the way keeps the collision bound (a start's contact allowed as
    for any path, `StartContact`, at the stretch's share of the way) and the held object up,
    at points no joint moves more than CHECK_STEP apart, checked coarse to fine and given up
    at the first point that fails."""

    def __init__(self, scene, ignore, contact: StartContact, q_from, q_to):
        self.scene, self.ignore, self.contact = scene, ignore, contact
        self.up_bound = None if scene.upright is None else path_bound(scene, q_from, q_to)

    def __call__(self, stretch: np.ndarray, first: int) -> bool:
        moves = np.diff(stretch, axis=0)
        steps = np.maximum(1, np.ceil(np.abs(moves).max(axis=1) / CHECK_STEP)).astype(int)
        segment = np.repeat(np.arange(len(moves)), steps)
        # Each segment's share done at each check: 0, 1/steps, ..., (steps - 1)/steps.
        share = (np.arange(len(segment)) - np.repeat(np.cumsum(steps) - steps, steps)) / steps[
            segment
        ]
        configurations = np.vstack([stretch[segment] + moves[segment] * share[:, None],
                                    stretch[-1:]])  # fmt: skip
        spots = np.append(first + segment + share, first + len(moves)) / (WAY_POINTS - 1)
        count = len(configurations)
        order = dict.fromkeys([*range(0, count, 8), *range(0, count, 2), *range(count)])
        return all(self._keeps(configurations[i], spots[i]) for i in order)

    def _keeps(self, q: np.ndarray, spot: float) -> bool:
        scene = self.scene
        clearances = scene.part_clearances_at(q, self.ignore, within=COLLISION_BOUND)
        if self.contact.dip(clearances, spot) > 0:
            return False
        return self.up_bound is None or tilt(scene, q) <= self.up_bound
