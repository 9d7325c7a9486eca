"""The station: the world alone on its ports (commands in, sensors and truth out), and end to end
with the robot: the head camera sees the table at its height, the person points along the
shoulder-to-object ray, the robot holds its posture and the objects stay put."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.systems.analysis import Simulator

from hsr_handover import interface
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.hsr import COMMANDED_JOINTS, PALM_FRAME
from hsr_handover.robot.builder import ready_command
from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.scenario import ImprecisionConfig, load_scenario, object_center
from hsr_handover.simulation import build_simulation
from hsr_handover.world.station import build_station, check_initial_clearance
from hsr_handover.world.station.hsr_interface import command_matrix, measurement_matrices
from tests.paths import SCENARIOS


def _frame_position(station, context, name: str, instance=None) -> np.ndarray:
    plant = station.plant
    frame = plant.GetFrameByName(name) if instance is None else plant.GetFrameByName(name, instance)
    return frame.CalcPoseInWorld(plant.GetMyContextFromRoot(context)).translation()


def _port_names(system, count, port) -> set[str]:
    return {port(i).get_name() for i in range(count)}


@pytest.fixture(scope="module")
def station_alone():
    """point_left.yaml's world with the camera slowed: nothing here reads images."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.camera.rate_hz = 1.0
    return build_station(scenario)


def test_station_exports_commands_sensors_and_truth_only(station_alone):
    diagram = station_alone.diagram
    inputs = _port_names(diagram, diagram.num_input_ports(), diagram.get_input_port)
    outputs = _port_names(diagram, diagram.num_output_ports(), diagram.get_output_port)
    assert inputs == set(interface.COMMANDS)
    assert outputs == set(interface.SENSORS) | set(interface.TRUTH)
    assert all(name.startswith(interface.TRUTH_PREFIX) for name in interface.TRUTH)
    assert not any(name.startswith(interface.TRUTH_PREFIX) for name in interface.SENSORS)
    # No controller inside: nothing but the command inputs drives the HSR's PD.
    assert not any("posture" in system.get_name() for system in diagram.GetSystems())


@pytest.mark.parametrize("missing", interface.COMMANDS)
def test_an_unconnected_command_fails_loudly(station_alone, missing):
    context = station_alone.diagram.CreateDefaultContext()
    state, opening = ready_command(station_alone.scenario)
    given = {interface.HSR_DESIRED_STATE: state, interface.GRIPPER_DESIRED_OPENING: [opening]}
    for name, value in given.items():
        if name != missing:
            station_alone.diagram.GetInputPort(name).FixValue(context, value)
    simulator = Simulator(station_alone.diagram, context)
    with pytest.raises(RuntimeError, match=f"input '{missing}' .* is not connected"):
        simulator.AdvanceTo(0.01)


def test_command_and_measurement_maps_are_inverse_on_the_commanded_joints(station_alone):
    plant, robot = station_alone.plant, station_alone.robot
    D = command_matrix(plant, robot)
    S, G = measurement_matrices(plant, robot)
    context = plant.CreateDefaultContext()
    n = len(COMMANDED_JOINTS)
    command = np.concatenate([np.linspace(0.1, 0.5, n), np.linspace(-0.2, 0.2, n), [0.08]])
    desired = D @ command
    # Put the plant where the PD would drive it: desired positions, velocities per actuator.
    for row, index in enumerate(plant.GetJointActuatorIndices(robot)):
        joint = plant.get_joint_actuator(index).joint()
        m = len(plant.GetJointActuatorIndices(robot))
        q, v = plant.GetPositions(context).copy(), plant.GetVelocities(context).copy()
        q[joint.position_start()], v[joint.velocity_start()] = desired[row], desired[m + row]
        plant.SetPositions(context, q)
        plant.SetVelocities(context, v)
    state = plant.GetPositionsAndVelocities(context, robot)
    np.testing.assert_allclose(S @ state, command[: 2 * n])
    np.testing.assert_allclose(G @ state, [0.08])


def test_the_hsr_follows_its_command_ports_and_reports_on_its_sensor_ports(station_alone):
    diagram = station_alone.diagram
    context = diagram.CreateDefaultContext()
    state, _ = ready_command(station_alone.scenario)
    n = len(COMMANDED_JOINTS)
    moved = {"head_pan_joint": 0.3, "arm_lift_joint": 0.1, "base_x_joint": 0.05}
    for name, value in moved.items():
        state[COMMANDED_JOINTS.index(name)] = value
    diagram.GetInputPort(interface.HSR_DESIRED_STATE).FixValue(context, state)
    diagram.GetInputPort(interface.GRIPPER_DESIRED_OPENING).FixValue(context, [0.08])
    simulator = Simulator(diagram, context)
    simulator.AdvanceTo(1.5)
    measured = diagram.GetOutputPort(interface.HSR_STATE_MEASURED).Eval(context)
    np.testing.assert_allclose(measured[:n], state[:n], atol=2e-3)
    opening = diagram.GetOutputPort(interface.GRIPPER_OPENING_MEASURED).Eval(context)
    assert opening[0] == pytest.approx(0.08, abs=2e-3)
    truth = diagram.GetOutputPort(interface.TRUTH_HSR_STATE).Eval(context)
    plant = station_alone.plant
    lift = plant.GetJointByName("arm_lift_joint").position_start()
    assert truth[lift] == pytest.approx(measured[COMMANDED_JOINTS.index("arm_lift_joint")])


