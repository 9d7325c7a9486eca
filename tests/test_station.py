"""The station end to end: the head camera sees the table at its height, the person points
along the shoulder-to-object ray, the robot holds its posture and the objects stay put."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from hsr_handover.hsr import PALM_FRAME
from hsr_handover.scenario import load_scenario, object_center
from hsr_handover.station import build_station, check_initial_clearance
from tests.conftest import SCENARIOS

EXPORTED = (
    "camera_color_image", "camera_depth_image", "camera_label_image", "camera_pose",
    "robot_state", "person_state", "query_object", "contact_results",
)  # fmt: skip


def _frame_position(station, context, name: str, instance=None) -> np.ndarray:
    plant = station.plant
    frame = plant.GetFrameByName(name) if instance is None else plant.GetFrameByName(name, instance)
    return frame.CalcPoseInWorld(plant.GetMyContextFromRoot(context)).translation()


@pytest.fixture(scope="module")
def camera_view():
    """The demo scene a few frames in, at the camera's real resolution."""
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    station = build_station(scenario)
    simulator = Simulator(station.diagram)
    simulator.AdvanceTo(0.1)
    return station, simulator.get_context()


def test_station_exports_its_ports(camera_view):
    station, _ = camera_view
    names = {
        station.diagram.get_output_port(i).get_name()
        for i in range(station.diagram.num_output_ports())
    }
    assert set(EXPORTED) <= names


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
    station, context = camera_view
    diagram, table = station.diagram, station.scenario.table
    depth = diagram.GetOutputPort("camera_depth_image").Eval(context).data[:, :, 0]
    labels = diagram.GetOutputPort("camera_label_image").Eval(context).data[:, :, 0]
    X_WC = diagram.GetOutputPort("camera_pose").Eval(context)
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
    """point_left.yaml to mid-gesture; the camera is slowed because nothing here reads it."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.camera.rate_hz = 1.0
    station = build_station(scenario)
    simulator = Simulator(station.diagram)
    simulator.AdvanceTo(0.01)
    palm_start = _frame_position(station, simulator.get_context(), PALM_FRAME, station.robot)
    simulator.AdvanceTo(3.0)
    return station, simulator.get_context(), palm_start


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    cosine = a @ b / np.linalg.norm(a) / np.linalg.norm(b)
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


def test_pointing_wrist_lies_on_the_shoulder_to_object_ray(pointing_run):
    station, context, _ = pointing_run
    action = station.scenario.person.behavior[-1]
    target = next(o for o in station.scenario.objects if o.name == action.target)
    center = object_center(station.scenario, target)
    shoulder = _frame_position(station, context, "coco_r_shoulder")
    wrist = _frame_position(station, context, "coco_r_wrist")
    assert _angle_deg(wrist - shoulder, center - shoulder) < 5.0
    # And the other objects are clearly not the one pointed at.
    for other in station.scenario.objects:
        if other.name != target.name:
            assert (
                _angle_deg(wrist - shoulder, object_center(station.scenario, other) - shoulder) > 8
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
    assert _angle_deg(gaze, object_center(station.scenario, target) - eyes) < 5.0


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
