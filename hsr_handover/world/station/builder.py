"""Build the station from a Scenario: the world only (the `MakeHardwareStation` pattern).

The station holds the plant and scene graph (the HSR, the table, the objects, the person), the
person's actor, the head camera and the simulated pose detector, and, when given a Meshcat, the
visualizer. It holds no controller: the HSR follows whatever arrives on its command inputs.
Ports, by the names in `hsr_handover.interface`:

- inputs `hsr_desired_state`, `gripper_desired_opening` (no defaults: connect them);
- sensor outputs `hsr_state_measured`, `gripper_opening_measured`, `camera_color_image`,
  `camera_depth_image`, `camera_pose`, `camera_info`, `camera_image_time`,
  `skeleton_keypoints`;
- ground truth, for scoring and the person's own behaviour only: `truth_body_poses`,
  `truth_contact_results`, `truth_person_state`, `truth_hsr_state`, `truth_query_object`,
  `truth_label_image`.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import (
    Meshcat,
    MeshcatVisualizer,
    MeshcatVisualizerParams,
    QueryObject,
    SceneGraph,
)
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import ConstantValueSource

from hsr_handover import interface
from hsr_handover.hsr import GRIPPER_CAPSULES, actuated_joint_names, add_hsr
from hsr_handover.interface.camera_info import to_camera_info
from hsr_handover.scenario import (
    Scenario,
    ScenarioError,
    resolve_model_path,
    robot_start_positions,
)
from hsr_handover.world.person.behavior import PostureTimeline, posture_changes
from hsr_handover.world.person.body import PERSON_JOINTS, BodyDimensions
from hsr_handover.world.person.correcting import Corrector
from hsr_handover.world.person.receiving import Receiver
from hsr_handover.world.person.repeating import Repeater
from hsr_handover.world.station.camera import add_head_camera
from hsr_handover.world.station.hsr_interface import add_hsr_interface
from hsr_handover.world.station.recorded_skeleton import add_recorded_skeleton
from hsr_handover.world.station.world import (
    CORRECTION_STREAM,
    REPEAT_STREAM,
    add_floor,
    add_world,
    couple_default_positions,
    floor_filter,
    last_request,
    person_actions,
    person_pose,
    render_params,
    request_again,
    set_default_positions,
    wanted_object,
)
from hsr_handover.world.systems.hand_grip import GrippedBody, HandGrip
from hsr_handover.world.systems.head_camera import HeadCamera
from hsr_handover.world.systems.human_actor import HumanActor, WorldBodies
from hsr_handover.world.systems.skeleton_sensor import SkeletonSensor

RENDERER = "vtk"


@dataclasses.dataclass
class Station:
    """The built world and handles into it; `diagram` exports the ports listed above."""

    diagram: Diagram
    plant: MultibodyPlant
    scene_graph: SceneGraph
    robot: ModelInstanceIndex
    person: ModelInstanceIndex
    table: ModelInstanceIndex
    objects: dict[str, ModelInstanceIndex]
    body: BodyDimensions
    scenario: Scenario


def _add_plant(builder: DiagramBuilder, scenario: Scenario):
    config = MultibodyPlantConfig(
        time_step=scenario.simulation.time_step, discrete_contact_approximation="lagged"
    )
    plant, scene_graph = AddMultibodyPlant(config, builder)
    parser = Parser(plant)
    robot = add_hsr(plant, parser, resolve_model_path(scenario.robot.model, scenario.source))
    body = scenario.person.body()
    table, person, objects = add_world(plant, parser, scenario, body)
    floor = add_floor(plant)
    start = robot_start_positions(scenario)
    set_default_positions(plant, robot, start, "robot.joints", scenario.source)
    couple_default_positions(plant, robot, start)
    return plant, scene_graph, robot, body, table, person, objects, floor


def _person_timeline(
    plant: MultibodyPlant, person: ModelInstanceIndex, body: BodyDimensions, scenario: Scenario
) -> PostureTimeline:
    """The person's script as a posture timeline; sets the person's default posture to its
    start, so call it before Finalize."""
    actions = person_actions(scenario, body)
    timeline = PostureTimeline(posture_changes(body, actions, scenario.table.height))
    rest, _ = timeline.evaluate(0.0)
    set_default_positions(
        plant, person, dict(zip(PERSON_JOINTS, rest, strict=True)), "person", scenario.source
    )
    return timeline


def _add_person(builder, plant, robot, person, objects, body, timeline, scenario) -> None:
    """The person's actor (the script, and taking what the robot holds out) and the hand's
    grip on what it takes."""
    params = scenario.person.receiving.params()
    hands = {arm: plant.GetBodyByName(f"{arm[0]}_hand", person) for arm in ("right", "left")}
    bodies = {name: _gripped_body(plant, instance) for name, instance in objects.items()}
    world = _world_bodies(plant, robot, hands, objects, bodies, body.hand / 2, scenario)
    wanted = wanted_object(scenario)
    actor = builder.AddNamedSystem(
        "human_actor",
        HumanActor(
            timeline,
            actuated_joint_names(plant, person),
            Receiver(body, params, scenario.table.height, wanted),
            world,
            _corrector(body, scenario, wanted) if params.corrects else None,
            _repeater(body, scenario) if params.repeats else None,
        ),
    )
    builder.Connect(
        actor.GetOutputPort("person_desired_state"), plant.get_desired_state_input_port(person)
    )
    builder.Connect(plant.get_body_poses_output_port(), actor.GetInputPort("body_poses"))
    builder.Connect(plant.get_contact_results_output_port(), actor.GetInputPort("contact_results"))
    indices = tuple(int(hand.index()) for hand in hands.values())
    grip = builder.AddNamedSystem("hand_grip", HandGrip(indices, bodies))
    builder.Connect(actor.GetOutputPort("grip"), grip.GetInputPort("grip"))
    builder.ExportOutput(actor.GetOutputPort("grip"), interface.TRUTH_PERSON_GRIP)
    builder.ExportOutput(actor.GetOutputPort("repeated_at"), interface.TRUTH_PERSON_REPEATED_AT)
    builder.Connect(plant.get_body_poses_output_port(), grip.GetInputPort("body_poses"))
    builder.Connect(
        plant.get_body_spatial_velocities_output_port(),
        grip.GetInputPort("body_spatial_velocities"),
    )
    builder.Connect(
        grip.GetOutputPort("spatial_forces"), plant.get_applied_spatial_force_input_port()
    )


def _corrector(body: BodyDimensions, scenario: Scenario, wanted: str) -> Corrector | None:
    """The person asking again if the robot lifts another object (None with nothing asked)."""
    changes = _asked_again(body, scenario, CORRECTION_STREAM) if wanted else []
    if not changes:
        return None
    return Corrector(wanted, changes, scenario.person.receiving.reaction_s)


def _repeater(body: BodyDimensions, scenario: Scenario) -> Repeater | None:
    """The person asking again if the robot does not respond (None with nothing asked, or a
    pointing held to the end)."""
    point = last_request(scenario)
    if point is None or point.duration is None:
        return None
    changes = _asked_again(body, scenario, REPEAT_STREAM)
    ended = point.start + point.duration
    return Repeater(changes, ended, scenario.person.receiving.repeat_after_s)


def _asked_again(body: BodyDimensions, scenario: Scenario, stream: int) -> list:
    """The request made again (`request_again`) as posture changes from its start."""
    actions = request_again(scenario, body, stream)
    return posture_changes(body, actions, scenario.table.height)[1:]  # not the rest at 0


def _world_bodies(plant, robot, hands, objects, bodies, hand_middle, scenario) -> WorldBodies:
    """What the receiving person watches: the hands, the objects, the robot's gripper, and the
    geometries by which a hand touches the objects."""
    gripper = tuple(
        (int(plant.GetBodyByName(link, robot).index()), np.array(start), np.array(end), radius)
        for link, (start, end, radius) in GRIPPER_CAPSULES.items()
    )
    touch = {geometry: "" for hand in hands.values()
             for geometry in plant.GetCollisionGeometriesForBody(hand)}  # fmt: skip
    for name, instance in objects.items():
        for index in plant.GetBodyIndices(instance):
            touch |= dict.fromkeys(plant.GetCollisionGeometriesForBody(plant.get_body(index)), name)
    indices = {name: gripped.index for name, gripped in bodies.items()}
    hand_indices = {arm: int(hand.index()) for arm, hand in hands.items()}
    return WorldBodies(hand_indices, hand_middle, indices, person_pose(scenario), gripper,
                       touch)  # fmt: skip


def _gripped_body(plant: MultibodyPlant, instance: ModelInstanceIndex) -> GrippedBody:
    body = plant.get_body(plant.GetBodyIndices(instance)[0])
    inertia = body.default_rotational_inertia().CopyToFullMatrix3()
    return GrippedBody(int(body.index()), body.default_mass(), inertia)


def _add_pose_detector(builder, plant, person, objects, camera, intrinsics, scenario: Scenario):
    """The simulated pose detector on the head camera, capturing at its instants, erring as
    `perception.detector` says (a wrist now and then on one of the `objects`); its `keypoints`
    output."""
    objects = [int(plant.GetBodyIndices(instance)[0]) for instance in objects.values()]
    detector = builder.AddNamedSystem(
        "pose_detector",
        SkeletonSensor(
            plant, person, intrinsics, 1.0 / scenario.camera.rate_hz,
            scenario.perception.detector.model(), scenario.simulation.seed, objects,
        ),
    )  # fmt: skip
    builder.Connect(plant.get_body_poses_output_port(), detector.GetInputPort("body_poses"))
    for name in ("depth_image", "camera_pose"):
        builder.Connect(camera.GetOutputPort(name), detector.GetInputPort(name))
    return detector.GetOutputPort("keypoints")


def _add_sensors(
    builder, plant, scene_graph, robot, person, objects, scenario: Scenario
) -> HeadCamera:
    """The head camera and the pose detector: simulated, capturing at the camera's instants, or
    a recording of OpenPose's output played back (`perception.skeleton_recording`)."""
    camera_config = scenario.camera
    intrinsics = camera_config.pinhole()
    camera = add_head_camera(
        builder, plant, scene_graph, robot, intrinsics, camera_config.depth_range,
        camera_config.rate_hz, camera_config.render_label, RENDERER, render_params(),
    )  # fmt: skip
    if scenario.perception.skeleton_recording is not None:
        keypoints = add_recorded_skeleton(builder, scenario)
    else:
        keypoints = _add_pose_detector(
            builder, plant, person, objects, camera, intrinsics, scenario
        )
    info = builder.AddNamedSystem(
        "camera_intrinsics", ConstantValueSource(AbstractValue.Make(to_camera_info(intrinsics)))
    )
    exports = {
        interface.CAMERA_COLOR_IMAGE: camera.GetOutputPort("color_image"),
        interface.CAMERA_DEPTH_IMAGE: camera.GetOutputPort("depth_image"),
        interface.CAMERA_POSE: camera.GetOutputPort("camera_pose"),
        interface.CAMERA_IMAGE_TIME: camera.GetOutputPort("image_time"),
        interface.CAMERA_INFO: info.get_output_port(),
        interface.SKELETON_KEYPOINTS: keypoints,
        interface.TRUTH_LABEL_IMAGE: camera.GetOutputPort("label_image"),
    }
    for name, port in exports.items():
        builder.ExportOutput(port, name)
    return camera


