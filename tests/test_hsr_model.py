"""The HSR-B model (models/hsrb/hsrb.sdf) against docs/design.md §4.1, the numpy FK and the PD
helpers."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pytest
from pydrake.geometry import Box, Cylinder, SceneGraph
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, MultibodyPlant
from pydrake.multibody.tree import Joint, ModelInstanceIndex
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, Diagram, DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from hsr_handover.hsr import (
    ARM_JOINTS,
    BASE_JOINTS,
    BASE_RADIUS,
    CAMERA_FRAME,
    GRIPPER_JOINT,
    GRIPPER_MAX_OPENING,
    HEAD_JOINTS,
    PALM_FRAME,
    add_hsr,
    hsr_desired_state,
    hsr_set_positions,
)
from hsr_handover.kinematics.hsr_arm import palm_pose, sample_arm_joints

# docs/design.md §4.1, typed in independently of the SDF:
# joint: (type, axis, parent body, origin in parent, lower, upper, velocity limit).
DESIGN_JOINTS = {
    "arm_lift_joint": ("prismatic", (0, 0, 1), "base_link", (0, 0, 0.340), 0, 0.69, 0.2),
    "arm_flex_joint": ("revolute", (0, -1, 0), "arm_lift_link", (0.141, 0.078, 0), -2.62, 0, 1.2),
    "arm_roll_joint": ("revolute", (0, 0, 1), "arm_flex_link", (0.005, 0, 0.345), -2.09, 3.84, 2.0),
    "wrist_flex_joint": ("revolute", (0, -1, 0), "arm_roll_link", (0, 0, 0), -1.92, 1.22, 1.5),
    "wrist_roll_joint": ("revolute", (0, 0, 1), "wrist_flex_link", (0, 0, 0), -1.92, 3.67, 1.5),
    "torso_lift_joint": ("prismatic", (0, 0, 1), "base_link", (0, 0, 0.752), 0, 0.345, 0.1),
    "head_pan_joint": ("revolute", (0, 0, 1), "torso_lift_link", (0, 0, 0), -3.84, 1.75, 1.0),
    "head_tilt_joint": ("revolute", (0, -1, 0), "head_pan_link", (0.02, 0, 0), -1.57, 0.52, 1.0),
    "hand_l_finger_joint": ("prismatic", (0, 1, 0), "hand_palm_link", (0, 0, 0), 0, 0.0685, 1.0),
    "hand_r_finger_joint": ("prismatic", (0, -1, 0), "hand_palm_link", (0, 0, 0), 0, 0.0685, 1.0),
}
DESIGN_BASE = {  # joint: (type, axis, velocity limit); position limits are "free"
    "base_x_joint": ("prismatic", (1, 0, 0), 0.2),
    "base_y_joint": ("prismatic", (0, 1, 0), 0.2),
    "base_yaw_joint": ("revolute", (0, 0, 1), 1.0),
}
EFFORT_LIMITS = {
    "base_x_joint": 200,
    "base_y_joint": 200,
    "base_yaw_joint": 50,
    "arm_lift_joint": 300,
    "arm_flex_joint": 100,
    "arm_roll_joint": 100,
    "wrist_flex_joint": 100,
    "wrist_roll_joint": 100,
    "head_pan_joint": 100,
    "head_tilt_joint": 100,
    "hand_l_finger_joint": 10,
}

ARM_FORWARD = {"arm_lift_joint": 0.3, "arm_flex_joint": -1.57, GRIPPER_JOINT: 0.05}
TYPICAL_POSTURES = {
    "zero": {},
    "arm_raised": {"arm_lift_joint": 0.69},
    "arm_forward": {"arm_lift_joint": 0.3, "arm_flex_joint": -1.57, "gripper": 0.137},
    "carry": {"arm_lift_joint": 0.2, "wrist_flex_joint": -1.57, "head_tilt_joint": -0.5},
    "look_at_table": {
        "arm_lift_joint": 0.1,
        "arm_flex_joint": -1.0,
        "wrist_flex_joint": -0.57,
        "head_pan_joint": 0.4,
        "head_tilt_joint": -0.8,
        "gripper": 0.08,
    },
    "reach_down": {"arm_lift_joint": 0.05, "arm_flex_joint": -2.2, "wrist_flex_joint": -0.6},
    # The real hand clears the upper arm at its wrist-flex limit; the model must too.
    "wrist_folded": {
        "arm_lift_joint": 0.3,
        "arm_flex_joint": -1.0,
        "wrist_flex_joint": -1.92,
        "wrist_roll_joint": 0.8,
    },
}


@dataclass
class Robot:
    diagram: Diagram
    plant: MultibodyPlant
    scene_graph: SceneGraph
    instance: ModelInstanceIndex
    context: Context

    @property
    def plant_context(self) -> Context:
        return self.plant.GetMyContextFromRoot(self.context)

    def pose_in_base(self, frame: str) -> RigidTransform:
        base = self.plant.GetFrameByName("base_link", self.instance)
        target = self.plant.GetFrameByName(frame, self.instance)
        return self.plant.CalcRelativeTransform(self.plant_context, base, target)

    def position(self, joint: str) -> float:
        return self.plant.GetJointByName(joint, self.instance).GetOnePosition(self.plant_context)


def build_robot(time_step: float = 1e-3, command: Mapping[str, float] | None = None) -> Robot:
    """The HSR alone in a discrete plant (default SAP-family approximation, gravity on).

    With ``command``, a constant source feeds its desired state to the PD controllers.
    """
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=time_step)
    instance = add_hsr(plant, Parser(plant))
    plant.Finalize()
    if command is not None:
        source = builder.AddSystem(
            ConstantVectorSource(hsr_desired_state(plant, instance, command))
        )
        builder.Connect(source.get_output_port(), plant.get_desired_state_input_port(instance))
    diagram = builder.Build()
    return Robot(diagram, plant, scene_graph, instance, diagram.CreateDefaultContext())


@pytest.fixture(scope="module")
def robot() -> Robot:
    return build_robot()


def start_simulation(robot: Robot, start: Mapping[str, float]) -> Simulator:
    """A simulator of ``robot`` initialised at the joint positions ``start``."""
    hsr_set_positions(robot.plant, robot.plant_context, robot.instance, start)
    simulator = Simulator(robot.diagram, robot.context)
    simulator.Initialize()
    return simulator


def check_type_and_axis(robot: Robot, name: str, kind: str, axis) -> Joint:
    """The joint ``name`` after asserting its type and its axis (in its parent-side frame)."""
    joint = robot.plant.GetJointByName(name, robot.instance)
    assert joint.type_name() == kind
    joint_axis = joint.translation_axis() if kind == "prismatic" else joint.revolute_axis()
    np.testing.assert_allclose(joint_axis, axis, atol=1e-12)
    return joint


@pytest.mark.parametrize("name", DESIGN_JOINTS)
def test_joint_matches_design(robot: Robot, name: str) -> None:
    kind, axis, parent, origin, lower, upper, velocity = DESIGN_JOINTS[name]
    joint = check_type_and_axis(robot, name, kind, axis)
    assert joint.parent_body().name() == parent
    X_PJ = joint.frame_on_parent().GetFixedPoseInBodyFrame()
    np.testing.assert_allclose(X_PJ.translation(), origin, atol=1e-12)
    np.testing.assert_allclose(X_PJ.rotation().matrix(), np.eye(3), atol=1e-12)
    np.testing.assert_allclose(joint.position_lower_limits(), [lower])
    np.testing.assert_allclose(joint.position_upper_limits(), [upper])
    np.testing.assert_allclose(joint.velocity_upper_limits(), [velocity])


@pytest.mark.parametrize("name", DESIGN_BASE)
def test_base_joint_is_free_planar(robot: Robot, name: str) -> None:
    kind, axis, velocity = DESIGN_BASE[name]
    joint = check_type_and_axis(robot, name, kind, axis)
    assert joint.position_lower_limits()[0] <= -100
    assert joint.position_upper_limits()[0] >= 100
    np.testing.assert_allclose(joint.velocity_upper_limits(), [velocity])


def test_actuators_are_pd_controlled_with_design_efforts(robot: Robot) -> None:
    plant = robot.plant
    actuators = [plant.get_joint_actuator(i) for i in plant.GetJointActuatorIndices(robot.instance)]
    efforts = {actuator.joint().name(): actuator.effort_limit() for actuator in actuators}
    assert efforts == pytest.approx(EFFORT_LIMITS)
    assert all(actuator.has_controller() for actuator in actuators)
    assert set(BASE_JOINTS + ARM_JOINTS + HEAD_JOINTS + (GRIPPER_JOINT,)) == set(efforts)


def test_the_base_disc_is_the_models(robot: Robot) -> None:
    """The planner's base radius is the model's collision cylinder round the base."""
    inspector = robot.scene_graph.model_inspector()
    base = robot.plant.GetBodyByName("base_link", robot.instance)
    shapes = [inspector.GetShape(g) for g in robot.plant.GetCollisionGeometriesForBody(base)]
    radii = [shape.radius() for shape in shapes if isinstance(shape, Cylinder)]
    assert radii == [pytest.approx(BASE_RADIUS)]


def test_palm_at_zero_and_highest(robot: Robot) -> None:
    hsr_set_positions(robot.plant, robot.plant_context, robot.instance, {})
    np.testing.assert_allclose(
        robot.pose_in_base(PALM_FRAME).translation(), [0.158, 0.078, 0.8255], atol=1e-3
    )
    hsr_set_positions(robot.plant, robot.plant_context, robot.instance, {"arm_lift_joint": 0.69})
    assert robot.pose_in_base(PALM_FRAME).translation()[2] == pytest.approx(1.5155, abs=1e-3)


def test_palm_pose_matches_numpy_fk(robot: Robot) -> None:
    for q in sample_arm_joints(36, np.random.default_rng(7)):
        hsr_set_positions(
            robot.plant, robot.plant_context, robot.instance, dict(zip(ARM_JOINTS, q, strict=True))
        )
        X_BP = robot.pose_in_base(PALM_FRAME)
        position, rotation = palm_pose(q)
        np.testing.assert_allclose(X_BP.translation(), position, atol=1e-3, err_msg=str(q))
        np.testing.assert_allclose(X_BP.rotation().matrix(), rotation, atol=1e-6, err_msg=str(q))


def test_camera_frame_looks_forward(robot: Robot) -> None:
    camera = robot.plant.GetFrameByName(CAMERA_FRAME, robot.instance)
    assert camera.body().name() == "head_tilt_link"
    X_TC = camera.GetFixedPoseInBodyFrame()
    np.testing.assert_allclose(X_TC.translation(), [-0.0798, 0.022, 0.2152], atol=1e-12)
    hsr_set_positions(robot.plant, robot.plant_context, robot.instance, {})
    R_BC = robot.pose_in_base(CAMERA_FRAME).rotation().matrix()
    # Drake camera frame: z forward, x right, y down.
    np.testing.assert_allclose(R_BC[:, 2], [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(R_BC[:, 0], [0, -1, 0], atol=1e-9)
    np.testing.assert_allclose(R_BC[:, 1], [0, 0, -1], atol=1e-9)


def test_mass_and_inertias_are_physical(robot: Robot) -> None:
    plant = robot.plant
    assert 35.0 <= plant.CalcTotalMass(robot.plant_context, [robot.instance]) <= 39.0
    for index in plant.GetBodyIndices(robot.instance):
        body = plant.get_body(index)
        M = body.default_spatial_inertia()
        assert M.get_mass() > 0, body.name()
        assert M.IsPhysicallyValid(), body.name()
        assert M.CalcRotationalInertia().CouldBePhysicallyValid(), body.name()


@pytest.mark.parametrize("posture", TYPICAL_POSTURES)
def test_no_self_collision_in_typical_postures(robot: Robot, posture: str) -> None:
    hsr_set_positions(robot.plant, robot.plant_context, robot.instance, TYPICAL_POSTURES[posture])
    scene_graph = robot.scene_graph
    query = scene_graph.get_query_output_port().Eval(
        scene_graph.GetMyContextFromRoot(robot.context)
    )
    inspector = query.inspector()
    pairs = [
        (inspector.GetName(pair.id_A), inspector.GetName(pair.id_B))
        for pair in query.ComputePointPairPenetration()
    ]
    assert not query.HasCollisions(), pairs


@pytest.mark.parametrize("time_step", [1e-3, 2e-3])
def test_torso_and_fingers_follow_their_mimic(time_step: float) -> None:
    command = {"arm_lift_joint": 0.3, "gripper": 0.08}
    robot = build_robot(time_step, command)
    simulator = start_simulation(robot, {})
    for t in np.linspace(0.1, 2.0, 20):
        simulator.AdvanceTo(t)
        # Coupled all along the motion, not only once settled.
        lift = robot.position("arm_lift_joint")
        assert robot.position("torso_lift_joint") == pytest.approx(0.5 * lift, abs=1e-4)
        left, right = robot.position(GRIPPER_JOINT), robot.position("hand_r_finger_joint")
        assert left == pytest.approx(right, abs=1e-5)
    assert robot.position("torso_lift_joint") == pytest.approx(0.15, abs=1e-3)
    assert left + right == pytest.approx(0.08, abs=1e-3)


@pytest.mark.parametrize("time_step", [1e-3, 2e-3])
def test_pd_holds_posture_under_gravity(time_step: float) -> None:
    robot = build_robot(time_step, ARM_FORWARD)
    q_arm = [ARM_FORWARD.get(name, 0.0) for name in ARM_JOINTS]
    expected = palm_pose(np.array(q_arm))[0]
    simulator = start_simulation(robot, ARM_FORWARD)
    # Measured from the unloaded start, so the drift includes the initial sag under gravity.
    start = robot.pose_in_base(PALM_FRAME).translation()
    for t in [0.5, 1.0, 2.0]:
        simulator.AdvanceTo(t)
        palm = robot.pose_in_base(PALM_FRAME).translation()
        assert np.linalg.norm(palm - expected) < 1e-3
    assert np.linalg.norm(palm - start) < 1e-3


def test_desired_state_layout(robot: Robot) -> None:
    plant, instance = robot.plant, robot.instance
    x_d = hsr_desired_state(plant, instance, {"arm_flex_joint": -1.0, "gripper": 0.1})
    names = [
        plant.get_joint_actuator(i).joint().name() for i in plant.GetJointActuatorIndices(instance)
    ]
    assert x_d.shape == (2 * len(names),)
    assert plant.get_desired_state_input_port(instance).size() == x_d.size
    q_d = dict(zip(names, x_d[: len(names)], strict=True))
    assert q_d["arm_flex_joint"] == -1.0
    assert q_d[GRIPPER_JOINT] == pytest.approx(0.05)
    assert sum(q_d.values()) == pytest.approx(-1.0 + 0.05)
    assert not np.any(x_d[len(names) :])
    assert GRIPPER_MAX_OPENING == pytest.approx(
        2 * plant.GetJointByName(GRIPPER_JOINT).position_upper_limits()[0]
    )


@pytest.mark.parametrize("name", ["elbow_joint", "torso_lift_joint"])
def test_desired_state_rejects_unknown_joint(robot: Robot, name: str) -> None:
    with pytest.raises(ValueError, match=name):
        hsr_desired_state(robot.plant, robot.instance, {name: 0.1})


def test_set_positions_keeps_couplings(robot: Robot) -> None:
    hsr_set_positions(
        robot.plant,
        robot.plant_context,
        robot.instance,
        {"arm_lift_joint": 0.4, "gripper": 0.1, "base_x_joint": 1.5},
    )
    assert robot.position("torso_lift_joint") == pytest.approx(0.2)
    assert robot.position("hand_r_finger_joint") == pytest.approx(0.05)
    assert robot.position(GRIPPER_JOINT) == pytest.approx(0.05)
    assert robot.position("base_x_joint") == pytest.approx(1.5)


def box_extents(robot: Robot, geometry: str, role: str) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corners, in the head_tilt_link frame, of the box ``geometry`` (visual or
    collision) on that link: the axis-aligned bounds of its eight corners."""
    plant, inspector = robot.plant, robot.scene_graph.model_inspector()
    body = plant.GetBodyByName("head_tilt_link", robot.instance)
    by_role = {
        "visual": plant.GetVisualGeometriesForBody,
        "collision": plant.GetCollisionGeometriesForBody,
    }
    ids = by_role[role](body)
    (found,) = [g for g in ids if inspector.GetName(g).endswith(f"::{geometry}_{role}")]
    shape = inspector.GetShape(found)
    assert isinstance(shape, Box)
    signs = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1)
    corners = inspector.GetPoseInFrame(found).multiply(0.5 * shape.size()[:, None] * signs)
    return corners.min(axis=1), corners.max(axis=1)


@pytest.mark.parametrize("role", ["visual", "collision"])
def test_sensor_bar_sits_on_head(robot: Robot, role: str) -> None:
    bar_low, bar_high = box_extents(robot, "sensor_bar", role)
    head_low, head_high = box_extents(robot, "head", role)
    # Touching or overlapping along every axis: the bar does not float above the head.
    assert np.all(bar_low <= head_high + 1e-9) and np.all(head_low <= bar_high + 1e-9)
    # It sits on top, and the camera's optical centre is inside the bar.
    assert bar_high[2] > head_high[2]
    camera = robot.plant.GetFrameByName(CAMERA_FRAME, robot.instance)
    origin = camera.GetFixedPoseInBodyFrame().translation()
    assert np.all(bar_low <= origin) and np.all(origin <= bar_high)
