"""Timing a path within the joints' limits with toppra."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from pydrake.math import BsplineBasis
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import PrismaticJoint, SpatialInertia
from pydrake.trajectories import BsplineTrajectory
from toppra.parametrizer import ParametrizeConstAccel

from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.timing import JointLimits, _DrakePath, joint_limits, time_path
from tests.robot.planning.conftest import configuration

STEP = 0.01  # s between the samples the limits are checked on
# (lower, upper, velocity, acceleration) as hsrb.sdf gives them: m, m/s, m/s^2 or rad, ...
MODEL_LIMITS = {
    "base_x_joint": (-100, 100, 0.2, 0.3),
    "base_y_joint": (-100, 100, 0.2, 0.3),
    "base_yaw_joint": (-1000, 1000, 1.0, 1.0),
    "arm_lift_joint": (0, 0.69, 0.2, 0.3),
    "torso_lift_joint": (0, 0.345, 0.1, 0.15),
    "arm_flex_joint": (-2.62, 0, 1.2, 1.5),
    "arm_roll_joint": (-2.09, 3.84, 2.0, 2.5),
    "wrist_flex_joint": (-1.92, 1.22, 1.5, 2.0),
    "wrist_roll_joint": (-1.92, 3.67, 1.5, 2.0),
    "head_pan_joint": (-3.84, 1.75, 1.0, 1.5),
    "head_tilt_joint": (-1.57, 0.52, 1.0, 1.5),
    "hand_l_finger_joint": (0, 0.0685, 1.0, 1.0),
    "hand_r_finger_joint": (0, 0.0685, 1.0, 1.0),
}
ARM_MOVE = {"arm_lift_joint": 0.3, "torso_lift_joint": 0.15, "arm_flex_joint": -1.2,
            "wrist_flex_joint": -1.0}  # fmt: skip
BASE_AND_ARM_MOVE = {"base_x_joint": 0.4, "base_yaw_joint": 0.5, "arm_flex_joint": -1.2}


def _line(start: np.ndarray, goal: np.ndarray, count: int = 8) -> BsplineTrajectory:
    """A cubic B-spline along the straight line from `start` to `goal` (its parameter in
    [0, count - 3], not in seconds)."""
    return BsplineTrajectory(BsplineBasis(4, count), np.linspace(start, goal, count).T)


def _fastest_line_time(move: np.ndarray, limits: JointLimits) -> float:
    """The least time (s) to go along a straight line `move` from rest to rest: with the
    fraction of the way as the path's coordinate, the joints allow a top speed V and an
    acceleration A (per s, per s^2), and the fastest is accelerate, coast, brake."""
    moving = np.abs(move) > 0
    top = np.min(limits.velocity[moving] / np.abs(move[moving]))
    acceleration = np.min(limits.acceleration[moving] / np.abs(move[moving]))
    if top**2 / acceleration >= 1.0:  # never reaches V: accelerate half way, brake half way
        return 2.0 * np.sqrt(1.0 / acceleration)
    return 1.0 / top + top / acceleration


def _assert_near_the_fastest(duration: float, move: np.ndarray, limits: JointLimits) -> None:
    """No faster than the true optimum (but for toppra's grid), and hardly slower: toppra's
    grid and the B-spline's uneven speed along its own parameter cost a few percent."""
    fastest = _fastest_line_time(move, limits)
    assert duration >= np.max(np.abs(move) / limits.velocity)  # the crudest bound
    assert 0.99 * fastest <= duration <= 1.1 * fastest


def _assert_within_limits(timed, limits: JointLimits) -> None:
    """Velocities within the limits on samples every STEP s; accelerations, by second
    differences of the positions, within them too (looser: toppra's acceleration jumps at
    its grid points and the differences smear it)."""
    times = np.arange(0.0, timed.duration, STEP)
    velocities = timed.velocities(times)
    assert np.all(np.abs(velocities) <= limits.velocity * (1 + 2e-3) + 1e-9)
    positions = timed.trajectory.values(times)
    accelerations = np.diff(positions, 2, axis=0) / STEP**2
    assert np.all(np.abs(accelerations) <= limits.acceleration * 1.02 + 1e-6)


def test_joint_limits_are_the_models_including_its_acceleration_limits(plant, limits):
    for name, (lower, upper, velocity, acceleration) in MODEL_LIMITS.items():
        index = plant.GetJointByName(name).position_start()
        assert limits.names[index] == name
        assert (limits.lower[index], limits.upper[index]) == (lower, upper), name
        assert (limits.velocity[index], limits.acceleration[index]) == (velocity, acceleration)
    torso, lift = (plant.GetJointByName(name).position_start()
                   for name in ("torso_lift_joint", "arm_lift_joint"))  # fmt: skip
    # The torso follows half the arm lift: half its speed and acceleration.
    assert limits.velocity[torso] == 0.5 * limits.velocity[lift]
    assert limits.acceleration[torso] == 0.5 * limits.acceleration[lift]


def test_joint_limits_keep_a_joint_without_position_limits_unbounded():
    plant = MultibodyPlant(0.0)
    body = plant.AddRigidBody("slider", SpatialInertia.SolidSphereWithMass(mass=1.0, radius=0.1))
    plant.AddJoint(PrismaticJoint("slide", plant.world_frame(), body.body_frame(), [1, 0, 0]))
    plant.Finalize()
    limits = joint_limits(plant)
    assert limits.lower[0] == -np.inf and limits.upper[0] == np.inf
    assert limits.names == ("slide",)


@pytest.mark.parametrize("move", [ARM_MOVE, BASE_AND_ARM_MOVE], ids=["arm", "base_and_arm"])
def test_a_straight_line_is_timed_from_rest_to_rest_within_the_limits(plant, limits, move):
    start = configuration(plant, {"arm_lift_joint": 0.1, "torso_lift_joint": 0.05})
    goal = start + configuration(plant, move)
    timed = time_path(_line(start, goal), limits)
    assert timed.ok, timed.reason
    times, positions = timed.sample(STEP)
    assert times[0] == 0 and times[-1] == timed.duration
    np.testing.assert_allclose(positions[0], start, atol=1e-12)
    np.testing.assert_allclose(positions[-1], goal, atol=1e-9)
    np.testing.assert_allclose(timed.velocities([0.0, timed.duration]), 0, atol=1e-9)
    _assert_within_limits(timed, limits)
    # It keeps to the line: every sample is start + fraction x (goal - start).
    fraction = (positions - start) @ (goal - start) / np.sum((goal - start) ** 2)
    np.testing.assert_allclose(positions, start + np.outer(fraction, goal - start), atol=1e-9)
    assert np.all(np.diff(fraction) >= -1e-12)
    _assert_near_the_fastest(timed.duration, goal - start, limits)


def test_a_curved_path_keeps_its_limits_between_toppras_grid_points(plant, limits):
    """Between grid points a curved path's speed peaks: the timing is slowed to cover that."""
    rng = np.random.default_rng(7)
    lower, upper = np.maximum(limits.lower, -1.0), np.minimum(limits.upper, 1.0)
    waypoints = rng.uniform(lower, upper, size=(4, len(lower)))
    fraction = np.linspace(0, 3, 30)
    control = np.array([np.interp(fraction, np.arange(4), column) for column in waypoints.T])
    path = BsplineTrajectory(BsplineBasis(4, 30), control)
    timed = time_path(path, limits)
    assert timed.ok, timed.reason
    _assert_within_limits(timed, limits)
    np.testing.assert_allclose(timed.trajectory.value(timed.duration).ravel(), control[:, -1])
    np.testing.assert_allclose(timed.velocities([0.0, timed.duration]), 0, atol=1e-9)


def test_the_per_step_state_is_the_trajectorys_positions_and_velocities(plant, limits):
    """`state(t)`, the robot's command every plant step, gives what `values` gives, on a
    curved path whose timing is stretched, before its start and after its end too."""
    rng = np.random.default_rng(3)
    waypoints = rng.uniform(-0.8, 0.8, size=(4, plant.num_positions()))
    control = np.array([np.interp(np.linspace(0, 3, 20), np.arange(4), w) for w in waypoints.T])
    trajectory = time_path(BsplineTrajectory(BsplineBasis(4, 20), control), limits).trajectory
    assert trajectory.stretch > 1.0  # the case where speeds are scaled back
    for time in [-1.0, 0.0, *rng.uniform(0, trajectory.duration, 50), trajectory.duration, 99]:
        position, velocity = trajectory.state(time)
        np.testing.assert_allclose(position, trajectory.values([time])[0], atol=1e-12)
        np.testing.assert_allclose(velocity, trajectory.values([time], 1)[0], atol=1e-12)
    held = time_path(_line(control[:, 0], control[:, 0]), limits).trajectory
    position, velocity = held.state(0.5)
    np.testing.assert_allclose(position, control[:, 0], atol=1e-12)
    np.testing.assert_array_equal(velocity, 0.0)


def test_the_timing_is_toppras_constant_acceleration_parametrisation(plant, limits):
    """Positions, velocities and accelerations as toppra's own `ParametrizeConstAccel` gives
    them for the same grid and path speeds, the stretch applied."""
    goal = configuration(plant, ARM_MOVE)
    path = _line(np.zeros_like(goal), goal)
    trajectory = time_path(path, limits).trajectory
    geometric = _DrakePath(path, np.arange(path.rows()))
    grid, speeds = trajectory.toppra_timing
    toppra_timing = ParametrizeConstAccel(geometric, grid, speeds)
    assert trajectory.duration == pytest.approx(trajectory.stretch * toppra_timing.duration)
    times = np.linspace(0.0, trajectory.duration, 37)
    for order in (0, 1, 2):
        expected = toppra_timing(times / trajectory.stretch, order) / trajectory.stretch**order
        np.testing.assert_allclose(trajectory.values(times, order), expected, atol=1e-10)


def test_held_joints_need_no_usable_limits_but_moving_ones_do(plant, limits):
    path = _line(np.zeros(plant.num_positions()), configuration(plant, {"arm_flex_joint": -1}))
    flex = plant.GetJointByName("arm_flex_joint").position_start()
    held = np.arange(plant.num_positions()) != flex
    # Zero and infinite limits on the joints the path does not move change nothing.
    odd = dataclasses.replace(limits, velocity=np.where(held, 0.0, limits.velocity),
                              acceleration=np.where(held, np.inf, limits.acceleration))  # fmt: skip
    assert time_path(path, odd).duration == pytest.approx(time_path(path, limits).duration)
    frozen = dataclasses.replace(limits, velocity=np.where(held, limits.velocity, 0.0))
    timed = time_path(path, frozen)
    assert not timed.ok and "arm_flex_joint" in timed.reason and "velocity" in timed.reason


def test_an_unbounded_base_is_timed(plant, limits):
    unbounded = dataclasses.replace(limits, lower=np.full_like(limits.lower, -np.inf),
                                    upper=np.full_like(limits.upper, np.inf))  # fmt: skip
    goal = configuration(plant, {"base_x_joint": 0.5, "base_y_joint": -0.3})
    timed = time_path(_line(np.zeros_like(goal), goal), unbounded)
    assert timed.ok, timed.reason
    _assert_near_the_fastest(timed.duration, goal, limits)


def test_a_path_that_does_not_move_takes_no_time(plant, limits):
    q = configuration(plant, {"arm_flex_joint": -0.3})
    timed = time_path(_line(q, q), limits)
    assert timed.ok and timed.duration == 0.0
    times, positions = timed.sample(STEP)
    np.testing.assert_array_equal(positions, [q])  # the start is the end
    np.testing.assert_array_equal(timed.velocities(times), 0.0)


def test_a_path_that_cannot_be_timed_is_reported_not_raised(plant, limits):
    goal = configuration(plant, {"arm_flex_joint": -1.0})
    broken = _line(np.zeros_like(goal), goal)
    control = np.hstack(broken.control_points())
    control[4, 3] = np.nan
    timed = time_path(BsplineTrajectory(broken.basis(), control), limits)
    assert not timed.ok and "non-finite" in timed.reason
    short = time_path(_line(np.zeros_like(goal), goal), limits, grid_points=1)
    assert not short.ok and "grid points" in short.reason
    wrong = time_path(_line(np.zeros(3), np.ones(3)), limits)
    assert not wrong.ok and "rows" in wrong.reason


def test_a_timed_path_is_given_to_a_controller_at_toppras_grid_points(plant, limits):
    """As a joint trajectory controller is sent it: toppra's grid points, from rest at the
    start to rest at the goal, and a held path is one point."""
    start = configuration(plant, {"arm_lift_joint": 0.1, "torso_lift_joint": 0.05})
    goal = start + configuration(plant, ARM_MOVE)
    timed = time_path(_line(start, goal), limits, grid_points=40)
    motion = Motion(name="move", trajectory=timed)
    times, positions, velocities = motion.knots()
    assert len(times) == 40 and times[0] == 0.0
    assert times[-1] == pytest.approx(timed.duration) and np.all(np.diff(times) > 0)
    np.testing.assert_allclose(positions[[0, -1]], [start, goal], atol=1e-9)
    np.testing.assert_allclose(velocities[[0, -1]], 0.0, atol=1e-9)
    np.testing.assert_allclose(velocities[1:-1], timed.velocities(times[1:-1]), atol=1e-9)
    held = Motion(name="hold", trajectory=time_path(_line(start, start), limits)).knots()
    assert held[0].tolist() == [0.0]
