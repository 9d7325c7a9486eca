"""The simulated skeleton sensor (paper 3.2): COCO-18 keypoints projected, noisy, dropped and
hidden as a detector would report them, lifted with depth; OpenPose JSON; the Drake systems;
and the sensor on the rendered pointing scene."""

from __future__ import annotations

import dataclasses
import io

import numpy as np
import pytest
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.analysis import Simulator
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS, FACE_KEYPOINTS, keypoint_index
from hsr_handover.interface.keypoints import NOT_IN_VIEW, Detection
from hsr_handover.interface.openpose_json import (
    read_openpose_frames,
    read_openpose_json,
    to_openpose_dict,
    write_openpose_json,
)
from hsr_handover.robot.intent.rays import face_normal
from hsr_handover.robot.perception.skeleton import (
    NO_VALID_DEPTH,
    Skeleton,
    lift_detection,
    lift_keypoints,
)
from hsr_handover.robot.systems.skeleton_lifter import SkeletonLifter
from hsr_handover.scenario import load_scenario, object_center
from hsr_handover.simulation import build_simulation
from hsr_handover.world.sensors.detector_model import DetectorModel, DetectorState
from hsr_handover.world.sensors.pose_detector import detect_keypoints
from hsr_handover.world.systems.skeleton_sensor import RecordedSkeletonSource, SkeletonSensor
from tests.paths import SCENARIOS
from tests.synthetic_person_image import (
    CAMERA,
    KEYPOINTS,
    SURFACE_OFFSET,
    X_WC,
    synthetic_depth,
)

EXACT = dataclasses.replace(DetectorModel.ideal(), pixel_sigma=0.0, miss_rate=(0.0,) * 4)
IDEAL = DetectorModel.ideal()
ANKLES = [keypoint_index("r_ankle"), keypoint_index("l_ankle")]
WRIST = keypoint_index("r_wrist")


def _simulate(depth=None, noise=EXACT, seed=0, X=X_WC, state=None) -> Skeleton:
    depth = synthetic_depth() if depth is None else depth
    # The simulated sensor, then the robot's lifting of what it reported.
    rng = np.random.default_rng(seed)
    detection = detect_keypoints(KEYPOINTS, CAMERA, X, depth, noise, rng, state)
    return lift_detection(detection, depth, CAMERA, X)


def test_exact_detection_is_the_projection_and_lifts_the_surface():
    skeleton = _simulate()
    pixels, z = CAMERA.project(KEYPOINTS, X_WC)
    in_image = np.ones(18, dtype=bool)
    in_image[ANKLES] = False
    assert skeleton.status == "ok"
    np.testing.assert_array_equal(skeleton.visible, in_image)
    np.testing.assert_array_equal(skeleton.pixels[in_image], pixels[in_image])
    assert np.isnan(skeleton.pixels[ANKLES]).all() and np.isnan(skeleton.points[ANKLES]).all()
    surface = CAMERA.deproject(pixels, z - SURFACE_OFFSET, X_WC)
    np.testing.assert_allclose(skeleton.points[in_image], surface[in_image], atol=1e-6)
    assert np.all((skeleton.confidence[in_image] >= 0.6) & (skeleton.confidence[in_image] <= 0.9))
    wrist = skeleton.keypoint("r_wrist")
    assert wrist.confidence > 0 and np.allclose(wrist.point, surface[WRIST], atol=1e-6)


def test_pixel_noise_has_the_configured_sigma():
    noise = dataclasses.replace(EXACT, pixel_sigma=3.0)
    depth, true_pixels = synthetic_depth(), CAMERA.project(KEYPOINTS, X_WC)[0]
    errors = []
    for seed in range(200):
        detection = detect_keypoints(
            KEYPOINTS, CAMERA, X_WC, depth, noise, np.random.default_rng(seed)
        )
        visible = detection.confidence > 0
        errors.append((detection.pixels - true_pixels)[visible])
    errors = np.concatenate(errors)
    assert len(errors) > 3000
    assert abs(errors.mean()) < 0.2
    assert errors.std() == pytest.approx(3.0, rel=0.08)


