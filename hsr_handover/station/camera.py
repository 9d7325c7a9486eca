"""The HSR's head RGB-D camera (an Xtion): intrinsics from the scenario, mounted on the head."""

from __future__ import annotations

from pydrake.geometry import (
    ClippingRange,
    ColorRenderCamera,
    DepthRange,
    DepthRenderCamera,
    RenderCameraCore,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.hsr import CAMERA_FRAME
from hsr_handover.perception.pinhole import PinholeCamera
from hsr_handover.systems.head_camera import HeadCamera, to_camera_info


def add_head_camera(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    robot: ModelInstanceIndex,
    intrinsics: PinholeCamera,
    depth_range: tuple[float, float],
    rate_hz: float,
    render_label: bool,
    renderer: str,
) -> HeadCamera:
    """Mount the head camera on the robot's camera frame, rendering colour, depth ([near, far]
    in m) and, when `render_label`, labels at `rate_hz`; images are held between frames, as a
    real camera's are."""
    frame = plant.GetFrameByName(CAMERA_FRAME, robot)
    parent = plant.GetBodyFrameIdOrThrow(frame.body().index())
    near, far = depth_range
    core = RenderCameraCore(
        renderer, to_camera_info(intrinsics), ClippingRange(0.05, far + 1.0), RigidTransform()
    )
    camera = builder.AddNamedSystem(
        "head_camera",
        HeadCamera(
            ColorRenderCamera(core, show_window=False),
            DepthRenderCamera(core, DepthRange(near, far)),
            parent,
            frame.GetFixedPoseInBodyFrame(),
            rate_hz,
            render_label,
        ),
    )
    builder.Connect(scene_graph.get_query_output_port(), camera.GetInputPort("query_object"))
    return camera
