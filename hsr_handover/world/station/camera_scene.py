"""The camera's own scene: the world's perception geometry copied into a SceneGraph of its own.

A renderer on the plant's SceneGraph has every geometry's pose pushed to it at every plant step
(140 us a 2 ms step for the HSR, the person and the table, about 5 % of a handover trial),
though the camera renders at most at its frame rate. In a SceneGraph of its own the renderer
is posed only when an image is rendered, from the poses the camera latched when it captured.
"""

from __future__ import annotations

import dataclasses

from pydrake.geometry import (
    FrameId,
    GeometryFrame,
    GeometryInstance,
    MakeRenderEngineVtk,
    RenderEngineVtkParams,
    Role,
    SceneGraph,
    SourceId,
)
from pydrake.systems.framework import DiagramBuilder, OutputPort

from hsr_handover.world.systems.head_camera import HeadCamera


@dataclasses.dataclass(frozen=True)
class CameraScene:
    """The camera's SceneGraph, the source that poses its frames, and each world frame's copy
    (`frames`: the plant SceneGraph's FrameId -> the camera scene's)."""

    scene_graph: SceneGraph
    source: SourceId
    frames: dict[FrameId, FrameId]


def add_camera_scene(
    builder: DiagramBuilder,
    world: SceneGraph,
    renderer: str,
    params: RenderEngineVtkParams,
    extra_frames: tuple[FrameId, ...] = (),
) -> CameraScene:
    """A SceneGraph with renderer `renderer` holding a copy of every perception geometry of
    `world` (anchored ones anchored, the others on copies of their frames, which also include
    `extra_frames`, e.g. the one the camera is mounted on). Call once `world` is complete."""
    scene_graph = builder.AddNamedSystem("camera_scene_graph", SceneGraph())
    scene_graph.AddRenderer(renderer, MakeRenderEngineVtk(params))
    source = scene_graph.RegisterSource("world_seen_by_the_camera")
    inspector = world.model_inspector()
    frames: dict[FrameId, FrameId] = {}

    def copy_of(frame: FrameId) -> FrameId:
        if frame not in frames:
            copy = GeometryFrame(inspector.GetName(frame), inspector.GetFrameGroup(frame))
            frames[frame] = scene_graph.RegisterFrame(source, copy)
        return frames[frame]

    for frame in extra_frames:
        copy_of(frame)
    for geometry in inspector.GetAllGeometryIds(Role.kPerception):
        clone = inspector.CloneGeometryInstance(geometry)
        instance = GeometryInstance(clone.pose(), clone.shape(), clone.name())
        instance.set_perception_properties(clone.perception_properties())
        frame = inspector.GetFrameId(geometry)
        if frame == inspector.world_frame_id():
            scene_graph.RegisterAnchoredGeometry(source, instance)
        else:
            scene_graph.RegisterGeometry(source, copy_of(frame), instance)
    return CameraScene(scene_graph, source, frames)


def connect_camera(
    builder: DiagramBuilder, scene: CameraScene, camera: HeadCamera, world_poses: OutputPort
) -> None:
    """Wire `camera` to its scene: the world's frame poses (`world_poses`, the plant's geometry
    poses) in, the poses it latches out to the scene, and the scene's queries back to it."""
    builder.Connect(world_poses, camera.GetInputPort("frame_poses"))
    builder.Connect(
        camera.GetOutputPort("scene_poses"), scene.scene_graph.get_source_pose_port(scene.source)
    )
    builder.Connect(scene.scene_graph.get_query_output_port(), camera.GetInputPort("query_object"))
