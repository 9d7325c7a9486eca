"""The robot's perception beside the station, end to end: its percepts of a rendered scene."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS
from hsr_handover.replay.overlays import SCENE_MAP
from hsr_handover.robot.perception_wiring import PERCEPTION_OUTPUTS
from hsr_handover.scenario import load_scenario, object_center
from hsr_handover.simulation import build_simulation
from tests.meshcat_html import meshcat_commands
from tests.paths import SCENARIOS


def _perceive(scenario, until: float):
    simulation = build_simulation(scenario)
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(until)
    robot, context = simulation.robot.diagram, simulation.robot_context(simulator.get_context())
    percepts = {name: robot.GetOutputPort(name).Eval(context) for name in PERCEPTION_OUTPUTS}
    plant = simulation.station.plant
    plant_context = plant.GetMyContextFromRoot(simulator.get_context())
    true_keypoints = {
        name: plant.GetFrameByName(f"coco_{name}").CalcPoseInWorld(plant_context).translation()
        for name in COCO18_KEYPOINTS
    }
    station_context = simulation.station_context(simulator.get_context())
    camera = simulation.station.diagram.GetOutputPort("camera_pose").Eval(station_context)
    true_keypoints["camera"] = camera.translation()
    return simulation.station, percepts, true_keypoints


@pytest.fixture(scope="module")
def watching_the_face():
    """attention_shift.yaml half a second after the focus moved to the face."""
    return _perceive(load_scenario(SCENARIOS / "attention_shift.yaml"), 2.5)


def test_the_map_the_detections_and_the_skeleton_come_from_the_camera(watching_the_face):
    station, percepts, _ = watching_the_face
    report, graph = percepts["gng_frame_report"], percepts["gng_graph"]
    assert report.status == "ok" and report.n_points > 5000
    assert 50 <= len(graph.nodes) <= station.scenario.perception.gng.max_nodes
    assert report.quantisation_error < 0.06
    labels = {d.label: d.center for d in percepts["detections"].detections}
    for obj in station.scenario.objects:
        assert np.linalg.norm(labels[obj.color] - object_center(station.scenario, obj)) < 0.015
    support = {entry.label: entry for entry in percepts["detection_support"]}
    assert all(support[obj.color].confirmed for obj in station.scenario.objects)
    skeleton = percepts["skeleton"]
    assert skeleton.status == "ok" and (skeleton.confidence > 0).sum() >= 8


def test_attention_is_on_the_perceived_face(watching_the_face):
    station, percepts, _ = watching_the_face
    (region,) = percepts["attention"]
    nose = station.plant.GetFrameByName("coco_nose").CalcPoseInWorld(
        station.plant.CreateDefaultContext()
    )
    assert region.name == "face"
    assert np.linalg.norm(region.center - nose.translation()) < 0.2
    nodes_near_face = region.contains(percepts["gng_graph"].nodes).sum()
    assert nodes_near_face >= 8  # attention gathers nodes there within half a second


def test_camera_facing_away_degrades_to_empty_percepts_that_say_why(write_scenario):
    def look_away(data):
        data["robot"]["base_pose"] = [0.0, 0.0, 3.14159]
        data["perception"] = {"enabled": True, "attention": [{"start": 0.0, "focus": "face"}]}

    _, percepts, _ = _perceive(load_scenario(write_scenario(look_away)), 0.3)
    assert percepts["detections"].detections == () and percepts["detections"].status != "ok"
    assert percepts["skeleton"].status == "person not in view"
    assert percepts["attention"] == ()
    assert percepts["gng_frame_report"].status in ("no points in the workspace", "ok")


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="the hand phase's density ratio is 2.3 with the robot's own view (active gaze); "
    "4.3 was measured from a hand-set head tilted 0.1 rad down: nodes per m^2 of observed "
    "surface depend on what else the view holds (README, 'Active perception')",
)
def test_attention_experiment_meets_the_papers_figures(tmp_path):
    """The CLI's attention experiment on the bundled scenario (paper figs. 9-12)."""
    outputs = {name: tmp_path / f"attention.{name}" for name in ("png", "csv", "json", "html")}
    result = subprocess.run(
        [sys.executable, "-m", "hsr_handover.cli", "attention",
         str(SCENARIOS / "attention_shift.yaml"), "--plot", str(outputs["png"]),
         "--csv", str(outputs["csv"]), "--json", str(outputs["json"]),
         "--html", str(outputs["html"])],
        capture_output=True, text=True, timeout=900, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    summary = json.loads(outputs["json"].read_text())
    assert summary["density_ratio"] >= 4.0  # the paper's figure: about 4x
    assert summary["region_settle_time_s"] <= 0.5  # the map follows attention within 0.5 s
    assert summary["settle_time_s"] <= 1.5  # the node count (target 1 s; 0.5-1.0 s over seeds)
    for phase in summary["phases"][1:]:
        assert phase["attention_gain"] > 2.5, phase["focus"]
    assert len(outputs["csv"].read_text().splitlines()) > 200
    assert outputs["png"].stat().st_size > 20_000
    commands = meshcat_commands(outputs["html"].read_bytes())
    (animation,) = [c for c in commands if c.get("type") == "set_animation"]
    assert any(e["path"].startswith(f"{SCENE_MAP.path}/") for e in animation["animations"])


def test_the_table_is_fitted_to_the_point_clouds(watching_the_face):
    """The planning scene's table: top height within 1 cm, extent within 3 cm."""
    station, percepts, _ = watching_the_face
    report, table = percepts["table"], station.scenario.table
    assert report.status == "ok" and report.frames >= 10
    estimate = report.estimate
    assert abs(estimate.height - table.height) < 0.01
    true_size = np.asarray(table.size)
    flipped = abs(math.cos(estimate.yaw - table.yaw)) < 0.5  # its long side along the table's y
    assert np.all(np.abs(estimate.size - (true_size[::-1] if flipped else true_size)) < 0.03)
    assert np.linalg.norm(estimate.center - table.center) < 0.03


def test_the_planning_scene_matches_the_true_scene(watching_the_face):
    """The planning scene from percepts: each object where it stands, of its size; each
    of the person's true joints inside the capsules or hidden behind them from the camera (an
    elbow behind its own forearm on the table is lifted onto the forearm's top, 24 cm short)."""
    station, percepts, truth = watching_the_face
    scene = percepts["perceived_scene"]
    scenario = station.scenario
    for obj in scenario.objects:
        shape = scene.object_named(obj.color)
        true_center = object_center(scenario, obj)
        assert np.linalg.norm(shape.center - true_center[:2]) < 0.01, obj.color
        true_top = 2 * true_center[2] - scenario.table.height
        assert abs(shape.bottom + shape.height - true_top) < 0.01, obj.color
    for name in ("nose", "neck", "r_shoulder", "r_elbow", "r_wrist", "l_elbow", "l_wrist"):
        sight = np.linspace(truth["camera"], truth[name], 200)
        covered = min(np.min(capsule.distance(sight[100:])) for capsule in scene.person)
        assert covered < 0, name
