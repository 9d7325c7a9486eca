"""Re-targeting during execution: when the handover point moves (the person's
hand moves), go from the robot's current state (position, velocity, acceleration) to the new
goal with a jerk-limited, time-optimal motion (the `ruckig` package). State to state only:
ruckig's intermediate waypoints call a remote service in its free build (docs/design.md §5).

Ruckig synchronises the joints in time but does not keep them on a line in joint space; the
caller checks the motion's clearance as for any timed trajectory, and plans anew when it is
not clear. Ruckig's free build ignores position limits, so they are checked here.
Positions are in plant order, in m or rad; velocities per s, accelerations per s^2.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory

from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.timing import STILL, JointLimits, sample_times

JERK_PER_ACCELERATION = 5.0  # 1/s: jerk limit = 5 x acceleration limit, full from rest in 0.2 s
POSITION_TOLERANCE = 1e-9  # m or rad beyond a position limit still taken as within (rounding)
KNOT_STEP_S = 0.02
"""s between the samples a ruckig motion is given at to a trajectory controller: its
jerk-limited phases last 0.2 s from rest, so 10 samples and more cover each."""


@dataclasses.dataclass(frozen=True, kw_only=True)
class Retargeting(Outcome):
    """`ok` with a motion of `duration` s, or not with the `reason`."""

    duration: float = 0.0
    trajectory: Trajectory | None = None

    def at(self, time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions, velocities and accelerations (each (nq,)) at `time` s, held at the start
        before 0 and at the goal after `duration`."""
        if not self.ok:
            raise ValueError(f"no motion to evaluate: {self.reason}")
        position, velocity, acceleration = self.trajectory.at_time(
            float(np.clip(time, 0.0, self.duration))
        )
        return np.array(position), np.array(velocity), np.array(acceleration)

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (nq,) at `time` s, held at the ends."""
        position, velocity, _ = self.at(time)
        return position, velocity

    def knot_times(self) -> np.ndarray:
        """Times (s) every KNOT_STEP_S, the end included: ruckig's motion, sampled."""
        return sample_times(self.duration, KNOT_STEP_S)

    def sample(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Times (n,) every `step` s from 0, the end included, and the positions (n, nq)."""
        times = sample_times(self.duration, step)
        return times, np.array([self.at(t)[0] for t in times])


@dataclasses.dataclass(frozen=True)
class _State:
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    target_position: np.ndarray
    target_velocity: np.ndarray


def retarget(
    position: np.ndarray,
    velocity: np.ndarray,
    acceleration: np.ndarray,
    target_position: np.ndarray,
    limits: JointLimits,
    target_velocity: np.ndarray | None = None,
) -> Retargeting:
    """The fastest jerk-limited motion from the current state to `target_position`, arriving
    with `target_velocity` (at rest if None) and no acceleration, within the velocity and
    acceleration `limits` (jerk JERK_PER_ACCELERATION times the latter) and never further
    beyond a position limit than it starts. Never raises: bad input gives `ok` False and why.
    """
    goal_velocity = np.zeros_like(target_position) if target_velocity is None else target_velocity
    state, reason = _state(position, velocity, acceleration, target_position, goal_velocity)
    if state is None:
        return Retargeting(ok=False, reason=reason)
    moving = _moving(state)
    reason = _limits_problem(state, limits, moving)
    if reason:
        return Retargeting(ok=False, reason=reason)
    trajectory = Trajectory(len(moving))
    try:
        result = Ruckig(len(moving)).calculate(_input(state, limits, moving), trajectory)
    except RuckigError as error:  # ruckig's validation of the input
        return Retargeting(
            ok=False, reason=f"ruckig refused the input ({str(error).strip()[:160]})"
        )
    if result not in (Result.Working, Result.Finished):
        return Retargeting(ok=False, reason=f"ruckig found no motion ({result.name})")
    reason = _overshoot(trajectory, state, limits, moving)
    if reason:
        return Retargeting(ok=False, reason=reason)
    return Retargeting(
        ok=True, reason="ok", duration=float(trajectory.duration), trajectory=trajectory
    )


def _state(*vectors) -> tuple[_State | None, str]:
    """The five vectors as a state, or None and why: they must be finite and of one length."""
    try:
        arrays = [np.asarray(vector, dtype=float) for vector in vectors]
    except (TypeError, ValueError) as error:
        return None, f"the state is not numbers ({error})"
    names = [field.name for field in dataclasses.fields(_State)]
    count = arrays[0].shape
    for name, array in zip(names, arrays, strict=True):
        if array.ndim != 1 or array.shape != count:
            return None, f"{name} has shape {array.shape}, expected {count} like position"
        if not np.all(np.isfinite(array)):
            return None, f"{name} is not finite at {np.flatnonzero(~np.isfinite(array)).tolist()}"
    return _State(*arrays), ""


def _moving(state: _State) -> np.ndarray:
    """Which joints must move: not those at rest at their target (ruckig leaves them out, so a
    held joint needs no usable limit)."""
    at_rest = (state.velocity == 0) & (state.acceleration == 0) & (state.target_velocity == 0)
    return ~(at_rest & (np.abs(state.target_position - state.position) <= STILL))


def _limits_problem(state: _State, limits: JointLimits, moving: np.ndarray) -> str:
    """Why the limits forbid the motion, or "" if they do not."""
    if len(limits.velocity) != len(moving):
        return f"{len(moving)} positions but limits for {len(limits.velocity)}"
    for kind, bound in (("velocity", limits.velocity), ("acceleration", limits.acceleration)):
        bad = np.flatnonzero(moving & ~(np.isfinite(bound) & (bound > 0)))
        if len(bad):
            return f"{_names(limits, bad)} must move without a finite positive {kind} limit"
    target = state.target_position
    outside = np.flatnonzero(
        (target < limits.lower - POSITION_TOLERANCE) | (target > limits.upper + POSITION_TOLERANCE)
    )
    if len(outside):
        return f"target_position is beyond the position limits of {_names(limits, outside)}"
    fast = np.flatnonzero(np.abs(state.target_velocity) > limits.velocity)
    if len(fast):
        return f"target_velocity exceeds the velocity limits of {_names(limits, fast)}"
    return ""


def _input(state: _State, limits: JointLimits, moving: np.ndarray) -> InputParameter:
    """Ruckig's problem: state to state, no intermediate waypoints."""
    problem = InputParameter(len(moving))
    problem.current_position = state.position
    problem.current_velocity = state.velocity
    problem.current_acceleration = state.acceleration
    problem.target_position = state.target_position
    problem.target_velocity = state.target_velocity
    problem.enabled = moving.tolist()
    # Held joints are left out; ruckig still wants numbers for their limits.
    acceleration = np.where(moving, limits.acceleration, 1.0)
    problem.max_velocity = np.where(moving, limits.velocity, 1.0)
    problem.max_acceleration = acceleration
    problem.max_jerk = JERK_PER_ACCELERATION * acceleration
    return problem


def _overshoot(
    trajectory: Trajectory, state: _State, limits: JointLimits, moving: np.ndarray
) -> str:
    """Why the motion passes a position limit (further than where the joint starts), or ""."""
    extrema = trajectory.position_extrema
    lowest = np.array([extremum.min for extremum in extrema])
    highest = np.array([extremum.max for extremum in extrema])
    lower = np.minimum(limits.lower, state.position) - POSITION_TOLERANCE
    upper = np.maximum(limits.upper, state.position) + POSITION_TOLERANCE
    beyond = np.flatnonzero(moving & ((lowest < lower) | (highest > upper)))
    if len(beyond):
        return f"the motion passes the position limits of {_names(limits, beyond)}"
    return ""


def _names(limits: JointLimits, indices: np.ndarray) -> str:
    return ", ".join(limits.name(int(index)) for index in indices)