def test_keypoints_outside_the_image_are_missing():
    # Move the camera 0.85 m sideways: the keypoints on one side leave the image.
    X = np.eye(4)
    X[0, 3] = -0.85
    skeleton = _simulate(X=X)
    pixels, _ = CAMERA.project(KEYPOINTS, X)
    outside = ~CAMERA.contains(pixels)
    assert outside.any() and not outside.all()
    assert np.all(skeleton.confidence[outside] == 0)
    assert np.all(CAMERA.contains(skeleton.pixels[skeleton.visible]))


def test_an_occluder_hides_the_wrist_and_nothing_else():
    depth = synthetic_depth()
    u, v = np.rint(CAMERA.project(KEYPOINTS[[WRIST]], X_WC)[0][0]).astype(int)
    depth[v - 4 : v + 5, u - 4 : u + 5] = 1.2
    noise = dataclasses.replace(IDEAL, pixel_sigma=1.0, miss_rate=(0.3, 0, 0, 0))
    clear, occluded = _simulate(noise=noise, seed=5), _simulate(depth, noise=noise, seed=5)
    assert clear.confidence[WRIST] > 0 and occluded.confidence[WRIST] == 0
    others = np.arange(18) != WRIST
    np.testing.assert_array_equal(occluded.confidence[others], clear.confidence[others])
    np.testing.assert_array_equal(occluded.pixels[others], clear.pixels[others])


def test_own_limb_in_front_of_a_joint_does_not_hide_it():
    # A forearm pointing at the camera covers its elbow 10 cm in front: still the elbow.
    depth = synthetic_depth()
    elbow = keypoint_index("r_elbow")
    u, v = np.rint(CAMERA.project(KEYPOINTS[[elbow]], X_WC)[0][0]).astype(int)
    depth[v - 4 : v + 5, u - 4 : u + 5] = KEYPOINTS[elbow, 2] - 0.10
    assert _simulate(depth).confidence[elbow] > 0


def test_keypoints_in_a_missed_run_are_missing():
    face = [keypoint_index(name) for name in FACE_KEYPOINTS]
    missing = np.isin(np.arange(len(KEYPOINTS)), face)
    state = dataclasses.replace(DetectorState.start(), missing=missing)
    assert np.all(_simulate(state=state).confidence[face] == 0)
    assert np.all(_simulate(state=state).confidence[keypoint_index("neck")] > 0)
    for seed in range(20):
        assert np.all(_simulate(noise=EXACT, seed=seed).confidence[face] > 0)


def test_lifting_uses_the_window_median_and_keeps_pixels_without_depth():
    depth = synthetic_depth()
    pixels, z = CAMERA.project(KEYPOINTS, X_WC)
    confidence = np.full(18, 0.8)
    confidence[ANKLES] = 0.0
    neck, wrist = keypoint_index("neck"), WRIST
    (nu, nv), (wu, wv) = np.rint(pixels[[neck, wrist]]).astype(int)
    depth[nv, nu] = np.nan  # a hole exactly at the neck: its neighbours still lift it
    depth[wv - 10 : wv + 11, wu - 10 : wu + 11] = np.inf  # no depth around the wrist at all
    skeleton = lift_keypoints(pixels, confidence, depth, CAMERA, X_WC)
    expected = CAMERA.deproject(pixels[neck], z[neck] - SURFACE_OFFSET, X_WC)[0]
    np.testing.assert_allclose(skeleton.points[neck], expected, atol=1e-6)
    assert skeleton.confidence[wrist] == 0 and np.isnan(skeleton.points[wrist]).all()
    np.testing.assert_array_equal(skeleton.pixels[wrist], pixels[wrist])
    assert skeleton.status == "ok"


