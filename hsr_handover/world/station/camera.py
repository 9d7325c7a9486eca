"""The HSR's head RGB-D camera (an Xtion): intrinsics from the scenario, mounted on the head,
rendering a copy of the world's perception geometry (`camera_scene`)."""

from __future__ import annotations

from pydrake.geometry import (
    ClippingRange,
    ColorRenderCamera,
    DepthRange,
    DepthRenderCamera,
    RenderCameraCore,
    RenderEngineVtkParams,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.hsr import CAMERA_FRAME
from hsr_handover.interface.camera_info import to_camera_info
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.world.station.camera_scene import add_camera_scene, connect_camera
from hsr_handover.world.systems.head_camera import HeadCamera


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
    render_params: RenderEngineVtkParams,
) -> HeadCamera:
    """Mount the head camera on the robot's camera frame, capturing colour, depth ([near, far]
    in m) and, when `render_label`, labels at `rate_hz`; images are held between frames, as a
    real camera's are. Call once the world's geometry is complete: the camera renders its own
    copy of it, with `renderer` made from `render_params`."""
    frame = plant.GetFrameByName(CAMERA_FRAME, robot)
    parent = plant.GetBodyFrameIdOrThrow(frame.body().index())
    scene = add_camera_scene(builder, scene_graph, renderer, render_params, (parent,))
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
            scene.frames,
            render_label,
        ),
    )
    connect_camera(builder, scene, camera, plant.get_geometry_pose_output_port())
    return camera
