"""The robot's perception (docs/design.md §2), fed only by the station's sensor ports.

- camera_depth_image -> DepthDownsampler -> DepthImageToPointCloud -> PointCloudGng (the map)
- camera_color_image + depth -> ObjectDetector -> DetectionCrossCheck (against the map)
- skeleton_keypoints + depth -> SkeletonLifter -> AttentionFocus -> the map's `attention`
- skeleton, detections and their cross-check -> IntentEstimator (eqs. 16-17)
- cloud -> TableEstimator; with detections, depth and skeleton -> PerceivedSceneEstimator (what
  the planner avoids)
"""

from __future__ import annotations

import dataclasses

from pydrake.perception import BaseField, DepthImageToPointCloud
from pydrake.systems.framework import DiagramBuilder, InputPort, LeafSystem
from pydrake.systems.sensors import PixelType

from hsr_handover import interface
from hsr_handover.interface.camera_info import to_camera_info
from hsr_handover.robot.perception.attention import FocusChange
from hsr_handover.robot.perception.cloud_map import Workspace
from hsr_handover.robot.systems.attention_focus import AttentionFocus
from hsr_handover.robot.systems.depth_downsampler import DepthDownsampler
from hsr_handover.robot.systems.detection_cross_check import DetectionCrossCheck
from hsr_handover.robot.systems.intent_estimator import IntentEstimator
from hsr_handover.robot.systems.object_detector import ObjectDetector
from hsr_handover.robot.systems.perceived_scene_estimator import PerceivedSceneEstimator
from hsr_handover.robot.systems.point_cloud_gng import PointCloudGng
from hsr_handover.robot.systems.skeleton_lifter import SkeletonLifter
from hsr_handover.robot.systems.table_estimator import TableEstimator
from hsr_handover.scenario import Scenario, ScenarioError
from hsr_handover.topology.growing_neural_gas import GrowingNeuralGas

PERCEPTION_OUTPUTS = ("gng_graph", "gng_stats", "gng_frame_report", "point_cloud",
                      "detections", "detection_support", "skeleton", "attention", "intent",
                      "intent_rays", "table", "perceived_scene")  # fmt: skip
TABLE_FRAME_STRIDE = 6
"""The table is fitted to every sixth frame (5 Hz at 30 Hz): it does not move, and a frame's
fit costs about 5 ms."""


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


class SensorInputs:
    """Exports each station sensor the robot reads as one diagram input, fanned out to every
    system that reads it."""

    def __init__(self, builder: DiagramBuilder):
        self._builder = builder
        self._exported: set[str] = set()

    def feed(self, sensor: str, port: InputPort) -> None:
        if sensor in self._exported:
            self._builder.ConnectInput(sensor, port)
        else:
            self._builder.ExportInput(port, sensor)
            self._exported.add(sensor)


def _add_cloud(builder: DiagramBuilder, inputs: SensorInputs, scenario: Scenario) -> LeafSystem:
    width, height = scenario.perception.cloud_size
    downsampler = builder.AddNamedSystem("depth_downsampler", DepthDownsampler(width, height))
    inputs.feed(interface.CAMERA_DEPTH_IMAGE, downsampler.get_input_port())
    info = to_camera_info(scenario.camera.pinhole().scaled(width, height))
    to_cloud = builder.AddNamedSystem(
        "depth_to_point_cloud",
        DepthImageToPointCloud(info, PixelType.kDepth32F, 1.0, BaseField.kXYZs),
    )
    builder.Connect(downsampler.get_output_port(), to_cloud.depth_image_input_port())
    inputs.feed(interface.CAMERA_POSE, to_cloud.camera_pose_input_port())
    return to_cloud


def _add_detectors(
    builder: DiagramBuilder, inputs: SensorInputs, scenario: Scenario
) -> tuple[LeafSystem, LeafSystem]:
    """The object detector and the skeleton lifter, on the full-size images."""
    camera = scenario.camera.pinhole()
    detector = builder.AddNamedSystem("object_detector", ObjectDetector(camera))
    lifter = builder.AddNamedSystem("skeleton_lifter", SkeletonLifter(camera))
    inputs.feed(interface.CAMERA_COLOR_IMAGE, detector.GetInputPort("color_image"))
    inputs.feed(interface.SKELETON_KEYPOINTS, lifter.GetInputPort("keypoints"))
    for system in (detector, lifter):
        inputs.feed(interface.CAMERA_DEPTH_IMAGE, system.GetInputPort("depth_image"))
        inputs.feed(interface.CAMERA_POSE, system.GetInputPort("camera_pose"))
    return detector, lifter