def test_all_nan_depth_gives_an_empty_skeleton_that_says_why():
    depth = np.full((CAMERA.height, CAMERA.width), np.nan, dtype=np.float32)
    skeleton = _simulate(depth, noise=IDEAL)
    assert skeleton.is_empty and np.all(skeleton.confidence == 0)
    assert skeleton.status == NO_VALID_DEPTH


def test_camera_facing_away_sees_no_person():
    turned = X_WC @ RigidTransform(RollPitchYaw(0, np.pi, 0), np.zeros(3)).GetAsMatrix4()
    skeleton = _simulate(noise=IDEAL, X=turned)
    assert skeleton.is_empty and np.all(skeleton.confidence == 0)
    assert skeleton.status == NOT_IN_VIEW
    assert np.isnan(skeleton.pixels).all() and np.isnan(skeleton.points).all()


def test_openpose_json_round_trip(tmp_path):
    noisy = _simulate(noise=dataclasses.replace(IDEAL, miss_rate=(0.5, 0, 0, 0)), seed=3)
    people = [noisy.detection(), _simulate().detection()]
    path = tmp_path / "frame_000000000000_keypoints.json"
    write_openpose_json(path, people)
    stream = io.StringIO()
    write_openpose_json(stream, people)
    stream.seek(0)
    for read_back in (read_openpose_json(path), read_openpose_json(stream)):
        assert len(read_back) == 2
        for original, again in zip(people, read_back, strict=True):
            np.testing.assert_array_equal(again.pixels, original.pixels)
            np.testing.assert_array_equal(again.confidence, original.confidence)
    values = to_openpose_dict(people)["people"][0]["pose_keypoints_2d"]
    assert len(values) == 54 and values[3 * ANKLES[0] : 3 * ANKLES[0] + 3] == [0.0, 0.0, 0.0]