def _export_truth(builder, plant, scene_graph, robot, person) -> None:
    exports = {
        interface.TRUTH_BODY_POSES: plant.get_body_poses_output_port(),
        interface.TRUTH_CONTACT_RESULTS: plant.get_contact_results_output_port(),
        interface.TRUTH_PERSON_STATE: plant.get_state_output_port(person),
        interface.TRUTH_HSR_STATE: plant.get_state_output_port(robot),
        interface.TRUTH_QUERY_OBJECT: scene_graph.get_query_output_port(),
    }
    for name, port in exports.items():
        builder.ExportOutput(port, name)


def build_station(scenario: Scenario, meshcat: Meshcat | None = None) -> Station:
    """Build the world's Diagram (ports in the module docstring). With `meshcat`, the world is
    drawn there at the scenario's replay rate."""
    builder = DiagramBuilder()
    plant, scene_graph, robot, body, table, person, objects, floor = _add_plant(builder, scenario)
    timeline = _person_timeline(plant, person, body, scenario)
    plant.Finalize()
    scene_graph.collision_filter_manager().Apply(floor_filter(plant, floor, (robot, person)))
    _add_person(builder, plant, robot, person, objects, body, timeline, scenario)
    add_hsr_interface(builder, plant, robot)
    _add_sensors(builder, plant, scene_graph, robot, person, objects, scenario)
    _export_truth(builder, plant, scene_graph, robot, person)
    if meshcat is not None:
        params = MeshcatVisualizerParams(publish_period=1.0 / scenario.simulation.replay_fps)
        MeshcatVisualizer.AddToBuilder(builder, scene_graph, meshcat, params)
    diagram = builder.Build()
    diagram.set_name("station")
    return Station(diagram, plant, scene_graph, robot, person, table, objects, body, scenario)


