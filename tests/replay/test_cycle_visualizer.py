"""CycleVisualizer on its own ports: the rays while the robot watches, the target where seen
or in the hand holding it, the plan's path, maps and point, drawn in Meshcat and keyframed in
the replay where they change, on children of the overlays the user switches."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import Meshcat
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.analysis import Simulator

from hsr_handover.hsr import COMMANDED_JOINTS, PALM_FRAME, add_hsr, hsr_set_positions
from hsr_handover.replay.cycle_visualizer import RAY_LENGTH, CycleVisualizer, pads_in_world
from hsr_handover.replay.meshcat_replay import make_local_meshcat, start_recording
from hsr_handover.replay.overlays import (
    ARM_MAP,
    CATALOGUE,
    GAZE_RAY,
    HANDOVER_POINT,
    MUTUAL_AREA,
    PALM_PATH,
    PERSON_RANGE,
    POINTING_RAY,
    TARGET,
)
from hsr_handover.robot.handover.cycle_types import CycleRecord, Phase
from hsr_handover.robot.intent import IntentState
from hsr_handover.robot.intent.rays import Ray
from hsr_handover.robot.perception.object_detection import Detection, DetectionResult
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.plan_view import PlanView
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
NONE_SEEN = DetectionResult((), "none")
# The arm out over the table from a base moved and turned: [q; v] of COMMANDED_JOINTS.
REACHING = dict(
    zip(COMMANDED_JOINTS, (0.3, 0.1, 0.4, 0.2, -0.8, 0.3, -0.6, 0.5, 0.1, -0.3), strict=True)
)
COMMAND = np.concatenate([[REACHING[joint] for joint in COMMANDED_JOINTS], np.zeros(10)])


@pytest.fixture
def meshcat() -> Meshcat:
    return make_local_meshcat()


class Run:
    """The visualizer simulated alone, its inputs fixed between advances."""

    def __init__(self, meshcat: Meshcat):
        self.visualizer = CycleVisualizer(meshcat)
        self.context = self.visualizer.CreateDefaultContext()
        start_recording(meshcat, FPS)
        self.set(IntentState(), (None, None), NONE_SEEN, PlanView())
        self.simulator = Simulator(self.visualizer, self.context)
        self.simulator.Initialize()

    def set(self, intent, rays, detections, view) -> None:
        for name, value in (("intent", intent), ("intent_rays", rays),
                            ("detections", detections), ("plan_view", view)):  # fmt: skip
            self.visualizer.GetInputPort(name).FixValue(self.context, value)

    def act(self, phase: Phase, target: str = "yellow", command=COMMAND, watching=False) -> None:
        """The robot's cycle in `phase` fetching `target`, its arm commanded to `command`."""
        self.visualizer.GetInputPort("cycle").FixValue(
            self.context, CycleRecord(phase=phase, target=target)
        )
        self.visualizer.GetInputPort("hsr_desired_state").FixValue(self.context, command)
        self.visualizer.GetInputPort("watching").FixValue(self.context, [float(watching)])

    def advance(self, time: float) -> None:
        self.simulator.AdvanceTo(time)


def _box_seen(centre: np.ndarray = BOX) -> DetectionResult:
    detection = Detection("yellow", "yellow", (0, 0, 9, 9), (5.0, 5.0), centre, 80)
    return DetectionResult((detection,), "ok")