def _station_output(simulation, context, name: str):
    return simulation.station.diagram.GetOutputPort(name).Eval(simulation.station_context(context))


@pytest.fixture(scope="module")
def camera_view():
    """The demo scene a few frames in, at the camera's real resolution, station and robot."""
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    simulation = build_simulation(scenario)
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(0.1)
    return simulation, simulator.get_context()


def _table_label(station) -> int:
    inspector = station.scene_graph.model_inspector()
    table_body = station.plant.GetBodyByName("table", station.table)
    labels = {
        int(inspector.GetPerceptionProperties(geometry).GetProperty("label", "id"))
        for geometry in station.plant.GetVisualGeometriesForBody(table_body)
    }
    assert len(labels) == 1
    return int(labels.pop())


def test_depth_image_shows_the_table_top_at_its_height(camera_view):
    simulation, context = camera_view
    station, table = simulation.station, simulation.station.scenario.table
    depth = _station_output(simulation, context, "camera_depth_image").data[:, :, 0]
    labels = _station_output(simulation, context, "truth_label_image").data[:, :, 0]
    X_WC = _station_output(simulation, context, "camera_pose")
    assert depth.shape == (station.scenario.camera.height, station.scenario.camera.width)
    mask = (labels == _table_label(station)) & np.isfinite(depth)
    camera = station.scenario.camera.pinhole()
    points = camera.deproject_image(depth, X_WC.GetAsMatrix4())[mask.ravel()]
    # Away from the edges, where the legs (same body, same label) show below the top.
    near_edge, far_edge = table.center[0] - table.size[0] / 2, table.center[0] + table.size[0] / 2
    on_top = points[(points[:, 0] > near_edge + 0.1) & (points[:, 0] < far_edge - 0.1)]
    assert len(on_top) > 5000
    assert abs(np.median(on_top[:, 2]) - table.height) < 0.01
    assert np.mean(np.abs(on_top[:, 2] - table.height) < 0.01) > 0.99


