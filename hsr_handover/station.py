"""Build the simulation Diagram from a Scenario (the `MakeHardwareStation` pattern).

The station holds the world: the HSR, the table, the objects, the person, the head camera and,
when given a Meshcat, the visualizer. The robot holds its start posture through its joint PD
controllers; the person follows its script through the HumanActor. Later layers (perception,
intent, the handover supervisor) connect to the exported ports.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.geometry import (
    LightParameter,
    MakeRenderEngineVtk,
    Meshcat,
    MeshcatVisualizer,
    MeshcatVisualizerParams,
    QueryObject,
    RenderEngineVtkParams,
    SceneGraph,
)
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from hsr_handover.camera import add_head_camera
from hsr_handover.hsr import (
    BASE_JOINTS,
    GRIPPER_JOINT,
    GRIPPER_MIMIC_JOINT,
    TORSO_JOINT,
    actuated_joint_names,
    add_hsr,
    hsr_desired_state,
)
from hsr_handover.human.behavior import Action, PostureTimeline, posture_changes
from hsr_handover.human.body import PERSON_JOINTS, BodyDimensions
from hsr_handover.scenario import Scenario, ScenarioError, object_center, resolve_model_path
from hsr_handover.scene.object_models import object_sdf
from hsr_handover.scene.person_model import person_sdf
from hsr_handover.scene.table_model import table_sdf
from hsr_handover.systems.human_actor import HumanActor

RENDERER = "vtk"


@dataclasses.dataclass
class Station:
    """The built world and handles into it; `diagram` exports the ports `build_station` lists."""

    diagram: Diagram
    plant: MultibodyPlant
    scene_graph: SceneGraph
    robot: ModelInstanceIndex
    person: ModelInstanceIndex
    table: ModelInstanceIndex
    objects: dict[str, ModelInstanceIndex]
    body: BodyDimensions
    scenario: Scenario


def person_pose(scenario: Scenario) -> RigidTransform:
    """Pose of the person frame (floor below the hips, facing +x) in the world."""
    x, y = scenario.person.position
    return RigidTransform(RollPitchYaw(0, 0, scenario.person.yaw), [x, y, 0.0])


def robot_start_positions(scenario: Scenario) -> dict[str, float]:
    """The robot's start configuration by actuated joint name: base pose plus the posture."""
    for name in scenario.robot.joints:
        if name in BASE_JOINTS:
            expected = "the base pose under robot.base_pose, not as a joint"
        elif name in (TORSO_JOINT, GRIPPER_MIMIC_JOINT):
            expected = "an actuated joint; this one follows its partner by mimic"
        else:
            continue
        raise ScenarioError(scenario.source, f"robot.joints.{name}", f"expected {expected}")
    x, y, yaw = scenario.robot.base_pose
    return {**dict(zip(BASE_JOINTS, (x, y, yaw), strict=True)), **scenario.robot.joints}


def _couple_default_positions(
    plant: MultibodyPlant, robot: ModelInstanceIndex, start: dict[str, float]
) -> None:
    """Start coupled joints consistent, or the mimic constraints snap them on the first step."""
    lift = start.get("arm_lift_joint", 0.0)
    plant.GetJointByName(TORSO_JOINT, robot).set_default_positions([0.5 * lift])
    finger = start.get(GRIPPER_JOINT, 0.0)
    plant.GetJointByName(GRIPPER_MIMIC_JOINT, robot).set_default_positions([finger])


def person_actions(scenario: Scenario) -> list[Action]:
    """The scenario's behaviour script with object names resolved to points in the person frame.

    The actor is part of the simulated world, so it may know where the objects really are.
    """
    to_person = person_pose(scenario).inverse()
    centers = {obj.name: object_center(scenario, obj) for obj in scenario.objects}
    actions = []
    for item in scenario.person.behavior:
        world_point = centers.get(item.target) if item.target else None
        if item.action == "reach_to":
            world_point = np.asarray(item.point, dtype=float)
        point = None if world_point is None else to_person @ world_point
        end = None if item.duration is None else item.start + item.duration
        actions.append(Action(item.action, item.start, end, point, item.arm))
    return actions


def _add_world(plant: MultibodyPlant, parser: Parser, scenario: Scenario, body: BodyDimensions):
    table = scenario.table
    table_instance = parser.AddModelsFromString(
        table_sdf(*table.size, table.height, table.thickness), "sdf"
    )[0]
    X_WT = RigidTransform(RollPitchYaw(0, 0, table.yaw), [*table.center, 0.0])
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("table", table_instance), X_WT)

    person = parser.AddModelsFromString(person_sdf(body), "sdf")[0]
    plant.WeldFrames(
        plant.world_frame(), plant.GetFrameByName("pelvis", person), person_pose(scenario)
    )
    # The person's muscles hold the limbs wherever the actor puts them; modelling the fight
    # against gravity would only add tracking lag nobody measures.
    plant.set_gravity_enabled(person, False)

    objects = {}
    for obj in scenario.objects:
        instance = parser.AddModelsFromString(
            object_sdf(obj.name, obj.shape, obj.size, obj.color, obj.mass), "sdf"
        )[0]
        pose = RigidTransform(RollPitchYaw(0, 0, obj.yaw), object_center(scenario, obj))
        plant.SetDefaultFloatingBaseBodyPose(plant.GetBodyByName(obj.name, instance), pose)
        objects[obj.name] = instance
    return table_instance, person, objects


