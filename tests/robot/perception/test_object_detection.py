"""Object detection by colour (paper section 4.3): on a ray-cast synthetic frame with known
geometry, on degraded frames, as a LeafSystem on its own, and on the station's rendered scene,
where every object must be found once, within 1.5 cm of its true centre, and nothing else."""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.object_detection import (
    DetectionResult,
    DetectorSettings,
    detect_objects,
)
from hsr_handover.robot.perception.object_shapes import CYLINDER, fit_shape, object_points
from hsr_handover.robot.systems.object_detector import ObjectDetector
from hsr_handover.scenario import load_scenario
from hsr_handover.simulation import add_station_and_robot
from tests.paths import SCENARIOS

CENTER_TOLERANCE = 0.015  # m, the target for unoccluded objects 0.8-1.5 m away
TABLE_HEIGHT = 0.72
SKIN, SHIRT, TROUSERS = (0.87, 0.70, 0.58), (0.45, 0.47, 0.50), (0.15, 0.17, 0.22)
TABLE, SKY = (0.55, 0.42, 0.30), (0.80, 0.88, 1.00)


@dataclasses.dataclass(frozen=True)
class Cylinder:
    """An upright cylinder standing on the table, like the scenarios' cups."""

    color: str
    x: float
    y: float
    radius: float
    height: float

    @property
    def center(self) -> np.ndarray:
        return np.array([self.x, self.y, TABLE_HEIGHT + self.height / 2])


CUPS = (
    Cylinder("red", 0.78, 0.22, 0.035, 0.10),  # about 0.8 m from the camera
    Cylinder("green", 1.00, -0.05, 0.040, 0.09),
    Cylinder("blue", 1.20, 0.30, 0.035, 0.12),
    Cylinder("yellow", 1.45, -0.25, 0.040, 0.10),  # about 1.5 m
)


def camera_pose(position=(0.0, 0.0, 1.0), yaw: float = 0.0, tilt: float = 0.25) -> np.ndarray:
    """X_WC of a camera at `position` looking along world yaw, pitched down by `tilt` (rad)."""
    forward = np.array([np.cos(tilt) * np.cos(yaw), np.cos(tilt) * np.sin(yaw), -np.sin(tilt)])
    right = np.array([np.sin(yaw), -np.cos(yaw), 0.0])
    X_WC = np.eye(4)
    X_WC[:3, :3] = np.column_stack([right, np.cross(forward, right), forward])
    X_WC[:3, 3] = position
    return X_WC


def _cylinder_hits(origin, rays, cup: Cylinder) -> tuple[np.ndarray, np.ndarray]:
    """Ray parameter (= depth, rays have unit optical-axis component) of the nearest hit on the
    side or the top, inf on a miss; and a shading factor from the surface normal."""
    offset = origin[:2] - (cup.x, cup.y)
    a = np.sum(rays[:, :2] ** 2, axis=1)
    b = 2 * rays[:, :2] @ offset
    c = offset @ offset - cup.radius**2
    disc = b**2 - 4 * a * c
    with np.errstate(invalid="ignore", divide="ignore"):
        t_side = (-b - np.sqrt(disc)) / (2 * a)
        t_top = (TABLE_HEIGHT + cup.height - origin[2]) / rays[:, 2]
    z_side = origin[2] + t_side * rays[:, 2]
    side = (
        (disc > 0) & (t_side > 0) & (z_side >= TABLE_HEIGHT) & (z_side <= TABLE_HEIGHT + cup.height)
    )
    top_xy = origin[:2] + t_top[:, None] * rays[:, :2] - (cup.x, cup.y)
    top = (t_top > 0) & (np.sum(top_xy**2, axis=1) <= cup.radius**2)
    depth = np.where(side, t_side, np.where(top, t_top, np.inf))
    normal_xy = (origin[:2] + t_side[:, None] * rays[:, :2] - (cup.x, cup.y)) / cup.radius
    facing = -np.sum(normal_xy * rays[:, :2], axis=1) / np.linalg.norm(rays, axis=1)
    shade = np.where(side, 0.25 + 0.75 * np.clip(facing, 0, 1), 0.9)
    return depth, shade


