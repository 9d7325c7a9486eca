"""Time a geometric path within the joints' velocity and acceleration limits:
time-optimal path parameterisation by reachability analysis (the `toppra` package), starting
and ending at rest.

The path is the optimiser's cubic B-spline (C2), handed to toppra as it is, its derivatives
exact from Drake, so the timed trajectory follows exactly the path that was checked for
collisions. Positions are in plant order (a joint's entry is its `position_start()`), metres
for the prismatic joints and radians for the revolute ones.
"""

from __future__ import annotations

import dataclasses
import functools
import logging

import numpy as np
import toppra
import toppra.algorithm
import toppra.constraint
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JointIndex
from pydrake.trajectories import BsplineTrajectory
from toppra.exceptions import ToppraError
from toppra.interpolator import AbstractGeometricPath

from hsr_handover.robot.planning.outcome import Outcome

GRID_POINTS = 100  # toppra's discretisation of the path: its limits hold at these points
CHECKS_PER_INTERVAL = 4  # more points per grid interval where the limits are made to hold
SOLVER = "seidel"  # toppra's own LP solver for 2 variables: fast, and needs no other package
STILL = 1e-9  # m or rad: a joint whose control points span less than this does not move
logging.getLogger("toppra").setLevel(logging.WARNING)  # it reports every solve at INFO


@dataclasses.dataclass(frozen=True)
class JointLimits:
    """Per plant position: position bounds `lower`, `upper` (m or rad, possibly infinite) and
    the largest speed `velocity` (m/s or rad/s) and `acceleration` (m/s^2 or rad/s^2), both
    positive; `names` the joint of each position, for the reasons of failures."""

    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    names: tuple[str, ...] = ()

    def name(self, index: int) -> str:
        """The joint of position `index`, or "position <index>" without names."""
        return self.names[index] if index < len(self.names) else f"position {index}"


def joint_limits(plant: MultibodyPlant) -> JointLimits:
    """The finalised `plant`'s limits in plant position order. Every joint of the HSR has one
    position and one velocity, so velocity and acceleration limits share that order."""
    if plant.num_positions() != plant.num_velocities():
        raise ValueError("joint_limits needs a plant with one velocity per position")
    names = [""] * plant.num_positions()
    for index in range(plant.num_joints()):
        joint = plant.get_joint(JointIndex(index))
        for offset in range(joint.num_positions()):
            names[joint.position_start() + offset] = joint.name()
    return JointLimits(
        lower=plant.GetPositionLowerLimits().copy(),
        upper=plant.GetPositionUpperLimits().copy(),
        velocity=plant.GetVelocityUpperLimits().copy(),
        acceleration=plant.GetAccelerationUpperLimits().copy(),
        names=tuple(names),
    )