def _set_default_positions(
    plant: MultibodyPlant,
    instance: ModelInstanceIndex,
    positions: dict[str, float],
    key: str,
    source: str,
) -> None:
    for name, value in positions.items():
        if not plant.HasJointNamed(name, instance):
            raise ScenarioError(source, f"{key}.{name}", "expected a joint name of the model")
        joint = plant.GetJointByName(name, instance)
        lower, upper = joint.position_lower_limits()[0], joint.position_upper_limits()[0]
        if not lower - 1e-9 <= value <= upper + 1e-9:
            raise ScenarioError(
                source, f"{key}.{name}", f"expected a value in [{lower:g}, {upper:g}], got {value}"
            )
        joint.set_default_positions([value])


def render_params() -> RenderEngineVtkParams:
    """Room lighting: a ceiling light plus a dim headlight. With the headlight alone, surfaces
    seen at grazing angles (the table top, the tops of objects) render nearly black."""
    ceiling = LightParameter(
        type="directional", frame="world", direction=[0.2, 0.1, -1.0], intensity=0.9
    )
    headlight = LightParameter(
        type="directional", frame="camera", direction=[0, 0, 1], intensity=0.45
    )
    return RenderEngineVtkParams(lights=[ceiling, headlight])


def build_station(scenario: Scenario, meshcat: Meshcat | None = None) -> Station:
    """Build the Diagram. Exported ports: outputs `robot_state`, `person_state`,
    `camera_color_image`, `camera_depth_image`, `camera_label_image`, `camera_pose`,
    `query_object`, `contact_results`; with perception enabled also those of
    `perception_wiring.PERCEPTION_OUTPUTS`."""
    builder = DiagramBuilder()
    config = MultibodyPlantConfig(
        time_step=scenario.simulation.time_step, discrete_contact_approximation="lagged"
    )
    plant, scene_graph = AddMultibodyPlant(config, builder)
    parser = Parser(plant)
    robot = add_hsr(plant, parser, resolve_model_path(scenario.robot.model, scenario.source))
    body = BodyDimensions.from_height(scenario.person.height, scenario.person.posture == "seated")
    table, person, objects = _add_world(plant, parser, scenario, body)
    start = robot_start_positions(scenario)
    _set_default_positions(plant, robot, start, "robot.joints", scenario.source)
    _couple_default_positions(plant, robot, start)
    timeline = PostureTimeline(posture_changes(body, person_actions(scenario)))
    rest, _ = timeline.evaluate(0.0)
    _set_default_positions(
        plant, person, dict(zip(PERSON_JOINTS, rest, strict=True)), "person", scenario.source
    )
    plant.Finalize()

    hold = builder.AddNamedSystem(
        "robot_hold_posture", ConstantVectorSource(hsr_desired_state(plant, robot, start))
    )
    builder.Connect(hold.get_output_port(), plant.get_desired_state_input_port(robot))
    actor = builder.AddNamedSystem(
        "human_actor", HumanActor(timeline, actuated_joint_names(plant, person))
    )
    builder.Connect(actor.get_output_port(), plant.get_desired_state_input_port(person))

    scene_graph.AddRenderer(RENDERER, MakeRenderEngineVtk(render_params()))
    cam = scenario.camera
    camera = add_head_camera(
        builder, plant, scene_graph, robot, cam.pinhole(), cam.depth_range, cam.rate_hz,
        cam.render_label, RENDERER,
    )  # fmt: skip
    for name in ("color_image", "depth_image", "label_image"):
        builder.ExportOutput(camera.GetOutputPort(name), f"camera_{name}")
    builder.ExportOutput(camera.GetOutputPort("camera_pose"), "camera_pose")
    builder.ExportOutput(plant.get_state_output_port(robot), "robot_state")
    builder.ExportOutput(plant.get_state_output_port(person), "person_state")
    builder.ExportOutput(scene_graph.get_query_output_port(), "query_object")
    builder.ExportOutput(plant.get_contact_results_output_port(), "contact_results")
    if scenario.perception.enabled:
        from hsr_handover.perception_wiring import add_perception

        add_perception(builder, plant, person, camera, scenario, meshcat)
    if meshcat is not None:
        params = MeshcatVisualizerParams(publish_period=1.0 / scenario.simulation.replay_fps)
        MeshcatVisualizer.AddToBuilder(builder, scene_graph, meshcat, params)
    diagram = builder.Build()
    diagram.set_name("hsr_handover_station")
    return Station(diagram, plant, scene_graph, robot, person, table, objects, body, scenario)


def check_initial_clearance(station: Station, tolerance: float = 1e-3) -> None:
    """Raise ScenarioError when the robot or the person starts intersecting the table (or each
    other) by more than `tolerance` m, as measured on the built scene's collision geometry."""
    plant, scenario = station.plant, station.scenario
    context = station.diagram.CreateDefaultContext()
    query: QueryObject = station.diagram.GetOutputPort("query_object").Eval(context)
    inspector = query.inspector()
    owners = {
        station.robot: ("robot.base_pose", "the robot"),
        station.person: ("person.position", "the person"),
        station.table: ("table.center", "the table"),
    }
    for pair in query.ComputePointPairPenetration():
        if pair.depth <= tolerance:
            continue
        instances = [
            plant.GetBodyFromFrameId(inspector.GetFrameId(geometry)).model_instance()
            for geometry in (pair.id_A, pair.id_B)
        ]
        named = [owners[i] for i in instances if i in owners]
        if len(named) == 2 and named[0] != named[1]:
            (key, who), (_, other) = sorted(named, key=lambda n: n[1] == "the table")
            raise ScenarioError(
                scenario.source,
                key,
                f"expected {who} clear of {other}; they intersect by {pair.depth * 100:.1f} cm",
            )