def _add_intent(builder: DiagramBuilder, inputs: SensorInputs, scenario: Scenario) -> LeafSystem:
    try:
        params = scenario.intent.params()
    except ValueError as error:
        raise ScenarioError(scenario.source, "intent", str(error)) from None
    intent = builder.AddNamedSystem(
        "intent_estimator", IntentEstimator(1.0 / scenario.camera.rate_hz, params)
    )
    inputs.feed(interface.CAMERA_IMAGE_TIME, intent.GetInputPort("image_time"))
    return intent


def add_perception(builder: DiagramBuilder, scenario: Scenario) -> SensorInputs:
    """Add the perception systems to the robot's builder; export the sensor inputs they read
    (named as the station's outputs) and PERCEPTION_OUTPUTS. Returns the exported inputs, for
    the systems added later to read the same sensors."""
    perception, seed = scenario.perception, scenario.simulation.seed
    inputs = SensorInputs(builder)
    to_cloud = _add_cloud(builder, inputs, scenario)
    detector, lifter = _add_detectors(builder, inputs, scenario)

    focus = builder.AddNamedSystem("attention_focus", AttentionFocus(focus_schedule(scenario)))
    builder.Connect(lifter.GetOutputPort("skeleton"), focus.GetInputPort("skeleton"))
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
    inputs.feed(interface.CAMERA_IMAGE_TIME, gng.GetInputPort("image_time"))
    cross_check = builder.AddNamedSystem("detection_cross_check", DetectionCrossCheck())
    builder.Connect(detector.GetOutputPort("detections"), cross_check.GetInputPort("detections"))
    builder.Connect(gng.GetOutputPort("graph"), cross_check.GetInputPort("graph"))
    table = builder.AddNamedSystem(
        "table_estimator",
        TableEstimator(workspace, TABLE_FRAME_STRIDE / scenario.camera.rate_hz,
                       camera=scenario.camera.pinhole()),
    )  # fmt: skip
    builder.Connect(to_cloud.point_cloud_output_port(), table.GetInputPort("point_cloud"))
    inputs.feed(interface.CAMERA_POSE, table.GetInputPort("camera_pose"))
    scene = builder.AddNamedSystem(
        "perceived_scene_estimator", PerceivedSceneEstimator(scenario.camera.pinhole())
    )
    builder.Connect(table.GetOutputPort("table"), scene.GetInputPort("table"))
    builder.Connect(detector.GetOutputPort("detections"), scene.GetInputPort("detections"))
    builder.Connect(lifter.GetOutputPort("skeleton"), scene.GetInputPort("skeleton"))
    inputs.feed(interface.CAMERA_DEPTH_IMAGE, scene.GetInputPort("depth_image"))
    inputs.feed(interface.CAMERA_POSE, scene.GetInputPort("camera_pose"))
    intent = _add_intent(builder, inputs, scenario)
    for name, port in (
        ("skeleton", lifter.GetOutputPort("skeleton")),
        ("detections", detector.GetOutputPort("detections")),
        ("detection_support", cross_check.GetOutputPort("detection_support")),
    ):
        builder.Connect(port, intent.GetInputPort(name))  # fmt: skip

    exports = {
        "gng_graph": gng.GetOutputPort("graph"),
        "gng_stats": gng.GetOutputPort("stats"),
        "gng_frame_report": gng.GetOutputPort("frame_report"),
        "point_cloud": to_cloud.point_cloud_output_port(),
        "detections": detector.GetOutputPort("detections"),
        "detection_support": cross_check.GetOutputPort("detection_support"),
        "skeleton": lifter.GetOutputPort("skeleton"),
        "attention": focus.GetOutputPort("attention"),
        "intent": intent.GetOutputPort("intent"),
        "intent_rays": intent.GetOutputPort("rays"),
        "table": table.GetOutputPort("table"),
        "perceived_scene": scene.GetOutputPort("scene"),
    }
    for name, port in exports.items():
        builder.ExportOutput(port, name)
    return inputs