class _DrakePath(AbstractGeometricPath):
    """Some rows of a Drake B-spline seen by toppra as a geometric path over the spline's own
    parameter. Derivatives come from Drake's `MakeDerivative` (the same values as
    `EvalDerivative`, but evaluated for all of toppra's points at once: about 30x faster)."""

    def __init__(self, path: BsplineTrajectory, rows: np.ndarray):
        self._rows = rows
        self._derivatives = [path, path.MakeDerivative(1), path.MakeDerivative(2)]
        self._interval = np.array([path.start_time(), path.end_time()])

    def point(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """The path's value and tangent (its rows) at one path position `s`."""
        value, tangent = self._derivatives[0].value(s), self._derivatives[1].value(s)
        return value[self._rows, 0], tangent[self._rows, 0]

    def __call__(self, path_positions, order: int = 0) -> np.ndarray:
        scalar = np.isscalar(path_positions)
        s = np.clip(np.atleast_1d(np.asarray(path_positions, dtype=float)), *self._interval)
        values = self._derivatives[order].vector_values(s)[self._rows].T
        return values[0] if scalar else values

    @property
    def dof(self) -> int:
        return len(self._rows)

    @property
    def path_interval(self) -> np.ndarray:
        return self._interval

    @property
    def waypoints(self):
        return None


class TimedTrajectory:
    """The path's plant positions over time t in [0, duration] s (held at the ends outside),
    with Drake's `value(t)`, `start_time()` and `end_time()`, so it can stand in for the path.

    It follows toppra's constant-acceleration parametrisation s(t) of the original path rather
    than a spline fitted through samples: the positions are exactly on the B-spline that was
    checked for collisions, and the velocities are continuous."""

    def __init__(
        self,
        path: BsplineTrajectory,
        grid: np.ndarray | None = None,
        path_speeds: np.ndarray | None = None,
        stretch: float = 1.0,
    ):
        """`path_speeds` ds/dt at the `grid` points s of the path (None: nothing moves, the
        start is held), the timing then slowed uniformly by the factor `stretch` (>= 1)."""
        self._path = _DrakePath(path, np.arange(path.rows()))
        self._timing = None if grid is None else _ConstAccelTiming(grid, path_speeds)
        self._stretch = stretch
        self._duration = 0.0 if grid is None else stretch * self._timing.duration

    @property
    def duration(self) -> float:
        return self._duration

    @property
    def stretch(self) -> float:
        """The factor (>= 1) toppra's timing was slowed by to keep the limits between its grid
        points."""
        return self._stretch

    @property
    def toppra_timing(self) -> tuple[np.ndarray, np.ndarray] | None:
        """toppra's grid points s along the path and the path speeds ds/dt there, before the
        stretch (None: nothing moves)."""
        return None if self._timing is None else (self._timing.grid, self._timing.speeds)

    def knot_times(self) -> np.ndarray:
        """The times (s) of toppra's grid points, stretched: 0 and the end included."""
        if self._timing is None:
            return np.array([0.0])
        return self._stretch * self._timing.times

    def start_time(self) -> float:
        return 0.0

    def end_time(self) -> float:
        return self._duration

    def value(self, time: float) -> np.ndarray:
        """Positions (nq, 1) at `time` s, as a Drake trajectory gives them."""
        return self.values(np.array([time]))[0][:, np.newaxis]

    def values(self, times: np.ndarray, order: int = 0) -> np.ndarray:
        """Positions (order 0), velocities (1, per s) or accelerations (2, per s^2), shape
        (n, nq), at the n `times` s."""
        times = np.clip(np.atleast_1d(np.asarray(times, dtype=float)), 0.0, self._duration)
        if self._timing is None:  # nothing moves: the start held
            held = self._path(np.full(len(times), self._path.path_interval[0]))
            return held if order == 0 else np.zeros_like(held)
        s, speed, acceleration = self._timing.at(times / self._stretch)
        if order == 0:
            return self._path(s)
        if order == 1:
            return self._path(s, 1) * (speed / self._stretch)[:, np.newaxis]
        curvature = self._path(s, 2) * (speed**2)[:, np.newaxis]
        return (curvature + self._path(s, 1) * acceleration[:, np.newaxis]) / self._stretch**2

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (nq,) at one `time` s, as `values` gives them for orders 0
        and 1, in one pass: the robot's command, every plant step (16 us against 37 us for two
        calls of `values`)."""
        time = min(max(float(time), 0.0), self._duration)
        if self._timing is None:
            return self.values(np.array([time]))[0], np.zeros(self._path.dof)
        s, speed, _ = self._timing.at(np.array([time / self._stretch]))
        position, tangent = self._path.point(float(np.clip(s[0], *self._path.path_interval)))
        return position, tangent * (speed[0] / self._stretch)


class _ConstAccelTiming:
    """toppra's constant-acceleration timing s(t) between its grid points (the arithmetic of
    `toppra.parametrizer.ParametrizeConstAccel`, without its per-time Python loop)."""

    def __init__(self, grid: np.ndarray, path_speeds: np.ndarray):
        self.grid = np.asarray(grid, dtype=float)
        self.speeds = np.asarray(path_speeds, dtype=float)
        steps = np.diff(self.grid)
        self._accelerations = 0.5 * np.diff(self.speeds**2) / steps
        steps_time = 2 * steps / (self.speeds[:-1] + self.speeds[1:])
        self.times = np.concatenate([[0.0], np.cumsum(steps_time)])
        self.duration = float(self.times[-1])

    def at(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The path positions s, speeds ds/dt and accelerations at `times` (n,) s."""
        last = len(self._accelerations) - 1
        index = np.minimum(np.searchsorted(self.times, times, side="right") - 1, last)
        elapsed = times - self.times[index]
        acceleration, speed = self._accelerations[index], self.speeds[index]
        position = self.grid[index] + elapsed * speed + 0.5 * elapsed**2 * acceleration
        return position, speed + elapsed * acceleration, acceleration


