"""PerceivedSceneEstimator on its own ports and context: a camera looking straight down at a
table with a box on it, and a person in view."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.object_detection import Detection, DetectionResult
from hsr_handover.robot.perception.object_shapes import BOX
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.perception.table_fit import TableEstimate, TableReport
from hsr_handover.robot.systems.perceived_scene_estimator import PerceivedSceneEstimator
from tests.robot.planning.test_perceived_scene import _skeleton

CAMERA = PinholeCamera.from_fov_x(64, 48, 1.0)
CAMERA_HEIGHT, TABLE_TOP, BOX_TOP = 2.0, 0.72, 0.82
BOX_PIXELS = (27, 19, 36, 28)  # u_min, v_min, u_max, v_max


def _fix_inputs(system, table: TableEstimate | None):
    """The camera 2 m up looking down (its image's x along the world's x); the box's top fills
    BOX_PIXELS, the table's top the rest."""
    context = system.CreateDefaultContext()
    X_WC = RigidTransform(RotationMatrix.MakeXRotation(math.pi), [0.9, 0.0, CAMERA_HEIGHT])
    depth = np.full((CAMERA.height, CAMERA.width), CAMERA_HEIGHT - TABLE_TOP, np.float32)
    u0, v0, u1, v1 = BOX_PIXELS
    depth[v0 : v1 + 1, u0 : u1 + 1] = CAMERA_HEIGHT - BOX_TOP
    image = ImageDepth32F(CAMERA.width, CAMERA.height)
    image.mutable_data[:, :, 0] = depth
    center_pixel = ((u0 + u1) / 2, (v0 + v1) / 2)
    center = CAMERA.deproject(np.array([center_pixel]), [CAMERA_HEIGHT - BOX_TOP],
                              X_WC.GetAsMatrix4())[0]  # fmt: skip
    box = Detection("yellow", "yellow", BOX_PIXELS, center_pixel, center, 100)
    points, confidence = _skeleton()
    system.GetInputPort("table").FixValue(context, TableReport(table, 1, "ok"))
    system.GetInputPort("detections").FixValue(context, DetectionResult((box,), "ok"))
    system.GetInputPort("depth_image").FixValue(context, image)
    system.GetInputPort("camera_pose").FixValue(context, X_WC)
    system.GetInputPort("skeleton").FixValue(
        context, Skeleton(np.zeros((18, 2)), points, confidence)
    )
    return context, center


def test_each_detection_becomes_a_solid_standing_on_the_fitted_table():
    system = PerceivedSceneEstimator(CAMERA)
    table = TableEstimate(TABLE_TOP, np.array([0.9, 0.0]), np.array([1.0, 0.6]), 0.0, 5000)
    context, center = _fix_inputs(system, table)
    scene = system.GetOutputPort("scene").Eval(context)
    assert scene.table.height == TABLE_TOP and np.array_equal(scene.table.size, table.size)
    (shape,) = scene.objects
    metres_per_pixel = (CAMERA_HEIGHT - BOX_TOP) / CAMERA.fx
    assert shape.label == "yellow" and shape.kind == BOX
    assert shape.bottom == TABLE_TOP and shape.height == pytest.approx(BOX_TOP - TABLE_TOP)
    np.testing.assert_allclose(shape.center, center[:2], atol=metres_per_pixel)
    np.testing.assert_allclose(shape.size, 9 * metres_per_pixel, rtol=0.02)  # 10 pixel centres
    assert len(scene.person) == 7  # the six bones whose two keypoints were seen, the body


def test_before_the_table_is_seen_there_are_no_objects_but_the_person():
    system = PerceivedSceneEstimator(CAMERA, person_margin=0.0)
    context, _ = _fix_inputs(system, None)
    context.SetTime(3.5)
    scene = system.GetOutputPort("scene").Eval(context)
    assert scene.table is None and scene.objects == ()
    assert len(scene.person) == 7
    assert {capsule.seen_at for capsule in scene.person} == {3.5}


def test_the_scene_keeps_the_depth_view_it_was_seen_in():
    """The view tells the supervisor where the camera sees through a remembered part."""
    system = PerceivedSceneEstimator(CAMERA)
    context, center = _fix_inputs(system, None)
    view = system.GetOutputPort("scene").Eval(context).view
    over_box, over_table = center + [0, 0, 0.1], np.array([0.9, 0.3, TABLE_TOP + 0.1])
    np.testing.assert_allclose(view.depth_past(np.array([over_box, over_table])), 0.1,
                               atol=1e-6)  # fmt: skip
    # A copy: the port's image is reused for the next capture.
    image = system.GetInputPort("depth_image").Eval(context)
    image.mutable_data[:] = 0.0
    assert np.all(view.depth > 0)


def test_a_negative_margin_is_refused_by_name():
    with pytest.raises(ValueError, match="person_margin"):
        PerceivedSceneEstimator(CAMERA, person_margin=-0.01)


def test_a_hip_lifted_onto_the_fitted_table_draws_no_torso():
    """The table on the `table` port tells a hip lifted onto its top from the person's."""
    system = PerceivedSceneEstimator(CAMERA)
    table = TableEstimate(TABLE_TOP, np.array([0.9, 0.0]), np.array([1.0, 0.6]), 0.0, 5000)
    context, _ = _fix_inputs(system, table)
    points, confidence = _skeleton()
    points[keypoint_index("r_hip")] = (1.3, -0.1, TABLE_TOP + 0.01)
    system.GetInputPort("skeleton").FixValue(
        context, Skeleton(np.zeros((18, 2)), points, confidence)
    )
    parts = {capsule.part for capsule in system.GetOutputPort("scene").Eval(context).person}
    assert "neck-r_hip" not in parts and "neck-r_shoulder" in parts
    system.GetInputPort("table").FixValue(context, TableReport(None, 0, "not seen"))
    parts = {capsule.part for capsule in system.GetOutputPort("scene").Eval(context).person}
    assert "neck-r_hip" in parts
