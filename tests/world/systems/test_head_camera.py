"""HeadCamera on its own ports: a frame's images are the scene at its capture instant, rendered
from the camera's own copy of the world (`camera_scene`) exactly as the world itself renders."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.geometry import (
    Box,
    ClippingRange,
    ColorRenderCamera,
    DepthRange,
    DepthRenderCamera,
    MakeRenderEngineVtk,
    RenderCameraCore,
    RenderEngineVtkParams,
)
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.multibody.tree import FixedOffsetFrame, PrismaticJoint, SpatialInertia
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.sensors import CameraInfo

from hsr_handover.world.station.camera_scene import add_camera_scene, connect_camera
from hsr_handover.world.systems.head_camera import HeadCamera

RATE_HZ = 10.0
X_PC = RigidTransform(RollPitchYaw(-np.pi / 2, 0, -np.pi / 2), [0, 0, 0])  # looking along +x


def _box_body(plant, name: str, size, color):
    body = plant.AddRigidBody(name, SpatialInertia.SolidBoxWithMass(1.0, *size))
    plant.RegisterVisualGeometry(body, RigidTransform(), Box(*size), name, color)
    return body


@pytest.fixture()
def rig():
    """A camera on a mount 1 m from a wall, a red box sliding sideways between them; the world's
    SceneGraph renders too, to compare against."""
    builder = DiagramBuilder()
    plant, world = AddMultibodyPlantSceneGraph(builder, time_step=0.0)
    mount = plant.AddRigidBody("mount", SpatialInertia.SolidBoxWithMass(1.0, 0.1, 0.1, 0.1))
    plant.WeldFrames(plant.world_frame(), mount.body_frame(), RigidTransform([0, 0, 1.0]))
    wall = Box(0.1, 3.0, 3.0)
    plant.RegisterVisualGeometry(
        plant.world_body(), RigidTransform([1.5, 0, 1.0]), wall, "wall", [0.2, 0.6, 0.2, 1.0]
    )
    box = _box_body(plant, "box", (0.2, 0.2, 0.2), [0.9, 0.1, 0.1, 1.0])
    track = plant.AddFrame(
        FixedOffsetFrame("track", plant.world_frame(), RigidTransform([1.0, 0, 1.0]))
    )
    slide = plant.AddJoint(PrismaticJoint("slide", track, box.body_frame(), [0, 1, 0]))
    plant.Finalize()
    slide.set_default_translation(0.0)
    params = RenderEngineVtkParams()
    world.AddRenderer("vtk", MakeRenderEngineVtk(params))
    parent = plant.GetBodyFrameIdOrThrow(mount.index())
    scene = add_camera_scene(builder, world, "vtk", params, (parent,))
    core = RenderCameraCore(
        "vtk", CameraInfo(64, 48, np.pi / 3), ClippingRange(0.05, 5.0), RigidTransform()
    )
    color, depth = ColorRenderCamera(core), DepthRenderCamera(core, DepthRange(0.1, 4.0))
    camera = builder.AddSystem(HeadCamera(color, depth, parent, X_PC, RATE_HZ, scene.frames))
    connect_camera(builder, scene, camera, plant.get_geometry_pose_output_port())
    diagram = builder.Build()
    simulator = Simulator(diagram)
    simulator.Initialize()
    return diagram, plant, world, camera, slide, parent, simulator


def _images(rig):
    diagram, _, _, camera, _, _, simulator = rig
    context = camera.GetMyContextFromRoot(simulator.get_context())
    color = camera.GetOutputPort("color_image").Eval(context).data.copy()
    depth = camera.GetOutputPort("depth_image").Eval(context).data.copy()
    return color, depth


def _world_render(rig):
    """The images the world's own SceneGraph renders now."""
    _, _, world, camera, _, parent, simulator = rig
    query = world.get_query_output_port().Eval(world.GetMyContextFromRoot(simulator.get_context()))
    color = query.RenderColorImage(camera.color_camera, parent, X_PC).data.copy()
    depth = query.RenderDepthImage(camera.depth_camera, parent, X_PC).data.copy()
    return color, depth


def _slide_to(rig, y: float) -> None:
    _, plant, _, _, slide, _, simulator = rig
    slide.set_translation(plant.GetMyMutableContextFromRoot(simulator.get_mutable_context()), y)


def test_images_are_the_worlds_own_render_of_the_capture(rig):
    color, depth = _images(rig)
    world_color, world_depth = _world_render(rig)
    np.testing.assert_array_equal(color, world_color)
    np.testing.assert_array_equal(depth, world_depth)
    # The box is in the middle of the view, in front of the wall.
    assert depth[24, 32, 0] == pytest.approx(0.9, abs=1e-3)
    assert depth[24, 2, 0] == pytest.approx(1.45, abs=1e-3)


def test_a_frame_shows_the_scene_at_its_capture_however_late_it_is_read(rig):
    _, _, _, camera, _, _, simulator = rig
    simulator.AdvanceTo(0.1 / RATE_HZ)  # past the periodic capture at 0
    captured_color, captured_depth = _images(rig)
    _slide_to(rig, 0.5)  # the box leaves the view between captures
    simulator.AdvanceTo(0.9 / RATE_HZ)
    color, depth = _images(rig)
    np.testing.assert_array_equal(color, captured_color)
    np.testing.assert_array_equal(depth, captured_depth)
    context = camera.GetMyContextFromRoot(simulator.get_context())
    assert camera.GetOutputPort("image_time").Eval(context) == 0.0

    simulator.AdvanceTo(1.5 / RATE_HZ)  # the next capture
    color, depth = _images(rig)
    assert camera.GetOutputPort("image_time").Eval(context) == pytest.approx(1.0 / RATE_HZ)
    assert depth[24, 32, 0] == pytest.approx(1.45, abs=1e-3)  # the wall, the box gone
    world_color, world_depth = _world_render(rig)
    np.testing.assert_array_equal(color, world_color)
    np.testing.assert_array_equal(depth, world_depth)


def test_camera_pose_is_the_mount_at_the_capture(rig):
    _, _, _, camera, _, _, simulator = rig
    context = camera.GetMyContextFromRoot(simulator.get_context())
    X_WC = camera.GetOutputPort("camera_pose").Eval(context)
    expected = RigidTransform([0, 0, 1.0]) @ X_PC
    assert X_WC.IsNearlyEqualTo(expected, 1e-12)


def test_labels_mark_the_box_with_its_bodys_label(rig):
    _, plant, world, camera, _, _, simulator = rig
    context = camera.GetMyContextFromRoot(simulator.get_context())
    labels = camera.GetOutputPort("label_image").Eval(context).data[:, :, 0]
    (geometry,) = plant.GetVisualGeometriesForBody(plant.GetBodyByName("box"))
    box_label = world.model_inspector().GetPerceptionProperties(geometry).GetProperty("label", "id")
    assert labels[24, 32] == int(box_label)
    assert labels[24, 2] != int(box_label)


def test_a_camera_needs_its_mount_among_the_scenes_frames(rig):
    _, _, _, camera, _, parent, _ = rig
    with pytest.raises(ValueError, match="parent frame"):
        HeadCamera(camera.color_camera, camera.depth_camera, parent, X_PC, RATE_HZ, {})
    with pytest.raises(ValueError, match="rate_hz"):
        HeadCamera(camera.color_camera, camera.depth_camera, parent, X_PC, 0.0, {parent: parent})
