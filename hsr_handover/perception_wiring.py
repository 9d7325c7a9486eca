"""Wire the robot's perception into the station (DESIGN §2):

    head camera depth -> DepthDownsampler -> DepthImageToPointCloud -> PointCloudGng
    head camera colour + depth ----------> ObjectDetector -----------+--> DetectionCrossCheck
                                                                     |    (against the GNG)
    plant body poses + depth ------------> SkeletonSensor -----------+-> AttentionFocus -+
                                                                                        v
                                                              PointCloudGng `attention` input

Everything downstream of the camera and the skeleton sensor reads only percepts.
"""

from __future__ import annotations

import dataclasses

from pydrake.geometry import Meshcat
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.perception import BaseField, DepthImageToPointCloud
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.sensors import PixelType

from hsr_handover.camera import to_camera_info
from hsr_handover.perception.attention import FocusChange
from hsr_handover.perception.cloud_map import Workspace
from hsr_handover.perception.skeleton import SkeletonNoise
from hsr_handover.scenario import Scenario, ScenarioError
from hsr_handover.systems.attention_focus import AttentionFocus
from hsr_handover.systems.depth_downsampler import DepthDownsampler
from hsr_handover.systems.detection_cross_check import DetectionCrossCheck
from hsr_handover.systems.graph_visualizer import add_graph_visualizer
from hsr_handover.systems.object_detector import ObjectDetector
from hsr_handover.systems.point_cloud_gng import PointCloudGng
from hsr_handover.systems.skeleton_sensor import SkeletonSensor
from hsr_handover.topology.growing_neural_gas import GrowingNeuralGas

PERCEPTION_OUTPUTS = ("gng_graph", "gng_stats", "gng_frame_report", "point_cloud",
                      "detections", "detection_support", "skeleton", "attention")  # fmt: skip


def focus_schedule(scenario: Scenario) -> list[FocusChange]:
    """The scenario's attention script; objects are named by their colour, as the robot
    tells them apart (the detector's labels)."""
    color_of = {obj.name: obj.color for obj in scenario.objects}
    return [
        FocusChange(change.start, change.focus, color_of.get(change.target, ""))
        for change in scenario.perception.attention
    ]


def _gng_params(scenario: Scenario) -> dict:
    params = dataclasses.asdict(scenario.perception.gng)
    try:
        GrowingNeuralGas(**params)
    except ValueError as error:
        raise ScenarioError(scenario.source, "perception.gng", str(error)) from None
    return params


def _add_cloud(builder: DiagramBuilder, camera: LeafSystem, scenario: Scenario) -> LeafSystem:
    width, height = scenario.perception.cloud_size
    downsampler = builder.AddNamedSystem("depth_downsampler", DepthDownsampler(width, height))
    builder.Connect(camera.GetOutputPort("depth_image"), downsampler.get_input_port())
    info = to_camera_info(scenario.camera.pinhole().scaled(width, height))
    to_cloud = builder.AddNamedSystem(
        "depth_to_point_cloud",
        DepthImageToPointCloud(info, PixelType.kDepth32F, 1.0, BaseField.kXYZs),
    )
    builder.Connect(downsampler.get_output_port(), to_cloud.depth_image_input_port())
    builder.Connect(camera.GetOutputPort("camera_pose"), to_cloud.camera_pose_input_port())
    return to_cloud


def add_perception(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    person: ModelInstanceIndex,
    camera: LeafSystem,
    scenario: Scenario,
    meshcat: Meshcat | None = None,
) -> None:
    """Add the perception systems and export PERCEPTION_OUTPUTS from the builder."""
    perception, seed = scenario.perception, scenario.simulation.seed
    image_camera = scenario.camera.pinhole()
    to_cloud = _add_cloud(builder, camera, scenario)

    detector = builder.AddNamedSystem("object_detector", ObjectDetector(image_camera))
    noise = SkeletonNoise(
        pixel_sigma=perception.pixel_sigma,
        face_drop_probability=perception.face_drop_probability,
    )
    skeleton = builder.AddNamedSystem(
        "skeleton_sensor", SkeletonSensor(plant, person, image_camera, noise, seed)
    )
    builder.Connect(plant.get_body_poses_output_port(), skeleton.GetInputPort("body_poses"))
    for system in (detector, skeleton):
        for name in ("depth_image", "camera_pose"):
            builder.Connect(camera.GetOutputPort(name), system.GetInputPort(name))
    builder.Connect(camera.GetOutputPort("color_image"), detector.GetInputPort("color_image"))
    builder.Connect(camera.GetOutputPort("image_time"), skeleton.GetInputPort("image_time"))

    focus = builder.AddNamedSystem("attention_focus", AttentionFocus(focus_schedule(scenario)))
    builder.Connect(skeleton.GetOutputPort("skeleton"), focus.GetInputPort("skeleton"))
    builder.Connect(detector.GetOutputPort("detections"), focus.GetInputPort("detections"))

    workspace = Workspace(tuple(perception.workspace[:3]), tuple(perception.workspace[3:]))
    gng = builder.AddNamedSystem(
        "point_cloud_gng",
        PointCloudGng(
            _gng_params(scenario), workspace, 1.0 / scenario.camera.rate_hz,
            perception.signals_per_frame, perception.attention_weight, seed,
        ),
    )  # fmt: skip
    builder.Connect(to_cloud.point_cloud_output_port(), gng.GetInputPort("point_cloud"))
    builder.Connect(focus.GetOutputPort("attention"), gng.GetInputPort("attention"))
    cross_check = builder.AddNamedSystem("detection_cross_check", DetectionCrossCheck())
    builder.Connect(detector.GetOutputPort("detections"), cross_check.GetInputPort("detections"))
    builder.Connect(gng.GetOutputPort("graph"), cross_check.GetInputPort("graph"))
    if meshcat is not None:
        add_graph_visualizer(builder, gng.GetOutputPort("graph"), meshcat)

    exports = {
        "gng_graph": gng.GetOutputPort("graph"),
        "gng_stats": gng.GetOutputPort("stats"),
        "gng_frame_report": gng.GetOutputPort("frame_report"),
        "point_cloud": to_cloud.point_cloud_output_port(),
        "detections": detector.GetOutputPort("detections"),
        "detection_support": cross_check.GetOutputPort("detection_support"),
        "skeleton": skeleton.GetOutputPort("skeleton"),
        "attention": focus.GetOutputPort("attention"),
    }
    for name, port in exports.items():
        builder.ExportOutput(port, name)