def test_malformed_openpose_json_names_the_file_and_the_problem(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"version": 1.3, "people": [{"pose_keypoints_2d": ' + str([1.0] * 50) + "}]}")
    expected = (
        r"bad\.json: people\[0\]\.pose_keypoints_2d: expected 54 numbers \(18 keypoints x 3\)"
    )
    with pytest.raises(ValueError, match=expected + ", got 50"):
        read_openpose_json(path)
    path.write_text("{not json")
    with pytest.raises(ValueError, match=r"bad\.json: expected OpenPose JSON"):
        read_openpose_json(path)
    empty = tmp_path / "empty.json"
    empty.write_text('{"version": 1.3, "people": []}')
    assert read_openpose_json(empty) == [] and read_openpose_frames([empty])[0].status != "ok"


# The station: point_left.yaml mid-gesture, the right hand pointing across to the red cup.


@pytest.fixture(scope="module")
def pointing_scene():
    """The scene at 3 s with a depth image rendered at that moment (the camera is slowed to
    render only at 0 s and 3 s), the world's sensor inputs then, and the true keypoints."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.camera.rate_hz = 1.0 / 3.0
    scenario.camera.render_label = False
    simulation = build_simulation(scenario)
    station = simulation.station
    simulator = Simulator(simulation.diagram)
    simulator.AdvanceTo(3.001)  # the capture at 3 s runs at the start of the next step
    context = simulator.get_context()
    plant_context = station.plant.GetMyContextFromRoot(context)
    station_context = simulation.station_context(context)
    inputs = {
        "body_poses": station.plant.get_body_poses_output_port().Eval(plant_context),
        "depth_image": station.diagram.GetOutputPort("camera_depth_image").Eval(station_context),
        "camera_pose": station.diagram.GetOutputPort("camera_pose").Eval(station_context),
    }
    truth = np.array([
        station.plant.GetFrameByName(f"coco_{name}", station.person)
        .CalcPoseInWorld(plant_context).translation()
        for name in COCO18_KEYPOINTS
    ])  # fmt: skip
    return station, inputs, truth


def _fixed_context(system, inputs: dict, time: float = 3.0):
    context = system.CreateDefaultContext()
    context.SetTime(time)
    for name, value in inputs.items():
        system.GetInputPort(name).FixValue(context, value)
    return context


def _sensor(station, noise=None, seed=0) -> SkeletonSensor:
    camera = station.scenario.camera.pinhole()
    return SkeletonSensor(station.plant, station.person, camera, 1.0 / 30.0, noise, seed)


def _captured_context(sensor: SkeletonSensor, inputs: dict, time: float = 3.0):
    """The sensor's own context after a capture at `time` with `inputs`."""
    context = _fixed_context(sensor, inputs, time)
    sensor.ExecuteInitializationEvents(context)
    return context


def _lift(station, detection, inputs: dict):
    lifter = SkeletonLifter(station.scenario.camera.pinhole())
    given = {k: v for k, v in inputs.items() if k != "body_poses"}
    context = _fixed_context(lifter, {**given, "keypoints": detection})
    return lifter.GetOutputPort("skeleton").Eval(context)


def _skeleton(station, inputs: dict, noise=None, seed=0):
    """What the robot makes of the world's sensor at 3 s: the detection, lifted."""
    sensor = _sensor(station, noise, seed)
    detection = sensor.GetOutputPort("keypoints").Eval(_captured_context(sensor, inputs))
    return _lift(station, detection, inputs)


def test_sensor_reports_nothing_before_its_first_capture(pointing_scene):
    station, inputs, _ = pointing_scene
    sensor = _sensor(station)
    detection = sensor.GetOutputPort("keypoints").Eval(_fixed_context(sensor, inputs))
    assert detection.status == "no capture yet" and not (detection.confidence > 0).any()


def test_sensor_is_reproducible_per_capture_and_holds_it_between_captures(pointing_scene):
    station, inputs, truth = pointing_scene
    sensor = _sensor(station, seed=7)
    port = sensor.GetOutputPort("keypoints")
    context = _captured_context(sensor, inputs, 3.0)
    first = port.Eval(context)
    keypoints, time = sensor.captured(context)
    np.testing.assert_allclose(keypoints, truth, atol=1e-9)
    assert time == 3.0
    # Evaluated later, with the person moved, the output is still that capture's detection.
    moved = [RigidTransform([0.3, 0.0, 0.0]) @ pose for pose in inputs["body_poses"]]
    sensor.GetInputPort("body_poses").FixValue(context, moved)
    context.SetTime(3.02)
    np.testing.assert_array_equal(port.Eval(context).pixels, first.pixels)
    again = port.Eval(_captured_context(sensor, inputs, 3.0))
    later = port.Eval(_captured_context(sensor, inputs, 3.1))
    np.testing.assert_array_equal(again.pixels, first.pixels)
    assert not np.array_equal(later.pixels, first.pixels, equal_nan=True)  # new capture, new noise
    no_image = _captured_context(sensor, {**inputs, "depth_image": ImageDepth32F()})
    assert port.Eval(no_image).status == "no depth image"


def test_sensor_captures_the_person_at_the_cameras_capture_instant():
    """In the whole simulation the detector's keypoints are the person's pose at the last
    camera capture, not at the moment someone evaluates them."""
    scenario = load_scenario(SCENARIOS / "point_left.yaml")
    scenario.camera.rate_hz = 10.0
    scenario.camera.render_label = False
    simulation = build_simulation(scenario)
    station = simulation.station
    sensor = station.diagram.GetSubsystemByName("pose_detector")
    simulator = Simulator(simulation.diagram)
    # The capture at 1.2 s and the camera's render read the plant's (sampled) outputs in the
    # same event; until the plant's next step at 1.202 s they still show that instant.
    simulator.AdvanceTo(1.2001)  # the arm is rising to point: it moves between captures
    at_capture = sensor.keypoints_in_world(sensor.GetMyContextFromRoot(simulator.get_context()))
    port = station.diagram.GetOutputPort("skeleton_keypoints")
    detections, held_keypoints = [], []
    for now in (1.2001, 1.29):  # between the capture at 1.2 s and the next at 1.3 s
        simulator.AdvanceTo(now)
        context = simulator.get_context()
        station_context = simulation.station_context(context)
        detections.append(port.Eval(station_context))
        held, time = sensor.captured(sensor.GetMyContextFromRoot(context))
        held_keypoints.append(held)
        image_time = station.diagram.GetOutputPort("camera_image_time").Eval(station_context)
        assert time == pytest.approx(1.2) and image_time == pytest.approx(1.2)
        np.testing.assert_allclose(held, at_capture, atol=1e-12)
    wrist = keypoint_index("r_wrist")
    now = sensor.keypoints_in_world(sensor.GetMyContextFromRoot(context))
    assert np.linalg.norm(now[wrist] - held_keypoints[0][wrist]) > 0.003  # the person moved on
    np.testing.assert_array_equal(detections[1].pixels, detections[0].pixels)


def test_sensor_sees_the_pointing_arm_where_it_is(pointing_scene):
    station, inputs, truth = pointing_scene
    camera = station.scenario.camera.pinhole()
    skeleton = _skeleton(station, inputs, EXACT)
    assert skeleton.status == "ok"
    # The upper body is in view, in front of the table; hips and legs are behind it or below.
    upper = [keypoint_index(n) for n in ("nose", "neck", "r_shoulder", "r_elbow", "r_wrist")]
    assert np.all(skeleton.confidence[upper] > 0)
    assert np.all(skeleton.confidence[[keypoint_index(n) for n in ("r_hip", "l_hip")]] == 0)
    assert np.all(camera.contains(skeleton.pixels[skeleton.visible]))
    X_WC = inputs["camera_pose"].GetAsMatrix4()
    projected = camera.project(truth, X_WC)[0]
    pixel_error = np.linalg.norm(skeleton.pixels - projected, axis=1)[skeleton.visible]
    assert np.all(pixel_error < 4 * 2.0 * np.sqrt(2))
    for name in ("r_shoulder", "r_elbow", "r_wrist"):
        i = keypoint_index(name)
        offset = skeleton.points[i] - truth[i]
        ray = truth[i] - X_WC[:3, 3]
        ray /= np.linalg.norm(ray)
        # The body surface seen at the pixel: in front of the joint along the viewing ray
        # (most for the shoulder, whose raised arm covers it), barely off it sideways.
        assert -0.17 < offset @ ray < 0.0, name
        assert np.linalg.norm(offset - (offset @ ray) * ray) < 0.03, name
    assert np.linalg.norm(skeleton.points[WRIST] - truth[WRIST]) < 0.06


def test_lifted_pointing_ray_hits_the_target(pointing_scene):
    station, inputs, _ = pointing_scene
    skeleton = _skeleton(station, inputs, seed=1)
    shoulder, wrist = skeleton.keypoint("r_shoulder").point, skeleton.keypoint("r_wrist").point
    scenario = station.scenario
    centers = {obj.name: object_center(scenario, obj) for obj in scenario.objects}
    target = scenario.person.behavior[-1].target

    def angle(center):
        a, b = wrist - shoulder, center - shoulder
        return np.degrees(np.arccos(a @ b / np.linalg.norm(a) / np.linalg.norm(b)))

    assert angle(centers[target]) < 10.0
    assert all(angle(c) > angle(centers[target]) for n, c in centers.items() if n != target)


def test_lifter_reads_the_face_from_the_heads_shape_in_the_rendered_depth(pointing_scene):
    """The realistic detector's face keypoints, lifted, turn eq. 17 by degrees; the face
    read from the rendered head's shape is the person's to within a degree or two."""
    station, inputs, truth = pointing_scene
    nose, r_eye, l_eye = (truth[keypoint_index(n)] for n in ("nose", "r_eye", "l_eye"))
    true_face = face_normal(nose, r_eye, l_eye)
    for seed in range(3):
        skeleton = _skeleton(station, inputs, DetectorModel(), seed=seed)
        assert np.isfinite(skeleton.face_forward).all()
        turn = np.degrees(
            np.arctan2(skeleton.face_forward[1], skeleton.face_forward[0])
            - np.arctan2(true_face[1], true_face[0])
        )
        assert abs((turn + 180.0) % 360.0 - 180.0) < 2.0


def test_lifter_says_why_a_skeleton_is_empty(pointing_scene):
    station, inputs, _ = pointing_scene
    assert _lift(station, Detection.missing(NOT_IN_VIEW), inputs).status == NOT_IN_VIEW
    no_depth = {**inputs, "depth_image": ImageDepth32F()}
    sensor = _sensor(station)
    detection = sensor.GetOutputPort("keypoints").Eval(_captured_context(sensor, inputs))
    assert _lift(station, detection, no_depth).status == "no depth image"


def test_recorded_detections_replay_through_the_same_lifting(pointing_scene, tmp_path):
    station, inputs, _ = pointing_scene
    sensor = _sensor(station, seed=2)
    live = sensor.GetOutputPort("keypoints").Eval(_captured_context(sensor, inputs))
    path = tmp_path / "frame.json"
    write_openpose_json(path, [live])
    source = RecordedSkeletonSource(read_openpose_frames([path]), 10.0)
    port = source.GetOutputPort("keypoints")
    replayed = port.Eval(_fixed_context(source, {}, 0.05))
    np.testing.assert_array_equal(
        _lift(station, replayed, inputs).points, _lift(station, live, inputs).points
    )
    assert port.Eval(_fixed_context(source, {}, 0.1)).status == "recording ended"


def _captures(sensor: SkeletonSensor, inputs: dict, count: int) -> list:
    """The sensor's detections of `count` captures at 30 Hz from t = 0 (its own context)."""
    context = _fixed_context(sensor, inputs, 0.0)
    simulator = Simulator(sensor, context)
    simulator.Initialize()
    detections = []
    for k in range(count):
        simulator.AdvanceTo(k / 30.0 + 1e-4)
        detections.append(sensor.GetOutputPort("keypoints").Eval(context))
    return detections


def test_sensor_carries_the_detectors_bias_from_capture_to_capture(pointing_scene):
    """A bias persists: consecutive captures differ far less than with the same error drawn
    anew each frame."""
    station, inputs, _ = pointing_scene
    exact = dict(miss_rate=(0.0,) * 4, swap_rate=0.0, spurious_rate=0.0, confidence_spread=0.0)

    def frame_to_frame(bias_share: float) -> float:
        model = DetectorModel(bias_share=bias_share, **exact)
        pixels = np.array([d.pixels for d in _captures(_sensor(station, model), inputs, 12)])
        return float(np.nanmean(np.abs(np.diff(pixels, axis=0))))

    assert frame_to_frame(1.0) < 0.2 * frame_to_frame(0.0)


def test_sensor_reports_a_wrist_on_an_object_near_it(pointing_scene):
    station, inputs, truth = pointing_scene
    cup = station.plant.GetBodyIndices(next(iter(station.objects.values())))[0]
    model = DetectorModel(
        joint_error_m=0.0, miss_rate=(0.0,) * 4, swap_rate=0.0, spurious_rate=0.9,
        spurious_run_s=1.0, spurious_reach_m=2.0,
    )  # fmt: skip
    camera = station.scenario.camera.pinhole()
    sensor = SkeletonSensor(station.plant, station.person, camera, 1.0 / 30.0, model, 0, [cup])
    on_cup = sensor.GetInputPort("body_poses").Eval(_fixed_context(sensor, inputs))[int(cup)]
    cup_pixel, _ = camera.project(on_cup.translation()[None], inputs["camera_pose"].GetAsMatrix4())
    wrists = [d.pixels[keypoint_index("r_wrist")] for d in _captures(sensor, inputs, 10)]
    on_object = [np.linalg.norm(w - cup_pixel[0]) < 1.0 for w in wrists if np.isfinite(w).all()]
    assert sum(on_object) >= 5