def render(camera: PinholeCamera, X_WC: np.ndarray, cups=CUPS, with_person: bool = True):
    """Ray-cast colour and depth of cups on a table top under a pale sky, with the person's
    colours drawn above the table, and each cup's true silhouette mask."""
    v, u = np.indices((camera.height, camera.width), dtype=float)
    rays_C = np.stack([(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, np.ones_like(u)])
    rays = rays_C.reshape(3, -1).T @ X_WC[:3, :3].T
    origin = X_WC[:3, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_table = (TABLE_HEIGHT - origin[2]) / rays[:, 2]
    depth = np.where(t_table > 0, t_table, np.inf)
    rgb = np.where((t_table > 0)[:, None], TABLE, SKY) * 255.0
    silhouettes = {}
    for cup in cups:
        t_cup, shade = _cylinder_hits(origin, rays, cup)
        hit = t_cup < depth
        depth[hit] = t_cup[hit]
        rgb[hit] = np.outer(shade[hit], OBJECT_COLORS[cup.color]) * 255.0
        silhouettes[cup.color] = hit.reshape(camera.height, camera.width)
    rgb = np.round(rgb).astype(np.uint8).reshape(camera.height, camera.width, 3)
    depth = depth.reshape(camera.height, camera.width).astype(np.float32)
    if with_person:
        _draw_person(rgb, depth)
    return rgb, depth, silhouettes


def _draw_person(rgb: np.ndarray, depth: np.ndarray) -> None:
    """Distractors 2 m away, above the table, in the person's colours: a face, a shirt and dark
    blue-grey trousers (whose hue is the blue cup's)."""
    height, width = depth.shape
    person = np.zeros((height, width), np.uint8)
    cv2.circle(person, (width // 2, height // 8), height // 14, 1, cv2.FILLED)
    top, bottom = height // 20, height // 5
    cv2.rectangle(person, (width // 10, top), (width // 3, bottom), 2, cv2.FILLED)
    cv2.rectangle(person, (2 * width // 3, top), (9 * width // 10, bottom), 3, cv2.FILLED)
    for value, color in ((1, SKIN), (2, SHIRT), (3, TROUSERS)):
        rgb[person == value] = np.round(np.array(color) * 255).astype(np.uint8)
    depth[person > 0] = 2.0


CAMERA = PinholeCamera.from_fov_x(640, 480, 1.05)


@pytest.fixture(scope="module")
def synthetic():
    X_WC = camera_pose()
    rgb, depth, silhouettes = render(CAMERA, X_WC)
    return rgb, depth, X_WC, silhouettes


def _box_of(mask: np.ndarray) -> tuple[int, int, int, int]:
    rows, columns = np.nonzero(mask)
    return columns.min(), rows.min(), columns.max(), rows.max()


def _assert_centers(result: DetectionResult, truth: dict[str, np.ndarray]) -> None:
    assert result.status == "ok"
    assert sorted(d.label for d in result.detections) == sorted(truth)
    for detection in result.detections:
        error = np.linalg.norm(detection.center - truth[detection.label])
        assert error < CENTER_TOLERANCE, (detection.label, error)


def test_synthetic_cups_are_found_with_their_boxes_pixels_and_centres(synthetic):
    rgb, depth, X_WC, silhouettes = synthetic
    result = detect_objects(rgb, depth, CAMERA, X_WC)
    _assert_centers(result, {cup.color: cup.center for cup in CUPS})
    for detection in result.detections:
        silhouette = silhouettes[detection.color]
        assert detection.color == detection.label
        assert np.allclose(detection.box, _box_of(silhouette), atol=1)
        # Opening trims only a few stair-step pixels off the outline.
        assert 0.97 * silhouette.sum() <= detection.pixel_count <= silhouette.sum()
        u_min, v_min, u_max, v_max = detection.box
        assert detection.center_pixel == ((u_min + u_max) / 2, (v_min + v_max) / 2)


def test_downsampled_frame_meets_the_same_target():
    camera = CAMERA.scaled(200, 200)
    X_WC = camera_pose()
    rgb, depth, _ = render(camera, X_WC)
    _assert_centers(detect_objects(rgb, depth, camera, X_WC), {c.color: c.center for c in CUPS})


def test_repeated_colour_is_numbered_largest_first():
    cups = (Cylinder("red", 0.9, 0.2, 0.03, 0.08), Cylinder("red", 1.1, -0.2, 0.045, 0.12))
    X_WC = camera_pose()
    rgb, depth, _ = render(CAMERA, X_WC, cups)
    result = detect_objects(rgb, depth, CAMERA, X_WC)
    assert [d.label for d in result.detections] == ["red", "red#2"]
    assert [d.color for d in result.detections] == ["red", "red"]
    assert result.detections[0].pixel_count > result.detections[1].pixel_count
    big, small = result.detections
    assert np.linalg.norm(big.center - cups[1].center) < CENTER_TOLERANCE
    assert np.linalg.norm(small.center - cups[0].center) < CENTER_TOLERANCE


def test_a_cup_cut_in_two_by_something_in_front_is_one_object(synthetic):
    """A finger across the green cup splits its blob in two: still one green cup, its box the
    whole cup's; cut into parts 4 pixels apart, the same."""
    rgb, depth, X_WC, silhouettes = synthetic
    u_min, v_min, u_max, v_max = _box_of(silhouettes["green"])
    rgb = rgb.copy()
    middle = (u_min + u_max) // 2
    rgb[:, middle - 2 : middle + 2] = np.round(np.array(SKIN) * 255)
    result = detect_objects(rgb, depth, CAMERA, X_WC)
    green = [d for d in result.detections if d.color == "green"]
    assert [d.label for d in green] == ["green"]
    assert green[0].box == (u_min, v_min, u_max, v_max)
    assert np.linalg.norm(green[0].center - CUPS[1].center) < CENTER_TOLERANCE
    apart = DetectorSettings(same_object_m=0.0)  # parts never joined: the cut shows
    assert len([d for d in detect_objects(rgb, depth, CAMERA, X_WC, settings=apart).detections
                if d.color == "green"]) == 2  # fmt: skip


def test_hollow_blob_takes_its_depth_from_its_own_pixels():
    """A ring's box centre falls in its hole, where the depth is the wall behind it."""
    rgb = np.zeros((240, 320, 3), np.uint8)
    ring = np.zeros((240, 320), np.uint8)
    cv2.circle(ring, (160, 120), 40, 1, thickness=8)
    rgb[ring > 0] = np.round(np.array(OBJECT_COLORS["magenta"]) * 255).astype(np.uint8)
    depth = np.where(ring > 0, 1.0, 3.0).astype(np.float32)
    camera = PinholeCamera.from_fov_x(320, 240, 1.05)
    result = detect_objects(rgb, depth, camera, np.eye(4))
    (detection,) = result.detections
    visible_half_width = (detection.box[2] - detection.box[0] + 1) / camera.fx / 2
    assert detection.center[2] == pytest.approx(1.0 + visible_half_width, abs=0.005)


def test_blob_without_depth_keeps_a_nan_centre(synthetic):
    rgb, depth, X_WC, silhouettes = synthetic
    depth = np.where(silhouettes["red"], np.nan, depth)
    result = detect_objects(rgb, depth, CAMERA, X_WC)
    centers = {d.label: d.center for d in result.detections}
    assert result.status == "ok" and np.all(np.isnan(centers["red"]))
    assert np.all(np.isfinite(centers["green"]))


@pytest.mark.parametrize(
    ("degrade", "min_pixels", "status"),
    [
        (lambda rgb, depth, X: (rgb, np.full_like(depth, np.nan), X), 40, "no valid depth"),
        (lambda rgb, depth, X: (np.zeros_like(rgb), depth, X), 40, "no object-coloured pixels"),
        (lambda rgb, depth, X: (rgb[:0], depth[:0], X), 40, "empty image"),
        (lambda rgb, depth, X: (rgb, depth, np.full((4, 4), np.nan)), 40, "invalid camera pose"),
        (lambda rgb, depth, X: (rgb, depth, X), 10**5, "no blob of at least 100000 pixels"),
    ],
    ids=["nan_depth", "black_image", "zero_size", "nan_pose", "blobs_too_small"],
)
def test_degraded_frames_give_no_detections_and_say_why(synthetic, degrade, min_pixels, status):
    rgb, depth, X_WC = degrade(*synthetic[:3])
    result = detect_objects(rgb, depth, CAMERA, X_WC, settings=DetectorSettings(min_pixels))
    assert result == DetectionResult((), status)


def test_camera_facing_away_sees_only_sky():
    X_WC = camera_pose(yaw=np.pi, tilt=-0.6)  # up and away: the whole view is sky
    rgb, depth, silhouettes = render(CAMERA, X_WC, with_person=False)
    assert not any(mask.any() for mask in silhouettes.values()) and np.all(np.isinf(depth))
    assert detect_objects(rgb, depth, CAMERA, X_WC) == DetectionResult((), "no valid depth")


def test_images_of_the_wrong_size_are_a_wiring_error(synthetic):
    rgb, depth, X_WC, _ = synthetic
    with pytest.raises(ValueError, match="sizes differ"):
        detect_objects(rgb, depth, CAMERA.scaled(200, 200), X_WC)


@pytest.mark.parametrize(
    ("palette", "problem"),
    [
        ({"red": (0.9, 0.1, 0.1), "dark_red": (0.5, 0.05, 0.05)}, "same hue"),
        ({"red": (0.9, 0.1, 0.1), "grey": (0.5, 0.5, 0.55)}, "too grey"),
    ],
)
def test_a_palette_colour_alone_cannot_separate_is_refused_up_front(palette, problem):
    with pytest.raises(ValueError, match=problem):
        ObjectDetector(CAMERA, palette)


def _fix_inputs(system: ObjectDetector, context, rgb, depth, X_WC) -> None:
    height, width = depth.shape
    color_image, depth_image = ImageRgba8U(width, height), ImageDepth32F(width, height)
    color_image.mutable_data[:, :, :3] = rgb
    color_image.mutable_data[:, :, 3] = 255
    depth_image.mutable_data[:, :, 0] = depth
    system.GetInputPort("color_image").FixValue(context, color_image)
    system.GetInputPort("depth_image").FixValue(context, depth_image)
    system.GetInputPort("camera_pose").FixValue(context, RigidTransform(X_WC))


def test_leaf_system_detects_on_fixed_inputs(synthetic):
    rgb, depth, X_WC, _ = synthetic
    detector = ObjectDetector(CAMERA)
    context = detector.CreateDefaultContext()
    _fix_inputs(detector, context, rgb, depth, X_WC)
    result = detector.GetOutputPort("detections").Eval(context)
    _assert_centers(result, {cup.color: cup.center for cup in CUPS})


def test_leaf_system_reports_an_empty_frame():
    detector = ObjectDetector(CAMERA)
    context = detector.CreateDefaultContext()
    _fix_inputs(detector, context, np.zeros((0, 0, 3), np.uint8), np.zeros((0, 0)), np.eye(4))
    assert detector.GetOutputPort("detections").Eval(context) == DetectionResult((), "empty image")


@pytest.fixture(
    scope="module",
    params=[("demo.yaml", 0.0), ("point_center.yaml", -0.65)],
    ids=["demo_0.9m", "point_center_1.5m"],
)
def rendered_scene(request):
    """The station a few frames in with an ObjectDetector on its camera; the second scene backs
    the robot off so that the cups are 1.5 m from the camera."""
    name, base_x = request.param
    scenario = load_scenario(SCENARIOS / name)
    scenario.robot.base_pose = [base_x, 0.0, 0.0]
    scenario.handover.enabled = False  # the head stays on the table (no look round)
    builder = DiagramBuilder()
    station, _ = add_station_and_robot(builder, scenario)
    detector = builder.AddSystem(ObjectDetector(scenario.camera.pinhole()))
    for station_port, detector_port in (
        ("camera_color_image", "color_image"),
        ("camera_depth_image", "depth_image"),
        ("camera_pose", "camera_pose"),
    ):
        builder.Connect(
            station.diagram.GetOutputPort(station_port), detector.GetInputPort(detector_port)
        )
    diagram = builder.Build()
    simulator = Simulator(diagram)
    simulator.AdvanceTo(0.1)
    context = simulator.get_context()
    result = detector.GetOutputPort("detections").Eval(detector.GetMyContextFromRoot(context))
    plant_context = station.plant.GetMyContextFromRoot(context)
    plant = station.plant
    truth = {
        obj.color: plant.GetBodyByName(obj.name).EvalPoseInWorld(plant_context).translation()
        for obj in scenario.objects
    }
    return result, truth


def test_rendered_scene_every_object_once_within_target_and_nothing_else(rendered_scene):
    result, truth = rendered_scene
    _assert_centers(result, truth)


def test_a_hand_in_front_of_a_cup_stays_out_of_its_shape():
    """A skin-coloured hand over two thirds of the cup's front, the cup showing round it, lies
    inside the cup's box: the shape is measured on the cup's own pixels (its blob), not
    the box's (over the box, a 7 cm cup reads as a 16 cm box)."""
    cup = CUPS[0]
    X_WC = camera_pose()
    rgb, depth, silhouettes = render(CAMERA, X_WC, (cup,))
    rows, columns = np.nonzero(silhouettes[cup.color])
    middle, right = (rows.min() + rows.max()) // 2, columns.max()
    hand = np.s_[middle - 10 : middle + 10, columns.min() - 12 : (columns.min() + 2 * right) // 3]
    rgb[hand] = np.round(np.array(SKIN) * 255).astype(np.uint8)
    depth[hand] = np.minimum(depth[hand], depth[middle, (columns.min() + right) // 2] - 0.03)
    (detection,) = detect_objects(rgb, depth, CAMERA, X_WC).detections
    assert detection.blob is not None and detection.blob.shape == (
        detection.box[3] - detection.box[1] + 1,
        detection.box[2] - detection.box[0] + 1,
    )
    own = fit_shape(cup.color, object_points(detection, depth, CAMERA, X_WC, TABLE_HEIGHT),
                    TABLE_HEIGHT)  # fmt: skip
    assert own.kind == CYLINDER and own.radius < cup.radius + 0.01
    np.testing.assert_allclose(own.center, cup.center[:2], atol=0.015)
    whole_box = dataclasses.replace(detection, blob=None)
    merged = fit_shape(cup.color, object_points(whole_box, depth, CAMERA, X_WC, TABLE_HEIGHT),
                       TABLE_HEIGHT)  # fmt: skip
    assert merged.radius > own.radius + 0.005  # the hand, within the box, joins the footprint