def sample_times(duration: float, step: float) -> np.ndarray:
    """Times (n,) every `step` s from 0 to `duration`, the end included."""
    return np.append(np.arange(0.0, duration, step), duration)


@dataclasses.dataclass(frozen=True, kw_only=True)
class TimedPath(Outcome):
    """`ok` with a `trajectory` of `duration` s, or not with the `reason`."""

    duration: float = 0.0
    trajectory: TimedTrajectory | None = None

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (nq,) at `time` s from the start (held at the ends)."""
        return self.trajectory.state(time)

    def knot_times(self) -> np.ndarray:
        """The times (s) of toppra's grid points along it (`TimedTrajectory.knot_times`)."""
        return self.trajectory.knot_times()

    def sample(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Times (n,) every `step` s from 0, the end included, and the positions (n, nq)."""
        times = sample_times(self.duration, step)
        return times, self.trajectory.values(times)

    def velocities(self, times: np.ndarray) -> np.ndarray:
        """Velocities (n, nq), in m/s or rad/s, at the n `times` s."""
        return self.trajectory.values(times, 1)

    def accelerations(self, times: np.ndarray) -> np.ndarray:
        """Accelerations (n, nq), in m/s^2 or rad/s^2, at the n `times` s (piecewise
        continuous: toppra's path acceleration is constant between its grid points)."""
        return self.trajectory.values(times, 2)


def time_path(
    path: BsplineTrajectory, limits: JointLimits, grid_points: int = GRID_POINTS
) -> TimedPath:
    """The fastest timing of `path` (a B-spline of plant positions over its own parameter)
    within the velocity and acceleration `limits`, from rest to rest; toppra's `grid_points`
    points along the path (at least 2). Never raises for a path it cannot time: `ok` is
    False and `reason` says why."""
    moving, reason = _moving_rows(path, limits)
    if reason:
        return TimedPath(ok=False, reason=reason)
    if len(moving) == 0:
        return TimedPath(ok=True, reason="ok", duration=0.0, trajectory=TimedTrajectory(path))
    # Only the moving joints constrain the timing: a held joint may have no usable limit.
    geometric = _DrakePath(path, moving)
    data, reason = _parameterize(geometric, limits, moving, grid_points)
    if data is None:
        return TimedPath(ok=False, reason=f"timing failed ({reason})")
    stretch = _stretch(geometric, data.gridpoints, data.sd_vec, limits, moving)
    trajectory = TimedTrajectory(path, data.gridpoints, data.sd_vec, stretch)
    return TimedPath(ok=True, reason="ok", duration=trajectory.duration, trajectory=trajectory)


def _parameterize(geometric: _DrakePath, limits: JointLimits, rows: np.ndarray, points: int):
    """toppra's problem data (grid points and path speeds ds/dt there) from rest to rest, or
    None and why."""
    if points < 2:
        return None, f"{points} grid points: toppra needs at least 2"
    grid = np.linspace(*geometric.path_interval, points)
    constraints = list(_constraints(limits, rows))
    try:
        solver = toppra.algorithm.TOPPRA(
            constraints, geometric, gridpoints=grid, solver_wrapper=SOLVER
        )
        solver.compute_parameterization(0.0, 0.0)
    except (ValueError, ArithmeticError, np.linalg.LinAlgError, ToppraError) as error:
        return None, f"{type(error).__name__}: {error}"
    data = solver.problem_data
    if data.return_code != toppra.algorithm.ParameterizationReturnCode.Ok:
        return None, f"toppra: {data.return_code.value}"
    return data, ""


def _stretch(
    geometric: _DrakePath,
    grid: np.ndarray,
    path_speed: np.ndarray,
    limits: JointLimits,
    rows: np.ndarray,
) -> float:
    """The factor (>= 1) by which to slow toppra's timing uniformly so that the limits hold
    at CHECKS_PER_INTERVAL points between its grid points too. toppra makes them hold only
    at the grid points; between them a curved path's speeds and accelerations exceed them
    (measured: by up to 3 % and 4 % on 100 points). Slowing by k divides the velocities by k and
    the accelerations by k^2; it costs a few percent of the duration when it is needed."""
    fractions = np.linspace(0.0, 1.0, CHECKS_PER_INTERVAL + 2)
    square = path_speed**2  # linear in s between grid points at constant path acceleration
    steps = np.diff(grid)
    s = (grid[:-1, np.newaxis] + fractions * steps[:, np.newaxis]).ravel()
    x = (square[:-1, np.newaxis] + fractions * np.diff(square)[:, np.newaxis]).ravel()
    u = np.repeat(0.5 * np.diff(square) / steps, len(fractions))  # as ParametrizeConstAccel
    first, second = geometric(s, 1), geometric(s, 2)
    velocity = first * np.sqrt(np.maximum(x, 0.0))[:, np.newaxis]
    acceleration = second * x[:, np.newaxis] + first * u[:, np.newaxis]
    over_velocity = np.max(np.abs(velocity) / limits.velocity[rows])
    over_acceleration = np.max(np.abs(acceleration) / limits.acceleration[rows])
    return max(1.0, over_velocity, np.sqrt(over_acceleration))


def _moving_rows(path: BsplineTrajectory, limits: JointLimits) -> tuple[np.ndarray, str]:
    """The positions the path moves, or a reason it cannot be timed."""
    control = np.hstack(path.control_points())
    if control.shape[0] != len(limits.velocity):
        return np.array([], int), f"path has {control.shape[0]} rows, limits {len(limits.velocity)}"
    if not np.all(np.isfinite(control)):
        return np.array([], int), "path has non-finite control points"
    # A B-spline stays within the hull of its control points: equal ones mean a held joint.
    moving = np.flatnonzero(np.ptp(control, axis=1) > STILL)
    for kind, bound in (("velocity", limits.velocity), ("acceleration", limits.acceleration)):
        bad = [i for i in moving if not (np.isfinite(bound[i]) and bound[i] > 0)]
        if bad:
            names = ", ".join(limits.name(i) for i in bad)
            return moving, f"path moves {names} without a finite positive {kind} limit"
    return moving, ""


def _constraints(limits: JointLimits, rows: np.ndarray) -> tuple:
    """toppra's per-joint bounds [-limit, limit] on the `rows`' velocity and acceleration."""
    return _cached_constraints(tuple(limits.velocity[rows]), tuple(limits.acceleration[rows]))


@functools.lru_cache(maxsize=32)
def _cached_constraints(velocity: tuple[float, ...], acceleration: tuple[float, ...]) -> tuple:
    """Kept, as toppra's constraints do not change with the path and building them costs
    about 2 ms, half as much again as the timing (they format every limit into a string)."""
    velocity, acceleration = np.array(velocity), np.array(acceleration)
    return (
        toppra.constraint.JointVelocityConstraint(np.column_stack([-velocity, velocity])),
        toppra.constraint.JointAccelerationConstraint(
            np.column_stack([-acceleration, acceleration])
        ),
    )