@dataclasses.dataclass(frozen=True)
class Overlap:
    """Two of the robot, the person and the table intersecting at the start: the scenario's
    `key` that places the first (`who`), the `other`, and the `depth` (m)."""

    key: str
    who: str
    other: str
    depth: float


def initial_overlaps(station: Station, tolerance: float = 1e-3) -> list[Overlap]:
    """Where the robot or the person starts intersecting the table (or each other) by more
    than `tolerance` m, as measured on the built scene's collision geometry."""
    plant = station.plant
    context = station.diagram.CreateDefaultContext()
    query: QueryObject = station.diagram.GetOutputPort(interface.TRUTH_QUERY_OBJECT).Eval(context)
    inspector = query.inspector()
    owners = {
        station.robot: ("robot.base_pose", "the robot"),
        station.person: ("person.position", "the person"),
        station.table: ("table.center", "the table"),
    }
    overlaps = []
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
            overlaps.append(Overlap(key, who, other, float(pair.depth)))
    return overlaps


def check_initial_clearance(station: Station, tolerance: float = 1e-3) -> None:
    """Raise ScenarioError when the robot or the person starts intersecting the table (or each
    other) by more than `tolerance` m, as measured on the built scene's collision geometry."""
    overlaps = initial_overlaps(station, tolerance)
    if overlaps:
        overlap = overlaps[0]
        raise ScenarioError(
            station.scenario.source,
            overlap.key,
            f"expected {overlap.who} clear of {overlap.other}; "
            f"they intersect by {overlap.depth * 100:.1f} cm",
        )
