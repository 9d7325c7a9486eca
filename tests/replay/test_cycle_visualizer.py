"""CycleVisualizer on its own ports: the rays, the target, the plan's path, maps and point
drawn in Meshcat and keyframed in the replay where they change."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import Meshcat
from pydrake.systems.analysis import Simulator

from hsr_handover.replay.cycle_visualizer import CYCLE, RAY_LENGTH, CycleVisualizer
from hsr_handover.replay.meshcat_replay import make_local_meshcat, start_recording
from hsr_handover.robot.handover.plan_view import PlanView
from hsr_handover.robot.intent import IntentState
from hsr_handover.robot.intent.rays import Ray
from hsr_handover.robot.perception.object_detection import Detection, DetectionResult
from tests.meshcat_html import animation_keys, meshcat_commands, replay_commands, visibility_keys

FPS = 20.0
BOX = np.array([0.8, 0.0, 0.78])
POINTING = Ray(np.array([1.5, 0.0, 1.2]), np.array([-1.0, 0.0, 0.0]))
NODES = np.array([[1.0, 0.0, 1.0], [1.1, 0.0, 1.0], [1.2, 0.0, 1.0], [1.3, 0.0, 1.0]])
CARRY = PlanView(
    palm_path=np.linspace([0.8, 0.0, 0.9], [1.2, 0.1, 1.0], 12),
    arm_nodes=NODES,
    mutual=np.array([False, True, True, False]),
    person_nodes=NODES[1:] + [0.3, 0.0, 0.0],
    handover_point=np.array([1.15, 0.0, 1.0]),
)


@pytest.fixture
def meshcat() -> Meshcat:
    return make_local_meshcat()


class Run:
    """The visualizer simulated alone, its inputs fixed between advances."""

    def __init__(self, meshcat: Meshcat):
        self.visualizer = CycleVisualizer(meshcat)
        self.context = self.visualizer.CreateDefaultContext()
        start_recording(meshcat, FPS)
        self.set(IntentState(), (None, None), DetectionResult((), "none"), PlanView())
        self.simulator = Simulator(self.visualizer, self.context)
        self.simulator.Initialize()

    def set(self, intent, rays, detections, view) -> None:
        for name, value in (("intent", intent), ("intent_rays", rays),
                            ("detections", detections), ("plan_view", view)):  # fmt: skip
            self.visualizer.GetInputPort(name).FixValue(self.context, value)

    def advance(self, time: float) -> None:
        self.simulator.AdvanceTo(time)


def _box_seen() -> DetectionResult:
    detection = Detection("yellow", "yellow", (0, 0, 9, 9), (5.0, 5.0), BOX, 80)
    return DetectionResult((detection,), "ok")


def test_the_pointing_ray_shows_while_seen_along_the_ray(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.advance(0.45)
    run.set(IntentState(), (POINTING, None), DetectionResult((), "none"), PlanView())
    run.advance(1.05)
    run.set(IntentState(), (None, None), DetectionResult((), "none"), PlanView())
    run.advance(1.5)
    commands = replay_commands(meshcat, tmp_path)
    visible = visibility_keys(commands)
    assert visible[f"{CYCLE}/pointing_ray"] == [(0.0, False), (0.5, True), (1.1, False)]
    assert visible[f"{CYCLE}/gaze_ray"] == [(0.0, False)]
    positions = animation_keys(commands, ".position")[f"{CYCLE}/pointing_ray"]
    middle = POINTING.origin + RAY_LENGTH / 2 * POINTING.direction
    assert positions and all(np.allclose(value, middle) for _, value in positions)


def test_the_recognised_target_is_marked_where_the_camera_sees_it(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.set(IntentState(), (None, None), _box_seen(), PlanView())
    run.advance(0.45)  # seen, not yet asked for
    run.set(IntentState(target="yellow"), (None, None), _box_seen(), PlanView())
    run.advance(1.0)
    commands = replay_commands(meshcat, tmp_path)
    assert visibility_keys(commands)[f"{CYCLE}/target"] == [(0.0, False), (0.5, True)]
    positions = animation_keys(commands, ".position")[f"{CYCLE}/target"]
    assert np.allclose(positions[-1][1], BOX)


def test_a_carry_plan_draws_the_maps_the_mutual_area_and_the_point(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.advance(0.45)
    run.set(IntentState(), (None, None), DetectionResult((), "none"), CARRY)
    run.advance(1.0)
    follow = PlanView(palm_path=np.linspace([1.2, 0.1, 1.0], [1.25, 0.1, 1.0], 5))
    run.set(IntentState(), (None, None), DetectionResult((), "none"), CARRY.updated(follow))
    run.advance(1.5)
    commands = replay_commands(meshcat, tmp_path)
    objects = {c["path"]: c for c in commands if c["type"] == "set_object"}
    counts = {name: _points(objects[f"{CYCLE}/{name}/0000"])
              for name in ("arm_map", "mutual_area", "person_range")}  # fmt: skip
    assert counts == {"arm_map": 2, "mutual_area": 2, "person_range": 3}
    assert f"{CYCLE}/mutual_area/0001" not in objects  # a follow keeps the handover's maps
    visible = visibility_keys(commands)
    assert visible[f"{CYCLE}/palm_path/0000"] == [(0.0, False), (0.5, True), (1.1, False)]
    assert visible[f"{CYCLE}/palm_path/0001"] == [(0.0, False), (1.1, True)]
    assert visible[f"{CYCLE}/mutual_area/0000"] == [(0.0, False), (0.5, True)]
    assert visible[f"{CYCLE}/handover_point"] == [(0.0, False), (0.5, True)]
    point = animation_keys(commands, ".position")[f"{CYCLE}/handover_point"]
    assert np.allclose(point[-1][1], CARRY.handover_point)


def test_rejects_a_period_that_is_not_positive(meshcat):
    with pytest.raises(ValueError, match="publish_period"):
        CycleVisualizer(meshcat, publish_period=0.0)


def _points(command: dict) -> int:
    """The points in a drawn cloud (its positions are packed float32 triples)."""
    packed = command["object"]["geometries"][0]["data"]["attributes"]["position"]["array"]
    return len(packed.data) // 12


def test_meshcat_commands_helper_reads_this_module_s_objects(meshcat):
    Run(meshcat)
    paths = {c.get("path") for c in meshcat_commands(meshcat.StaticHtml())}
    assert {f"{CYCLE}/pointing_ray", f"{CYCLE}/target", f"{CYCLE}/handover_point"} <= paths