def test_the_pointing_ray_shows_while_seen_along_the_ray(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.advance(0.45)
    run.set(IntentState(), (POINTING, None), NONE_SEEN, PlanView())
    run.advance(1.05)
    run.set(IntentState(), (None, None), NONE_SEEN, PlanView())
    run.advance(1.5)
    commands = replay_commands(meshcat, tmp_path)
    visible = visibility_keys(commands)
    assert visible[POINTING_RAY.mark] == [(0.0, False), (0.5, True), (1.1, False)]
    assert visible[GAZE_RAY.mark] == [(0.0, False)]
    positions = animation_keys(commands, ".position")[POINTING_RAY.mark]
    middle = POINTING.origin + RAY_LENGTH / 2 * POINTING.direction
    assert positions and all(np.allclose(value, middle) for _, value in positions)


def test_the_rays_hide_once_the_intent_estimator_rests(meshcat, tmp_path: Path):
    """Its last rays stay on its output while it rests: they are no longer measured."""
    run = Run(meshcat)
    run.set(IntentState(), (POINTING, POINTING), NONE_SEEN, PlanView())
    run.act(Phase.WATCH, target=None, watching=True)
    run.advance(0.45)
    run.act(Phase.APPROACH, watching=False)  # the same rays on the port, now stale
    run.advance(1.0)
    visible = visibility_keys(replay_commands(meshcat, tmp_path))
    shown = [(0.0, False), (0.1, True), (0.5, False)]  # hidden until the first publish
    assert visible[POINTING_RAY.mark] == shown and visible[GAZE_RAY.mark] == shown


def test_the_recognised_target_is_marked_where_the_camera_sees_it(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.set(IntentState(), (None, None), _box_seen(), PlanView())
    run.advance(0.45)  # seen, not yet asked for
    run.set(IntentState(target="yellow"), (None, None), _box_seen(), PlanView())
    run.advance(1.0)
    commands = replay_commands(meshcat, tmp_path)
    assert visibility_keys(commands)[TARGET.mark] == [(0.0, False), (0.5, True)]
    positions = animation_keys(commands, ".position")[TARGET.mark]
    assert np.allclose(positions[-1][1], BOX)


def test_the_target_stays_where_last_seen_while_it_is_on_the_table(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.set(IntentState(target="yellow"), (None, None), _box_seen(), PlanView())
    run.act(Phase.APPROACH)
    run.advance(0.45)
    run.set(IntentState(target="yellow"), (None, None), NONE_SEEN, PlanView())  # looked away
    run.advance(1.0)
    commands = replay_commands(meshcat, tmp_path)
    assert visibility_keys(commands)[TARGET.mark] == [(0.0, False), (0.1, True)]
    assert all(np.allclose(p, BOX) for _, p in animation_keys(commands, ".position")[TARGET.mark])


def test_the_held_target_follows_the_commanded_hand_not_its_detection(meshcat, tmp_path: Path):
    """While held, the robot believes the object is between its pads; the camera sees it
    partly hidden by the fingers, off its centre."""
    run = Run(meshcat)
    run.set(IntentState(target="yellow"), (None, None), _box_seen(BOX + 0.05), PlanView())
    run.act(Phase.CARRY)
    run.advance(0.45)
    command = COMMAND.copy()
    command[COMMANDED_JOINTS.index("base_x_joint")] += 0.2
    run.act(Phase.CARRY, command=command)
    run.advance(1.0)
    commands = replay_commands(meshcat, tmp_path)
    assert visibility_keys(commands)[TARGET.mark] == [(0.0, False), (0.1, True)]
    positions = dict(animation_keys(commands, ".position")[TARGET.mark])
    np.testing.assert_allclose(positions[0.4], pads_in_world(COMMAND), atol=1e-9)
    np.testing.assert_allclose(positions[1.0], pads_in_world(command), atol=1e-9)


def test_after_the_handover_the_target_shows_only_where_seen(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.set(IntentState(target="yellow"), (None, None), NONE_SEEN, PlanView())
    run.act(Phase.PRESENT)
    run.advance(0.45)
    run.act(Phase.RETREAT)  # let go: the person has it, unseen
    run.advance(1.05)
    run.set(IntentState(target="yellow"), (None, None), _box_seen(), PlanView())
    run.advance(1.5)
    commands = replay_commands(meshcat, tmp_path)
    keys = [(0.0, False), (0.1, True), (0.5, False), (1.1, True)]
    assert visibility_keys(commands)[TARGET.mark] == keys
    assert np.allclose(animation_keys(commands, ".position")[TARGET.mark][-1][1], BOX)


def test_pads_in_world_is_where_the_model_puts_the_pads():
    plant = MultibodyPlant(0.0)
    robot = add_hsr(plant, Parser(plant))
    plant.Finalize()
    context = plant.CreateDefaultContext()
    hsr_set_positions(plant, context, robot, REACHING)
    palm = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(PALM_FRAME, robot))
    np.testing.assert_allclose(pads_in_world(COMMAND), palm.multiply([0, 0, PAD_OFFSET]), atol=2e-3)


def test_a_carry_plan_draws_the_maps_the_mutual_area_and_the_point(meshcat, tmp_path: Path):
    run = Run(meshcat)
    run.advance(0.45)
    run.set(IntentState(), (None, None), NONE_SEEN, CARRY)
    run.advance(1.0)
    follow = PlanView(palm_path=np.linspace([1.2, 0.1, 1.0], [1.25, 0.1, 1.0], 5))
    run.set(IntentState(), (None, None), NONE_SEEN, CARRY.updated(follow))
    run.advance(1.5)
    commands = replay_commands(meshcat, tmp_path)
    objects = {c["path"]: c for c in commands if c["type"] == "set_object"}
    counts = {o.name: _points(objects[f"{o.path}/0000"])
              for o in (ARM_MAP, MUTUAL_AREA, PERSON_RANGE)}  # fmt: skip
    assert counts == {"arm_map": 2, "mutual_area": 2, "person_range": 3}
    assert f"{MUTUAL_AREA.path}/0001" not in objects  # a follow keeps the handover's maps
    visible = visibility_keys(commands)
    assert visible[f"{PALM_PATH.path}/0000"] == [(0.0, False), (0.5, True), (1.1, False)]
    assert visible[f"{PALM_PATH.path}/0001"] == [(0.0, False), (1.1, True)]
    assert visible[f"{MUTUAL_AREA.path}/0000"] == [(0.0, False), (0.5, True)]
    assert visible[HANDOVER_POINT.mark] == [(0.0, False), (0.5, True)]
    point = animation_keys(commands, ".position")[HANDOVER_POINT.mark]
    assert np.allclose(point[-1][1], CARRY.handover_point)


def test_only_children_are_animated_so_the_users_tick_holds(meshcat, tmp_path: Path):
    """The viewer's controls switch an overlay's own path: the recording never sets it."""
    run = Run(meshcat)
    run.set(IntentState(target="yellow"), (POINTING, POINTING), _box_seen(), CARRY)
    run.act(Phase.CARRY, watching=True)
    run.advance(0.45)
    run.set(IntentState(target="yellow"), (None, None), NONE_SEEN, PlanView())
    run.act(Phase.RETREAT)
    run.advance(1.0)
    commands = replay_commands(meshcat, tmp_path)
    parents = {overlay.path for overlay in CATALOGUE}
    animated = {
        path for track in (".visible", ".position") for path in animation_keys(commands, track)
    }
    assert animated and all(path.rsplit("/", 1)[0] in parents for path in animated)
    set_visible = {c["path"] for c in commands
                   if c["type"] == "set_property" and c["property"] == "visible"}  # fmt: skip
    assert not set_visible & parents


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
    assert {POINTING_RAY.mark, TARGET.mark, HANDOVER_POINT.mark} <= paths
