"""Re-targeting from a moving state with ruckig."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.retarget import JERK_PER_ACCELERATION, KNOT_STEP_S, retarget
from tests.robot.planning.conftest import configuration

STEP = 0.01  # s between the samples the limits are checked on
START = {"arm_lift_joint": 0.2, "torso_lift_joint": 0.1, "arm_flex_joint": -0.5,
         "wrist_flex_joint": -1.0}  # fmt: skip
MOVING = {"base_x_joint": 0.1, "arm_lift_joint": 0.1, "torso_lift_joint": 0.05,
          "arm_flex_joint": -0.4, "wrist_flex_joint": 0.5}  # fmt: skip
"""A velocity (m/s, rad/s) within the limits, the torso at half the arm lift's."""
ACCELERATING = {"arm_flex_joint": -0.8, "wrist_flex_joint": 1.0}  # rad/s^2
GOAL = {"base_x_joint": 0.3, "arm_lift_joint": 0.5, "torso_lift_joint": 0.25,
        "arm_flex_joint": -1.0, "wrist_flex_joint": -0.6, "head_tilt_joint": -0.3}  # fmt: skip


def _index(plant, joint: str) -> int:
    return plant.GetJointByName(joint).position_start()


def _states(motion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions, velocities and accelerations (n, nq) every STEP s, the end included."""
    times = np.append(np.arange(0.0, motion.duration, STEP), motion.duration)
    return tuple(np.array(column) for column in zip(*(motion.at(t) for t in times), strict=True))


def test_from_a_moving_state_it_carries_on_smoothly_to_the_new_goal(plant, limits):
    position, velocity = configuration(plant, START), configuration(plant, MOVING)
    acceleration, goal = configuration(plant, ACCELERATING), configuration(plant, GOAL)
    motion = retarget(position, velocity, acceleration, goal, limits)
    assert motion.ok, motion.reason
    start, end = motion.at(0.0), motion.at(motion.duration)
    for value, given in zip(start, (position, velocity, acceleration), strict=True):
        np.testing.assert_allclose(value, given, atol=1e-12)  # no jump in any of them
    np.testing.assert_allclose(end[0], goal, atol=1e-9)  # there, at rest, exactly at the end
    np.testing.assert_allclose(end[1:], 0.0, atol=1e-9)
    positions, velocities, accelerations = _states(motion)
    assert np.all(np.abs(velocities) <= limits.velocity + 1e-9)
    assert np.all(np.abs(accelerations) <= limits.acceleration + 1e-9)
    jerks = np.diff(accelerations[:-1], axis=0) / STEP  # the last step may be shorter
    assert np.all(np.abs(jerks) <= JERK_PER_ACCELERATION * limits.acceleration + 1e-6)
    assert np.all(positions >= limits.lower) and np.all(positions <= limits.upper)
    # The base goes 0.3 m at 0.2 m/s at most: 1.5 s at least. From rest it would take that
    # plus v/a to ramp its speed and a/j its acceleration: less, as it starts at 0.1 m/s.
    assert 0.3 / 0.2 <= motion.duration <= 0.3 / 0.2 + 0.2 / 0.3 + 1 / JERK_PER_ACCELERATION


def test_the_torso_keeps_to_half_the_arm_lift(plant, limits):
    """The torso's limits, state and goal are half the arm lift's, so is its whole motion."""
    start, moving = configuration(plant, START), configuration(plant, MOVING)
    still = np.zeros(len(limits.lower))
    motion = retarget(start, moving, still, configuration(plant, GOAL), limits)
    assert motion.ok, motion.reason
    positions, _, _ = _states(motion)
    torso, lift = _index(plant, "torso_lift_joint"), _index(plant, "arm_lift_joint")
    np.testing.assert_allclose(positions[:, torso], 0.5 * positions[:, lift], atol=1e-9)


def test_it_can_arrive_moving(plant, limits):
    arrive = configuration(plant, {"base_x_joint": 0.05, "arm_flex_joint": -0.2})
    motion = retarget(configuration(plant, START), np.zeros_like(arrive), np.zeros_like(arrive),
                      configuration(plant, GOAL), limits, target_velocity=arrive)  # fmt: skip
    assert motion.ok, motion.reason
    np.testing.assert_allclose(motion.at(motion.duration)[1], arrive, atol=1e-9)


def test_held_joints_and_an_unbounded_base_are_fine(plant, limits):
    held = np.ones(len(limits.lower), bool)
    held[[_index(plant, "base_x_joint"), _index(plant, "base_y_joint")]] = False
    odd = dataclasses.replace(
        limits,
        lower=np.where(held, limits.lower, -np.inf),
        upper=np.where(held, limits.upper, np.inf),
        velocity=np.where(held, 0.0, limits.velocity),  # the held joints could not move at all
    )
    start = configuration(plant, {"base_x_joint": 40.0, "arm_flex_joint": -0.3})
    goal = start + configuration(plant, {"base_x_joint": 0.5, "base_y_joint": -0.2})
    motion = retarget(start, np.zeros_like(start), np.zeros_like(start), goal, odd)
    assert motion.ok, motion.reason
    positions, _, _ = _states(motion)
    np.testing.assert_array_equal(positions[:, held] - start[held], 0.0)
    np.testing.assert_allclose(positions[-1], goal, atol=1e-9)


def test_a_nan_target_is_reported_not_raised(plant, limits):
    goal = configuration(plant, GOAL)
    goal[_index(plant, "arm_flex_joint")] = np.nan
    zeros = np.zeros_like(goal)
    motion = retarget(configuration(plant, START), zeros, zeros, goal, limits)
    assert not motion.ok
    assert "target_position" in motion.reason and "not finite" in motion.reason
    with pytest.raises(ValueError, match="not finite"):
        motion.at(0.0)


@pytest.mark.parametrize(
    ("name", "value", "reason"),
    [
        ("target_position", np.zeros(4), "target_position has shape (4,)"),
        ("velocity", {"base_x_joint": np.inf}, "velocity is not finite"),
        ("target_position", {"arm_flex_joint": 0.5}, "position limits of arm_flex_joint"),
        ("target_velocity", {"arm_flex_joint": 2.0}, "velocity limits of arm_flex_joint"),
    ],
)
def test_bad_input_is_reported_not_raised(plant, limits, name, value, reason):
    zeros = np.zeros(len(limits.lower))
    inputs = {"position": configuration(plant, START), "velocity": zeros, "acceleration": zeros,
              "target_position": configuration(plant, GOAL)}  # fmt: skip
    inputs[name] = value if isinstance(value, np.ndarray) else configuration(plant, value)
    motion = retarget(limits=limits, **inputs)
    assert not motion.ok and reason in motion.reason


def test_a_motion_that_would_overshoot_a_position_limit_is_refused(plant, limits):
    """Arm flex at -0.1 rad rising at its top speed 1.2 rad/s cannot stop before its upper
    limit 0: ruckig does not know position limits, the check after it does."""
    flex = _index(plant, "arm_flex_joint")
    start, velocity = configuration(plant, {"arm_flex_joint": -0.1}), np.zeros(len(limits.lower))
    velocity[flex] = 1.2
    motion = retarget(start, velocity, np.zeros_like(start), start, limits)
    assert not motion.ok and "passes the position limits of arm_flex_joint" in motion.reason


def test_a_controller_is_sent_the_moving_start_and_the_goal_at_rest(plant, limits):
    """Given as a joint trajectory: from the state it re-targets from, every KNOT_STEP_S, to
    the goal at rest at its end."""
    position, velocity = configuration(plant, START), configuration(plant, MOVING)
    goal = configuration(plant, GOAL)
    motion = Motion(name="follow", trajectory=retarget(position, velocity, 0 * goal, goal, limits))
    times, positions, velocities = motion.knots()
    assert times[0] == 0.0 and times[-1] == pytest.approx(motion.duration)
    assert np.diff(times).max() == pytest.approx(KNOT_STEP_S)
    np.testing.assert_allclose(positions[[0, -1]], [position, goal], atol=1e-9)
    np.testing.assert_allclose(velocities[[0, -1]], [velocity, 0 * goal], atol=1e-9)