@pytest.fixture(scope="module")
def pointing_run():
    """point_left.yaml to mid-gesture with an exact person (no pointing error, the head turning
    all the way); the camera is slowed because nothing here reads it."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.person.imprecision = ImprecisionConfig(0.0, 1.0, 0.0)
    scenario.camera.rate_hz = 1.0
    simulation = build_simulation(scenario)
    station = simulation.station
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(0.01)
    palm_start = _frame_position(station, simulator.get_context(), PALM_FRAME, station.robot)
    simulator.AdvanceTo(3.0)
    return station, simulator.get_context(), palm_start


def test_pointing_wrist_lies_on_the_shoulder_to_object_ray(pointing_run):
    station, context, _ = pointing_run
    action = station.scenario.person.behavior[-1]
    target = next(o for o in station.scenario.objects if o.name == action.target)
    center = object_center(station.scenario, target)
    shoulder = _frame_position(station, context, "coco_r_shoulder")
    wrist = _frame_position(station, context, "coco_r_wrist")
    assert angle_deg(wrist - shoulder, center - shoulder) < 5.0
    # And the other objects are clearly not the one pointed at.
    for other in station.scenario.objects:
        if other.name != target.name:
            assert (
                angle_deg(wrist - shoulder, object_center(station.scenario, other) - shoulder) > 8
            )


def test_pointing_person_looks_at_the_object(pointing_run):
    station, context, _ = pointing_run
    plant = station.plant
    head = plant.GetBodyByName("head", station.person)
    X_WH = head.EvalPoseInWorld(plant.GetMyContextFromRoot(context))
    eyes = (
        _frame_position(station, context, "coco_r_eye")
        + _frame_position(station, context, "coco_l_eye")
    ) / 2
    target = next(o for o in station.scenario.objects if o.name == "red_cup")
    gaze = X_WH.rotation().matrix()[:, 0]
    assert angle_deg(gaze, object_center(station.scenario, target) - eyes) < 5.0


def test_robot_holds_posture_and_objects_rest(pointing_run):
    station, context, palm_start = pointing_run
    palm = _frame_position(station, context, PALM_FRAME, station.robot)
    assert np.linalg.norm(palm - palm_start) < 1e-3
    plant_context = station.plant.GetMyContextFromRoot(context)
    q = station.plant.GetPositions(plant_context, station.robot)
    lift = station.plant.GetJointByName("arm_lift_joint").get_translation(plant_context)
    torso = station.plant.GetJointByName("torso_lift_joint").get_translation(plant_context)
    assert abs(torso - 0.5 * lift) < 1e-4 and np.all(np.isfinite(q))
    for obj in station.scenario.objects:
        body = station.plant.GetBodyByName(obj.name)
        position = body.EvalPoseInWorld(plant_context).translation()
        assert np.linalg.norm(position - object_center(station.scenario, obj)) < 3e-3


def test_standing_person_has_adult_proportions_and_clears_the_table(write_scenario):
    def stand_tall(data):
        data["person"].update(posture="standing", height=1.85)

    scenario = load_scenario(write_scenario(stand_tall))
    station = build_station(scenario)
    check_initial_clearance(station)
    context = station.diagram.CreateDefaultContext()
    # Winter's ratios of height; the head is tilted at rest, so check the rigid trunk and legs.
    for frame, ratio in (
        ("coco_r_shoulder", 0.818),
        ("coco_r_knee", 0.285),
        ("coco_r_ankle", 0.039),
    ):
        height = _frame_position(station, context, frame)[2]
        assert height == pytest.approx(ratio * 1.85, abs=0.01), frame


def test_a_higher_seat_raises_the_seated_person_and_the_chair_with_it(write_scenario):
    """At a bar table a person sits on a bar stool: the seat's height lifts the whole seated
    body, and the stool under it, by the difference."""
    heights = {}
    for seat in (0.45, 0.65):

        def on_seat(data, seat=seat):
            data["person"].update(posture="seated", seat_height=seat)

        scenario = load_scenario(write_scenario(on_seat))
        station = build_station(scenario)
        context = station.diagram.CreateDefaultContext()
        inspector = station.scene_graph.model_inspector()
        stool = next(
            g
            for g in inspector.GetAllGeometryIds()
            if inspector.GetName(g) == "person::chair_seat_collision"
        )
        top = inspector.GetPoseInFrame(stool).translation()[2] + 0.02  # the box is 4 cm thick
        heights[seat] = (_frame_position(station, context, "coco_r_shoulder")[2], top)
    assert heights[0.65][0] - heights[0.45][0] == pytest.approx(0.20, abs=1e-9)
    assert heights[0.45][1] == pytest.approx(0.45, abs=1e-9)
    assert heights[0.65][1] == pytest.approx(0.65, abs=1e-9)


def test_a_dropped_object_lands_on_the_floor_and_the_hsr_still_drives(station_alone):
    diagram, plant = station_alone.diagram, station_alone.plant
    context = diagram.CreateDefaultContext()
    state, _ = ready_command(station_alone.scenario)
    state[COMMANDED_JOINTS.index("base_x_joint")] = -0.1  # the base slides over the floor
    diagram.GetInputPort(interface.HSR_DESIRED_STATE).FixValue(context, state)
    diagram.GetInputPort(interface.GRIPPER_DESIRED_OPENING).FixValue(context, [0.08])
    plant_context = plant.GetMyMutableContextFromRoot(context)
    name, instance = next(iter(station_alone.objects.items()))
    cup = plant.GetBodyByName(name, instance)
    plant.SetFreeBodyPose(plant_context, cup, RigidTransform([-1.0, 1.0, 0.5]))
    Simulator(diagram, context).AdvanceTo(1.5)
    height = station_alone.scenario.objects[0].size[-1]
    assert cup.EvalPoseInWorld(plant_context).translation()[2] == pytest.approx(
        height / 2, abs=0.01
    )
    measured = diagram.GetOutputPort(interface.HSR_STATE_MEASURED).Eval(context)
    assert measured[COMMANDED_JOINTS.index("base_x_joint")] == pytest.approx(-0.1, abs=2e-3)


def test_a_seated_person_points_over_a_high_tables_edge_from_close_by():
    """At a 0.80 m table, forearms resting level put the hands under its top, the fingertips a
    centimetre from its edge: the arm swung out into the edge and never pointed (the staggered
    layout's trials 39 and 43 of seed 1). The hands rest over the top instead, and the arm
    points at the cup."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.table.height = 0.80
    scenario.person.position = [1.65, 0.0]  # fingertips resting level would touch the edge
    scenario.person.imprecision = ImprecisionConfig(0.0, 1.0, 0.0)
    scenario.camera.rate_hz = 1.0
    sit_clear(scenario)
    simulation = build_simulation(scenario)
    station = simulation.station
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(3.0)
    context = simulator.get_context()
    target = next(o for o in scenario.objects if o.name == "red_cup")
    shoulder = _frame_position(station, context, "coco_r_shoulder")
    wrist = _frame_position(station, context, "coco_r_wrist")
    assert angle_deg(wrist - shoulder, object_center(scenario, target) - shoulder) < 5.0
