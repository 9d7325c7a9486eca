"""The intent recogniser on synthetic skeletons: eqs. 16-17, rays, one frame, the dwell."""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np
import pytest

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.robot.intent import IntentParams, IntentTracker, Ray, elbow_angle_deg, face_normal
from hsr_handover.robot.intent.judging import (
    ARM_MOVING,
    ARM_NOT_RAISED,
    GAZE_ELSEWHERE,
    NO_CANDIDATES,
    NO_FACE,
    NO_POINTING,
    NO_SKELETON,
    NOTHING_POINTED_AT,
    POINTING,
    RECOGNISED,
    Observation,
    judge,
    judge_frame,
    observe,
)
from hsr_handover.robot.intent.person_rays import (
    ARMS,
    L_EYE,
    NOSE,
    R_EYE,
    bearing_errors_deg,
    bearing_tolerance_deg,
    face_ray,
    gaze_ray,
    pitch_errors_deg,
    pitch_tolerance_deg,
    torso_forward,
)
from hsr_handover.robot.intent.rays import (
    heading_elevation,
    ray_distances,
    tilt_down,
    unit_direction,
)
from hsr_handover.robot.intent.smoothing import RaySmoother
from hsr_handover.world.person.aiming import pointing_arm_angles
from hsr_handover.world.person.behavior import reaching_arm_angles
from tests.robot.intent.synthetic_person import BODY, CUPS, TRUE_FACE_TILT, keypoints, to_person

R_SHOULDER, R_ELBOW, R_WRIST = ARMS["right"]


def _without(confidence: np.ndarray, *names: str) -> np.ndarray:
    confidence = confidence.copy()
    confidence[[keypoint_index(name) for name in names]] = 0.0
    return confidence


def test_elbow_angle_is_eq_16():
    assert elbow_angle_deg([0, 0, 1], [0, 0, 0], [0, 0, -1]) == pytest.approx(180.0)
    assert elbow_angle_deg([0, 0, 1], [0, 0, 0], [1, 0, 0]) == pytest.approx(90.0)
    assert math.isnan(elbow_angle_deg([0, 0, 0], [0, 0, 0], [1, 0, 0]))


def test_face_normal_faces_away_from_the_head_and_tilts_up_by_the_face_tilt():
    points, _ = keypoints()  # head level-ish (pitch 0.2 down), facing -x
    nose, r_eye, l_eye = (points[keypoint_index(n)] for n in ("nose", "r_eye", "l_eye"))
    normal = face_normal(nose, r_eye, l_eye)
    assert normal[0] < -0.8  # toward the robot, away from the back of the head
    # The synthetic face's nose is 0.18 head radii ahead of the eyes and 0.42 below them;
    # the default (30 deg) is measured on lifted skeletons, whose eyes read deeper.
    level = tilt_down(normal, math.degrees(math.atan2(0.18, 0.42)))
    pitch_down = math.degrees(-math.asin(level[2]))
    assert pitch_down == pytest.approx(math.degrees(0.2), abs=1.0)  # the head's own pitch
    assert face_normal(nose, nose, nose) is None


def test_the_face_is_the_head_shapes_direction_where_it_is_found_and_eq_17_elsewhere():
    points, confidence = keypoints()
    eyes = (points[R_EYE] + points[L_EYE]) / 2
    shape = unit_direction(math.radians(170.0), math.radians(-25.0))
    params = IntentParams()
    from_shape = face_ray(points, confidence, params, shape)
    np.testing.assert_allclose(from_shape.direction, shape)
    np.testing.assert_allclose(from_shape.origin, eyes)
    without_eyes = face_ray(points, _without(confidence, "r_eye"), params, shape)
    np.testing.assert_allclose(without_eyes.origin, points[NOSE])  # eq. 17 would need both
    eq_17 = face_ray(points, confidence, params)
    for forward in (None, np.full(3, np.nan)):
        np.testing.assert_allclose(face_ray(points, confidence, params, forward).direction,
                                   eq_17.direction)  # fmt: skip
    paper = IntentParams(face_from_head_shape=False)
    np.testing.assert_allclose(face_ray(points, confidence, paper, shape).direction,
                               eq_17.direction)  # fmt: skip
    assert face_ray(points, _without(confidence, "r_eye", "l_eye", "nose"), params, shape) is None


def test_a_frame_judges_the_gaze_along_the_head_shapes_direction():
    """Eyes read toward the neighbour by eq. 17 ask for the cup the head's shape faces."""
    label, center = CUPS[0]
    points, confidence = keypoints(look_at=CUPS[1][1], point_with="right", point_at=center)
    eyes = (points[R_EYE] + points[L_EYE]) / 2
    forward = torso_forward(points, confidence, "right")
    toward = (center - eyes) / np.linalg.norm(center - eyes)
    # The face makes 1 / head_gain of the eyes' turn from the torso: the head's shape reads it.
    params = IntentParams()
    turn = math.atan2(np.cross(forward, toward)[2], forward @ toward) / params.head_gain
    heading = math.atan2(forward[1], forward[0]) + turn
    pitch = math.asin(toward[2]) / params.head_gain
    shape = unit_direction(heading, pitch)
    centers = np.array([c for _, c in CUPS])
    assert judge(observe(points, confidence, centers, params, shape), CUPS, params).candidate == (
        label
    )
    assert judge(observe(points, confidence, centers, params), CUPS, params).candidate != label


def test_ray_distance_is_perpendicular_ahead_and_to_the_origin_behind():
    ray = Ray.through([0, 0, 0], [1, 0, 0])
    distances = ray_distances(ray, np.array([[2.0, 0.5, 0.0], [-1.0, 0.0, 0.0]]))
    np.testing.assert_allclose(distances, [0.5, 1.0])
    assert Ray.through([1, 1, 1], [1, 1, 1]) is None


@pytest.mark.parametrize("arm", ["right", "left"])
@pytest.mark.parametrize("index", [0, 1, 2])
def test_a_frame_pointing_and_looking_at_a_cup_names_it(arm, index):
    label, center = CUPS[index]
    points, confidence = keypoints(look_at=center, point_with=arm, point_at=center)
    judgement = judge_frame(points, confidence, CUPS, IntentParams())
    assert (judgement.candidate, judgement.status, judgement.arm) == (label, POINTING, arm)
    assert judgement.elbow_angle_deg == pytest.approx(180.0, abs=1e-4)
    assert judgement.clarity > 0.5


def test_the_ray_kinds_start_where_they_say():
    label, center = CUPS[2]
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    starts = {
        "shoulder_wrist": points[keypoint_index("r_shoulder")],
        "elbow_wrist": points[keypoint_index("r_elbow")],
        "eye_wrist": (points[keypoint_index("r_eye")] + points[keypoint_index("l_eye")]) / 2,
    }
    for kind, start in starts.items():
        judgement = judge_frame(points, confidence, CUPS, IntentParams(pointing_ray=kind))
        np.testing.assert_allclose(judgement.pointing.origin, start)
    # This arm lies on the shoulder-to-cup line, so the forearm's ray finds the cup too.
    elbow = judge_frame(points, confidence, CUPS, IntentParams(pointing_ray="elbow_wrist"))
    assert elbow.candidate == label


@pytest.mark.parametrize("arm", ["right", "left"])
def test_an_arm_hiding_its_own_shoulder_points_from_the_torsos_mirror_of_the_other(arm):
    label, center = CUPS[1]
    points, confidence = keypoints(look_at=center, point_with=arm, point_at=center)
    own, other = (keypoint_index(f"{side}_shoulder") for side in ("rl" if arm == "right" else "lr"))
    points[keypoint_index("neck")] = (points[own] + points[other]) / 2  # OpenPose's neck
    hidden = _without(confidence, f"{arm[0]}_shoulder")
    judgement = judge_frame(points, hidden, CUPS, IntentParams())
    assert (judgement.candidate, judgement.arm) == (label, arm)
    np.testing.assert_allclose(judgement.pointing.origin, points[own])
    no_torso = _without(hidden, "neck")
    assert judge_frame(points, no_torso, CUPS, IntentParams()).status == NO_POINTING


def test_frames_that_do_not_ask_say_why():
    _, center = CUPS[0]
    params = IntentParams()
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    assert judge_frame(points, np.zeros(18), CUPS, params).status == NO_SKELETON
    assert judge_frame(points, confidence, [], params).status == NO_CANDIDATES
    bent = reaching_arm_angles(to_person(center) - BODY.shoulder("right"), BODY)
    bent[3] = -1.2  # an elbow bent by 70 degrees: gesturing, not pointing
    points, confidence = keypoints(look_at=center, point_with="right", arm_angles=bent)
    assert judge_frame(points, confidence, CUPS, params).status == NO_POINTING
    # Pointing at the red cup while looking at the blue one, 44 cm away.
    points, confidence = keypoints(look_at=CUPS[2][1], point_with="right", point_at=center)
    mismatched = judge_frame(points, confidence, CUPS, params)
    assert mismatched.candidate is None
    assert mismatched.status in (GAZE_ELSEWHERE, NOTHING_POINTED_AT)


def test_an_arm_plainly_on_one_cup_outweighs_eyes_a_few_degrees_nearer_its_neighbour():
    """The handover runs' wrong objects (the reference's trial 33 and four on the layouts): the
    arm pointed nearest the cup asked for, the estimated gaze a few degrees nearer the next
    one. With the gaze weighed as the arm (`gaze_weight` 1, `d_min` 0.3), the neighbour won."""
    red, green = CUPS[0][1], CUPS[1][1]
    toward_green = (green - red) / np.linalg.norm(green - red)
    points, confidence = keypoints(
        look_at=red + 0.14 * toward_green, point_with="right", point_at=red + 0.03 * toward_green
    )
    frame = judge_frame(points, confidence, CUPS, IntentParams())
    assert frame.candidate == "red"
    errors = bearing_errors_deg(frame.gaze, np.array([red, green]))
    assert errors[1] < errors[0] < IntentParams().gaze_tolerance_deg  # the eyes favour green
    gaze_as_arm = IntentParams(d_min=0.3, gaze_weight=1.0)
    assert judge_frame(points, confidence, CUPS, gaze_as_arm).candidate == "green"


def test_eyes_looking_over_the_table_do_not_ask_for_the_cup_the_arm_lies_toward():
    """A straight arm toward a cup, the head looking ahead over the table: the estimated gaze
    passes 20 degrees above the cup, beyond `gaze_pitch_tolerance_deg`; looking down at the
    cup, it asks for it. (The synthetic face's tilt is its geometric 23 degrees.)"""
    label, center = CUPS[1]
    params = IntentParams(face_tilt_deg=math.degrees(math.atan2(0.18, 0.42)))
    ahead = np.array([-1.0, 0.0, BODY.eye_z])  # far beyond the table, at eye height
    points, confidence = keypoints(look_at=ahead, point_with="right", point_at=center)
    over = judge_frame(points, confidence, CUPS, params)
    assert (over.candidate, over.status) == (None, GAZE_ELSEWHERE)
    assert pitch_errors_deg(over.gaze, center[None])[0] > params.gaze_pitch_tolerance_deg
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    assert judge_frame(points, confidence, CUPS, params).candidate == label


def test_the_eyes_may_pass_further_above_an_object_they_look_further_down_to():
    """A head that makes less than the usual share of a gaze shift reads above the object by a
    share of the whole look down: `gaze_pitch_tolerance_share` of it, when more than the
    fixed tolerance (a standing person's 45 degrees down, not a seated one's 30)."""
    params = IntentParams()
    eyes = np.array([0.0, 0.0, 1.2])
    seated = eyes + [0.8, 0.1, -0.46]  # 30 degrees down
    standing = eyes + [0.6, 0.6, -0.85]  # 45 degrees down
    assert pitch_tolerance_deg(eyes, seated, params) == params.gaze_pitch_tolerance_deg
    share = params.gaze_pitch_tolerance_share
    assert share == pytest.approx(0.232, abs=0.001)
    assert pitch_tolerance_deg(eyes, standing, params) == pytest.approx(share * 45.0, abs=0.1)
    fixed = IntentParams(gaze_pitch_tolerance_share=0.0)
    assert pitch_tolerance_deg(eyes, standing, fixed) == fixed.gaze_pitch_tolerance_deg
    # judged: the eyes ahead over the table pass 20 degrees above the cup, allowed by a share
    # of the look down to it as large as the whole
    label, center = CUPS[1]
    ahead = np.array([-1.0, 0.0, BODY.eye_z])
    points, confidence = keypoints(look_at=ahead, point_with="right", point_at=center)
    tilt = math.degrees(math.atan2(0.18, 0.42))
    lenient = IntentParams(face_tilt_deg=tilt, gaze_pitch_tolerance_share=1.0)
    assert judge_frame(points, confidence, CUPS, lenient).candidate == label


def _far_side_look(turn_deg: float, short_deg: float, params: IntentParams):
    """A person facing +x whose arm points straight at a cup `turn_deg` to their left and
    whose eyes, read from the face's turn times `head_gain`, fall `short_deg` short of it; a
    second cup as far to the right."""
    eyes, forward = np.array([0.0, 0.0, 1.2]), np.array([1.0, 0.0, 0.0])
    cups = []
    for side in (1.0, -1.0):
        yaw = math.radians(side * turn_deg)
        cups.append(eyes + [0.8 * math.cos(yaw), 0.8 * math.sin(yaw), -0.45])
    toward = cups[0] - eyes
    down = math.atan2(toward[2], math.hypot(toward[0], toward[1]))
    face_yaw = math.radians(turn_deg - short_deg) / params.head_gain
    face = Ray(eyes, unit_direction(face_yaw, down / params.head_gain))
    shoulder = eyes + [0.0, 0.18, -0.25]
    arm = Ray(shoulder, (cups[0] - shoulder) / np.linalg.norm(cups[0] - shoulder))
    observation = Observation("left", 175.0, arm, face, forward, at_object=True)
    return observation, [("near", cups[0]), ("far", cups[1])], eyes, forward


def test_the_eyes_may_miss_an_object_further_to_the_side_by_a_share_of_their_turn_to_it():
    """The gaze is the face's turn times `head_gain`, and a person whose head makes more or less
    of the shift than the usual share misses in proportion to the turn: beyond 52 degrees
    from the torso's front, `gaze_tolerance_share` of the turn allows more than the fixed
    `gaze_tolerance_deg` (an arm plainly on a box 60 degrees to the side, the eyes 13.5
    degrees short of it, is a request; the same eyes on a box ahead are not)."""
    params = IntentParams()
    assert params.gaze_tolerance_share == pytest.approx(0.232, abs=0.001)
    far, candidates, eyes, forward = _far_side_look(60.0, 13.5, params)
    assert bearing_tolerance_deg(eyes, forward, candidates[0][1], params) == pytest.approx(
        params.gaze_tolerance_share * 60.0, abs=0.1
    )
    assert bearing_tolerance_deg(eyes, None, candidates[0][1], params) == 12.0  # no torso
    assert judge(far, candidates, params).candidate == "near"
    fixed = IntentParams(gaze_tolerance_share=0.0)
    assert judge(far, candidates, fixed).status == GAZE_ELSEWHERE
    ahead, candidates, _, _ = _far_side_look(8.0, 13.5, params)
    assert judge(ahead, candidates[:1], params).status == GAZE_ELSEWHERE


def test_the_pitch_is_checked_on_the_face_over_the_longer_window():
    """The horizontal bearing is read from `face`; whether the eyes pass above the object from
    `face_for_pitch` (the face averaged over `pitch_smoothing_s`): a face that has looked
    ahead over the table for most of that window does not ask, though it dips to the cup now."""
    label, center = CUPS[1]
    params = IntentParams(face_tilt_deg=math.degrees(math.atan2(0.18, 0.42)))
    centers = np.array([c for _, c in CUPS])
    ahead = np.array([-1.0, 0.0, BODY.eye_z])
    down = observe(*keypoints(look_at=center, point_with="right", point_at=center), centers,
                   params)  # fmt: skip
    over = observe(*keypoints(look_at=ahead), centers, params)
    asking = dataclasses.replace(down, sweep_deg_s=0.0)
    assert judge(asking, CUPS, params).candidate == label
    looked_over = dataclasses.replace(asking, face_for_pitch=over.face)
    assert judge(looked_over, CUPS, params).status == GAZE_ELSEWHERE


def test_the_smoother_averages_the_face_for_pitch_over_its_own_window():
    smoother = RaySmoother(window=0.2, pitch_window=0.5)
    up, level = (Ray(np.zeros(3), np.array(d)) for d in ([0.6, 0.0, 0.8], [1.0, 0.0, 0.0]))
    smoother.smooth(0.0, Observation(face=up))
    seen = smoother.smooth(0.3, Observation(face=level))
    np.testing.assert_allclose(seen.face.direction, level.direction)  # `up` left the window
    expected = (up.direction + level.direction) / np.linalg.norm(up.direction + level.direction)
    np.testing.assert_allclose(seen.face_for_pitch.direction, expected)
    copied = copy.deepcopy(smoother)
    copied.smooth(0.4, Observation(face=up))
    again = smoother.smooth(0.4, Observation(face=level))  # the copy's frame is its own
    np.testing.assert_allclose(again.face.direction, level.direction)


def test_without_a_face_the_frame_is_unsure():
    label, center = CUPS[1]
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    judgement = judge_frame(points, _without(confidence, "nose"), CUPS, IntentParams())
    assert judgement.status == NO_FACE and not judgement.face_seen
    no_elbow = judge_frame(points, _without(confidence, "r_elbow"), CUPS, IntentParams())
    assert no_elbow.status == NO_POINTING


def _watching(params: IntentParams) -> IntentTracker:
    """A tracker that has watched the person sit at rest for 0.3 s before time 0, so that an arm
    pointing from time 0 has just risen to point (a request is a gesture: `IntentParams.rise_m`)."""
    tracker = IntentTracker(params)
    resting, confidence = keypoints()
    for time in np.arange(-0.3, 0.0, 1 / 30):
        tracker.update(time, resting, confidence, CUPS)
    return tracker


def _frames(tracker, times, confidence_of=lambda t: None, target=1, look=None):
    label, center = CUPS[target]
    points, confidence = keypoints(look_at=center if look is None else look,
                                   point_with="right", point_at=center)  # fmt: skip
    states = []
    for t in times:
        given = confidence_of(t)
        states.append(tracker.update(t, points, confidence if given is None else given, CUPS))
    return states


def test_the_dwell_recognises_after_t_max_and_latches():
    tracker = _watching(IntentParams(t_max=0.5))
    states = _frames(tracker, np.arange(0.0, 1.0, 1 / 30))
    recognised = [s for s in states if s.target is not None]
    # The dwell starts once the arm is known to hold still (RaySmoother.MIN_FRAMES frames).
    start = (RaySmoother.MIN_FRAMES - 1) / 30
    assert recognised[0].recognised_time == pytest.approx(start + 0.5, abs=1 / 30)
    assert all(s.target == "green" and s.status == RECOGNISED for s in recognised)
    assert states[5].target is None and states[5].candidate == "green"
    later = _frames(tracker, [1.2], target=0)[0]  # pointing elsewhere later changes nothing
    assert later.target == "green" and later.recognised_time == recognised[0].recognised_time


def test_a_copy_of_the_tracker_goes_on_alone():
    """Drake copies the tracker (the system's state) at every frame: what the copy sees must
    not reach the original, which goes on as if never copied."""
    original, untouched = (_watching(IntentParams(t_max=0.5)) for _ in range(2))
    for tracker in (original, untouched):
        _frames(tracker, np.arange(0.0, 0.2, 1 / 30), target=0)
    copied = copy.deepcopy(original)
    _frames(copied, np.arange(0.2, 0.6, 1 / 30), target=2)  # the copy sees another request
    later = np.arange(0.2, 1.0, 1 / 30)

    def summary(states):
        return [(s.target, s.recognised_time, s.candidate, s.frame.clarity) for s in states]

    assert summary(_frames(original, later, target=0)) == summary(
        _frames(untouched, later, target=0)
    )
    assert original.state_.target == "red"


def test_face_less_frames_neither_start_nor_finish_but_do_not_break_a_dwell():
    _, confidence = keypoints()
    faceless = _without(confidence, "r_eye")
    tracker = _watching(IntentParams(t_max=0.3))
    # The face is missing for the first 0.2 s: no dwell starts.
    states = _frames(tracker, np.arange(0.0, 0.2, 0.05), lambda t: faceless)
    assert all(s.candidate is None for s in states)
    # Then seen, with a face-less frame in the middle and at the end of the dwell.
    times = np.arange(0.2, 0.9, 0.05)
    states = _frames(tracker, times, lambda t: faceless if abs(t - 0.35) < 1e-9 else None)
    first = next(s for s in states if s.target is not None)
    assert first.recognised_time == pytest.approx(0.5)


def test_changing_the_request_restarts_the_dwell():
    tracker = IntentTracker(IntentParams(t_max=0.3, smoothing_s=0.0))
    _frames(tracker, [0.0, 0.1, 0.2], target=0)
    states = _frames(tracker, [0.25, 0.35, 0.45, 0.55], target=2)
    assert [s.target for s in states] == [None, None, None, "blue"]
    assert states[-1].candidate_since == pytest.approx(0.25)


def test_looking_elsewhere_breaks_the_dwell():
    tracker = _watching(IntentParams(t_max=0.3, smoothing_s=0.0))
    _frames(tracker, [0.0, 0.1, 0.2], target=0)
    broken = _frames(tracker, [0.25], target=0, look=CUPS[2][1] + [0.0, 0.3, 0.0])[0]
    assert broken.candidate is None
    assert broken.frame.status in (GAZE_ELSEWHERE, NOTHING_POINTED_AT)
    states = _frames(tracker, [0.3, 0.4, 0.5, 0.6], target=0)
    assert [s.target for s in states] == [None, None, None, "red"]


@pytest.mark.parametrize(
    "field, value",
    [
        ("straight_arm_deg", 90.0),
        ("d_min", 0.0),
        ("t_max", -1.0),
        ("pointing_ray", "nose"),
        ("gaze_pitch_tolerance_deg", 0.0),
        ("gaze_pitch_tolerance_share", 1.5),
        ("gaze_tolerance_share", -0.1),
        ("gaze_weight", 0.0),
    ],  # fmt: skip
)
def test_params_are_checked(field, value):
    with pytest.raises(ValueError, match=field):
        IntentParams(**{field: value})


def test_smoothing_steadies_a_noisy_face():
    """Face keypoints jittered by 1 cm swing the eq. 17 normal by tens of degrees; the mean of
    the last frames' rays holds it on the cup."""
    label, center = CUPS[0]
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    rng = np.random.default_rng(3)
    face = [keypoint_index(name) for name in ("nose", "r_eye", "l_eye")]

    def recognised(smoothing_s: float) -> bool:
        tracker = _watching(IntentParams(t_max=0.5, smoothing_s=smoothing_s))
        for time in np.arange(0.0, 1.5, 1 / 30):
            noisy = points.copy()
            noisy[face] += rng.normal(0.0, 0.01, (3, 3))
            state = tracker.update(time, noisy, confidence, CUPS)
        return state.target == label

    assert recognised(0.4) and not recognised(0.0)


def test_the_smoother_restarts_the_pointing_ray_when_the_arm_changes():
    smoother = RaySmoother(1.0)
    right = Observation("right", 180.0, Ray.through([0, 0, 0], [1, 0, 0]), None)
    left = Observation("left", 180.0, Ray.through([0, 0, 0], [0, 1, 0]), None)
    smoother.smooth(0.0, right)
    np.testing.assert_allclose(smoother.smooth(0.1, left).pointing.direction, [0, 1, 0])
    mixed = smoother.smooth(0.2, Observation("left", 180.0, Ray.through([0, 0, 0], [1, 0, 0])))
    np.testing.assert_allclose(mixed.pointing.direction, np.array([1, 1, 0]) / np.sqrt(2))


def test_the_torso_faces_square_to_the_shoulders_or_the_hips_or_a_shoulder_and_the_neck():
    """A seated person's hips are under the table, and a shoulder can stay unseen for a whole
    gesture: the neck and the other shoulder still give the torso's direction (without it the
    gaze is the face's own heading, short of the eyes' turn by the eyes' share)."""
    points, confidence = keypoints()
    np.testing.assert_allclose(torso_forward(points, confidence), [-1.0, 0.0, 0.0], atol=1e-9)
    no_shoulder = _without(confidence, "r_shoulder")
    np.testing.assert_allclose(torso_forward(points, no_shoulder), [-1.0, 0.0, 0.0], atol=1e-9)
    no_hips = _without(no_shoulder, "l_hip")
    np.testing.assert_allclose(torso_forward(points, no_hips), [-1.0, 0.0, 0.0], atol=0.02)
    assert torso_forward(points, _without(no_hips, "neck")) is None


def test_the_eyes_turn_head_gain_times_as_far_as_the_face():
    face = Ray(np.zeros(3), np.array([math.cos(0.3), math.sin(0.3), -0.2]))
    face = Ray(face.origin, face.direction / np.linalg.norm(face.direction))
    gaze = gaze_ray(face, np.array([1.0, 0.0, 0.0]), IntentParams(head_gain=1.5))
    assert math.atan2(gaze.direction[1], gaze.direction[0]) == pytest.approx(0.45)
    assert math.asin(gaze.direction[2]) == pytest.approx(1.5 * math.asin(face.direction[2]))
    alone = gaze_ray(face, None, IntentParams(head_gain=1.5))  # no torso: the face's heading
    np.testing.assert_allclose(alone.direction[:2] / np.linalg.norm(alone.direction[:2]),
                               face.direction[:2] / np.linalg.norm(face.direction[:2]))  # fmt: skip
    assert alone.direction[2] == pytest.approx(gaze.direction[2])
    errors = bearing_errors_deg(gaze, np.array([[1.0, math.tan(0.45), -5.0], [1.0, 0.0, 0.0]]))
    np.testing.assert_allclose(errors, [0.0, math.degrees(0.45)], atol=1e-9)


def test_a_sweeping_arm_is_read_only_once_it_holds():
    """An arm that swings across the cups (60 deg/s) names none of them; held on the blue cup,
    it names it after the dwell."""
    tracker = IntentTracker(IntentParams(t_max=0.3))
    label, center = CUPS[2]
    start = np.radians([-1.45, 0.5, 0.0, 0.0, 0.0])  # straight, off to the person's left
    final = pointing_arm_angles(to_person(center) - BODY.shoulder("right"))
    states, times = [], np.arange(0.0, 2.0, 1 / 30)
    for time in times:
        swing = min(time / 1.0, 1.0)  # reaches the cup at 1 s, then holds
        angles = start + swing * (final - start)
        points, confidence = keypoints(look_at=center, point_with="right", arm_angles=angles)
        states.append(tracker.update(time, points, confidence, CUPS))
    sweeping = [s for s, t in zip(states, times, strict=True) if 0.2 < t < 0.9]
    assert all(s.candidate is None and s.frame.status == ARM_MOVING for s in sweeping)
    assert states[-1].target == label and states[-1].recognised_time > 1.3


def test_a_face_dropped_for_a_frame_is_the_windows_face_and_one_long_gone_is_none():
    points, confidence = keypoints(look_at=CUPS[0][1], point_with="right", point_at=CUPS[0][1])
    faceless = _without(confidence, "nose")
    smoother = RaySmoother(0.4)
    params = IntentParams()
    centers = np.array([center for _, center in CUPS])
    seen = smoother.smooth(0.0, observe(points, confidence, centers, params))
    dropped = smoother.smooth(0.1, observe(points, faceless, centers, params))
    np.testing.assert_allclose(dropped.face.direction, seen.face.direction)
    assert smoother.smooth(0.6, observe(points, faceless, centers, params)).face is None


def test_the_torso_direction_is_the_mean_of_the_resting_frames():
    """Lifted shoulders jitter; the tracker's forward direction is their running mean while no
    arm points, not the last frame's (each frame as lifted: no keypoint filter)."""
    tracker = IntentTracker(IntentParams(track_keypoints=False))
    points, confidence = keypoints()
    r = keypoint_index("r_shoulder")
    for time, skew in ((0.0, 0.04), (0.1, -0.04)):  # shoulders 4 cm forward, then back
        jittered = points.copy()
        jittered[r, 0] += skew
        tracker.update(time, jittered, confidence, CUPS)
    steady = tracker.steady_forward(Observation(), None)
    np.testing.assert_allclose(steady.forward, [-1.0, 0.0, 0.0], atol=1e-9)


def test_the_chests_facing_outranks_the_shoulders():
    """Lifted shoulders read a turned person as facing the camera: once the chest's plane has
    been seen, the torso's direction is the mean of the chest's facings, whatever the
    shoulders say, also in frames that miss the chest; the gaze turns from it."""
    tracker = IntentTracker(IntentParams())
    points, confidence = keypoints(look_at=CUPS[0][1])
    turned = np.array([-math.cos(0.2), math.sin(0.2), 0.0])
    for time, chest in ((0.0, None), (0.1, turned), (0.2, np.full(3, np.nan))):
        state = tracker.update(time, points, confidence, CUPS, chest)
        assert not state.frame.pointing  # no arm points: the torso is taken from every frame
    np.testing.assert_allclose(tracker.steady_forward(Observation(), None).forward, turned)
    centers = np.array([center for _, center in CUPS])
    face = observe(points, confidence, centers, IntentParams()).face
    expected = gaze_ray(face, turned, IntentParams())
    np.testing.assert_allclose(state.frame.gaze.direction, expected.direction, atol=1e-9)
    shoulders_only = IntentTracker(IntentParams())
    shoulders_only.update(0.0, points, confidence, CUPS)
    forward = shoulders_only.steady_forward(Observation(), None).forward
    np.testing.assert_allclose(forward, [-1.0, 0.0, 0.0], atol=1e-9)


@pytest.mark.parametrize("rate_hz", [30.0, 5.0])
def test_a_held_arm_is_recognised_at_a_slow_camera_rate_too(rate_hz):
    """At 5 Hz the 0.4 s window holds two frames: the hold is judged from those, a frame after
    the arm has come to rest in them."""
    tracker = _watching(IntentParams(t_max=0.5, smoothing_s=0.4))
    states = _frames(tracker, np.arange(0.0, 2.0, 1 / rate_hz))
    assert states[-1].target == "green"
    assert states[-1].recognised_time <= 0.5 + 0.4 + 1 / rate_hz + 1e-9


def _bent(points: np.ndarray, arm: str) -> np.ndarray:
    """The arm's elbow lifted 12 cm off the shoulder-wrist line, as a foreshortened arm's is
    when its elbow lands on the forearm's depth: the elbow angle reads well under 150 deg."""
    bent = points.copy()
    bent[keypoint_index(f"{arm[0]}_elbow")] += [0.0, 0.0, -0.12]
    return bent


def test_an_arm_that_reads_bent_for_a_frame_in_three_still_points_within_the_gap():
    label, center = CUPS[1]
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    bent = _bent(points, "right")
    right = keypoint_index("r_shoulder"), keypoint_index("r_elbow"), keypoint_index("r_wrist")
    assert elbow_angle_deg(*bent[list(right)]) < IntentParams().straight_arm_deg - 10.0

    def recognised(gap: float) -> bool:
        tracker = _watching(IntentParams(t_max=0.5, smoothing_s=0.6, bent_gap_s=gap))
        for frame, time in enumerate(np.arange(0.0, 2.0, 1 / 30)):
            seen = bent if frame % 3 == 2 else points
            state = tracker.update(time, seen, confidence, CUPS)
        return state.target == label

    assert recognised(0.2) and not recognised(0.0)


def test_an_arm_lowered_for_longer_than_the_gap_ends_its_gesture():
    smoother = RaySmoother(1.0, gap=0.2)
    ray = Ray.through([0, 0, 0], [1, 0, 0])
    smoother.smooth(0.0, Observation("right", 170.0, ray))
    within = smoother.smooth(0.15, Observation())
    assert within.arm == "right" and within.pointing is not None
    assert smoother.smooth(0.45, Observation()).pointing is None  # 0.45 s since it last pointed
    after = smoother.smooth(0.5, Observation("right", 170.0, Ray.through([0, 0, 0], [0, 1, 0])))
    np.testing.assert_allclose(after.pointing.direction, [0, 1, 0])  # a new gesture


def test_another_arm_read_straight_in_the_pointing_arms_gap_does_not_end_its_gesture():
    """The pointing arm reads bent for a frame and the resting arm straight the next: the
    gesture goes on, its hold kept; the other arm points once the gap has passed."""
    smoother = RaySmoother(1.0, gap=0.2)
    ray, other = Ray.through([0, 0, 0], [1, 0, 0]), Ray.through([0, 0, 0], [0, 1, 0])
    for time in np.arange(0.0, 0.5, 0.1):
        smoother.smooth(time, Observation("right", 170.0, ray))
    smoother.smooth(0.5, Observation())  # bent for a frame
    resting = smoother.smooth(0.6, Observation("left", 160.0, other))
    assert resting.arm == "right" and resting.sweep_deg_s == pytest.approx(0.0)
    back = smoother.smooth(0.7, Observation("right", 170.0, ray))
    assert back.arm == "right" and back.sweep_deg_s == pytest.approx(0.0)
    np.testing.assert_allclose(back.pointing.direction, [1, 0, 0])
    # Straight while the right arm also points: the arm nearer an object points, anew.
    switched = smoother.smooth(0.8, Observation("left", 160.0, other))
    np.testing.assert_allclose(switched.pointing.direction, [0, 1, 0])


def test_an_arm_pointing_at_nothing_in_the_pointing_arms_gap_does_not_take_its_gesture():
    """A standing person's hanging arm reads straight, pointing at no object, in the frames in
    which the pointing arm reads bent: the gesture goes on, its hold kept. An arm pointing at
    an object takes over from one pointing at nothing at once."""
    smoother = RaySmoother(1.0, gap=0.3)
    ray, hanging = Ray.through([0, 0, 0], [1, 0, 0]), Ray.through([0, 0, 0], [0, 0, -1])
    for time in np.arange(0.0, 0.5, 0.1):
        smoother.smooth(time, Observation("right", 170.0, ray, at_object=True))
    kept = smoother.smooth(0.5, Observation("left", 175.0, hanging))  # the right read bent
    assert kept.arm == "right" and kept.sweep_deg_s == pytest.approx(0.0)
    np.testing.assert_allclose(kept.pointing.direction, [1, 0, 0])
    back = smoother.smooth(0.6, Observation("right", 170.0, ray, at_object=True))
    assert back.arm == "right" and back.sweep_deg_s == pytest.approx(0.0)
    # Once the pointing arm has been bent for longer than the gap, the hanging arm is read.
    smoother.smooth(0.7, Observation("left", 175.0, hanging))
    late = smoother.smooth(1.0, Observation("left", 175.0, hanging))
    assert late.arm == "left"
    np.testing.assert_allclose(late.pointing.direction, [0, 0, -1])
    raised = smoother.smooth(1.1, Observation("right", 170.0, ray, at_object=True))
    assert raised.arm == "right"
    np.testing.assert_allclose(raised.pointing.direction, [1, 0, 0])


def test_a_pointing_arm_is_at_an_object_when_its_ray_passes_within_d_min_of_one():
    center = CUPS[1][1]
    points, confidence = keypoints(look_at=center, point_with="right", point_at=center)
    centers = np.array([c for _, c in CUPS])
    seen = observe(points, confidence, centers, IntentParams())
    assert seen.arm == "right" and seen.at_object
    far = centers + [0.0, 0.0, 2.0]  # every object 2 m over where the arm points
    assert not observe(points, confidence, far, IntentParams()).at_object


def test_the_face_is_the_median_of_its_window_so_one_wild_frame_does_not_turn_it():
    """One frame's eq. 17 normal can read tens of degrees off (a jittered eye pixel whose depth
    window slips off the eye): the window's face keeps the others' heading and elevation,
    where their mean would turn a few degrees."""
    smoother = RaySmoother(window=1.0)
    steady = Ray(np.zeros(3), unit_direction(math.radians(170.0), math.radians(-20.0)))
    wild = Ray(np.array([0.0, 0.0, 0.05]), unit_direction(math.radians(-150.0), math.radians(10.0)))
    for time in np.arange(0.0, 0.3, 1 / 30):
        seen = smoother.smooth(time, Observation(face=steady))
    seen = smoother.smooth(0.3, Observation(face=wild))  # across the heading's wrap at 180 deg
    heading, elevation = heading_elevation(seen.face.direction)
    np.testing.assert_allclose(np.degrees([heading[0], elevation[0]]), [170.0, -20.0], atol=1e-9)
    np.testing.assert_allclose(seen.face.origin, steady.origin)
    mean = steady.direction * 9 + wild.direction
    assert math.degrees(math.atan2(mean[1], mean[0])) > 172.0  # the mean would turn


def _run(tracker, start, seconds, points, confidence, candidates=CUPS, rate=30.0):
    """Feed the same frame from `start` for `seconds`; the states and the time after."""
    times = start + np.arange(0.0, seconds, 1 / rate)
    return [tracker.update(t, points, confidence, candidates) for t in times], times[-1] + 1 / rate


def _recognised_green(params: IntentParams) -> tuple[IntentTracker, float]:
    """A tracker that has recognised the green cup (pointed at and looked at for 1.5 s)."""
    tracker = _watching(params)
    points, confidence = keypoints(look_at=CUPS[1][1], point_with="right", point_at=CUPS[1][1])
    states, time = _run(tracker, 0.0, 1.5, points, confidence)
    assert states[-1].target == "green"
    return tracker, time


def test_after_the_target_a_new_gesture_at_another_object_is_a_correction():
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    tracker, time = _recognised_green(params)
    resting, confidence = keypoints(look_at=CUPS[1][1])
    states, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence)
    assert all(state.correction is None for state in states)
    blue, confidence = keypoints(look_at=CUPS[2][1], point_with="right", point_at=CUPS[2][1])
    states, _ = _run(tracker, time, 2.0, blue, confidence)
    corrected = [state for state in states if state.correction is not None]
    assert corrected and all(state.correction == "blue" for state in corrected)
    assert corrected[0].correction_time >= time + params.t_max - 1e-9
    assert corrected[0].target == "green"  # the first target stays what it was


LEFT_ARM = [keypoint_index(f"l_{joint}") for joint in ("shoulder", "elbow", "wrist")]


def _left_hanging(points: np.ndarray, look_at: np.ndarray) -> np.ndarray:
    """`points` with the left arm hanging straight at the side, as a standing person's does."""
    hanging, _ = keypoints(look_at=look_at, point_with="left", arm_angles=np.zeros(5))
    points = points.copy()
    points[LEFT_ARM] = hanging[LEFT_ARM]
    return points


def test_a_hanging_arm_read_straight_does_not_keep_a_correction_from_being_read():
    """A standing person's other arm hangs straight and points at nothing: the first gesture
    is over once the pointing arm is lowered, and a new one at another object corrects it."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    tracker, time = _recognised_green(params)
    resting, confidence = keypoints(look_at=CUPS[1][1])
    resting = _left_hanging(resting, CUPS[1][1])
    assert elbow_angle_deg(*resting[LEFT_ARM]) > 170.0
    states, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence)
    assert states[-1].frame.arm == "left" and all(state.correction is None for state in states)
    blue, confidence = keypoints(look_at=CUPS[2][1], point_with="right", point_at=CUPS[2][1])
    states, _ = _run(tracker, time, 2.0, _left_hanging(blue, CUPS[2][1]), confidence)
    assert states[-1].correction == "blue"


def test_no_correction_without_the_arm_lowered_for_the_smoothing_window_first():
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    tracker, time = _recognised_green(params)
    blue, confidence = keypoints(look_at=CUPS[2][1], point_with="right", point_at=CUPS[2][1])
    states, time = _run(tracker, time, 2.0, blue, confidence)  # swung on without a rest
    assert all(state.correction is None for state in states)
    resting, confidence = keypoints(look_at=CUPS[1][1])
    _run(tracker, time, params.smoothing_s / 2, resting, confidence)  # lowered too briefly
    green, confidence = keypoints(look_at=CUPS[1][1], point_with="right", point_at=CUPS[1][1])
    states, _ = _run(tracker, time + params.smoothing_s / 2, 2.0, green, confidence)
    assert all(state.correction is None for state in states)  # the target again: no change


def test_a_correction_judges_the_objects_where_they_were_last_seen():
    """Carrying one object, the robot looks at the person: the others go out of its view."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    tracker, time = _recognised_green(params)
    resting, confidence = keypoints(look_at=CUPS[1][1])
    _, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence, candidates=[])
    blue, confidence = keypoints(look_at=CUPS[2][1], point_with="right", point_at=CUPS[2][1])
    states, _ = _run(tracker, time, 2.0, blue, confidence, candidates=CUPS[1:2])
    assert states[-1].correction == "blue"


def test_a_correction_reads_the_gaze_with_its_own_tolerance():
    """The same person's gaze misses the same way again: with the object first read left out,
    the eyes need only lean the arm's way (a head turned short of the blue cup)."""
    short_of_blue = CUPS[1][1] + 0.5 * (CUPS[2][1] - CUPS[1][1])
    blue = CUPS[2][1]

    def corrected(tolerance: float) -> str | None:
        params = IntentParams(
            t_max=0.5, correction_gaze_tolerance_deg=tolerance, face_tilt_deg=TRUE_FACE_TILT
        )
        tracker, time = _recognised_green(params)
        resting, confidence = keypoints(look_at=CUPS[1][1])
        _, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence)
        points, confidence = keypoints(look_at=short_of_blue, point_with="right", point_at=blue)
        others = [CUPS[0], CUPS[2]]  # the green cup is in the robot's hand, elsewhere
        states, _ = _run(tracker, time, 2.0, points, confidence, candidates=others)
        return states[-1].correction

    assert corrected(IntentParams().correction_gaze_tolerance_deg) == "blue"
    assert corrected(IntentParams().gaze_tolerance_deg / 4) is None


def test_a_correction_is_not_read_from_eyes_on_a_point_below_the_object():
    """A hand held out to receive is a straight arm toward the table, the eyes on the hand:
    below the object its ray passes near."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    blue = CUPS[2][1]

    def corrected(look: np.ndarray) -> str | None:
        tracker, time = _recognised_green(params)
        resting, confidence = keypoints(look_at=look)  # the eyes there from the start
        _, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence)
        points, confidence = keypoints(look_at=look, point_with="right", point_at=blue)
        states, _ = _run(tracker, time, 2.0, points, confidence)
        return states[-1].correction

    assert corrected(blue) == "blue"
    assert corrected(blue + [0.35, 0.0, -0.1]) is None  # nearer the person and lower: at the hand


def test_a_request_is_an_arm_raised_to_point_not_one_that_lay_there_from_the_start():
    """A forearm lying on the table toward a cup reads straight at it; with the eyes on that
    cup from the first frame and the arm never moving, it is not a request. The same arm
    raised to it from rest is one."""
    params = IntentParams(t_max=0.3)
    points, confidence = keypoints(look_at=CUPS[0][1], point_with="right", point_at=CUPS[0][1])
    lying = IntentTracker(params)
    states, _ = _run(lying, 0.0, 3.0, points, confidence)
    assert all(state.target is None and state.candidate is None for state in states)
    assert states[-1].frame.status == ARM_NOT_RAISED
    raised = _watching(params)
    states, _ = _run(raised, 0.0, 1.5, points, confidence)
    assert states[-1].target == "red"


def test_a_correction_is_a_new_gesture_not_an_arm_that_stays_where_it_is():
    """An arm held out to receive, its elbow angle flickering across the straight threshold,
    reads as pointing now and then but has not moved (a short person's held-out arm toward the
    table): no correction. The same pose reached from rest is one."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    blue = CUPS[2][1]
    points, confidence = keypoints(look_at=blue, point_with="right", point_at=blue)
    bent = points.copy()
    bent[R_ELBOW] += [0.0, 0.0, -0.12]  # the same wrist, the elbow read low: not straight
    assert elbow_angle_deg(*bent[[R_SHOULDER, R_ELBOW, R_WRIST]]) < params.straight_arm_deg

    def corrected(before: np.ndarray) -> str | None:
        tracker, time = _recognised_green(params)
        waited = params.smoothing_s + params.rise_s  # the arm off green for long
        _, time = _run(tracker, time, waited, before, confidence)
        states, _ = _run(tracker, time, 2.0, points, confidence)
        return states[-1].correction

    resting, _ = keypoints(look_at=blue)
    assert corrected(resting) == "blue"
    assert corrected(bent) is None


def test_eyes_that_may_be_on_the_object_held_do_not_refuse_a_new_gesture():
    """The wrong cup lifted beside the one wanted lies along nearly the same bearing from the
    eyes (5 degrees apart across, level): an arm raised to point at the blue cup, the eyes on
    it, is a correction."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    blue = CUPS[2][1]
    resting, confidence = keypoints(look_at=blue)
    eyes = (resting[R_EYE] + resting[L_EYE]) / 2
    held = [("green", eyes + 0.9 * (blue - eyes) + [0.0, 0.05, 0.03]), CUPS[2]]
    tracker, time = _recognised_green(params)
    _, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence, held)
    points, confidence = keypoints(look_at=blue, point_with="right", point_at=blue)
    states, _ = _run(tracker, time, 2.0, points, confidence, candidates=held)
    assert states[-1].correction == "blue"


def test_a_gesture_at_the_object_held_is_a_reach_for_it_not_a_correction():
    """The object fetched, held up in front of the one beside it, is what the person reaches
    for: the arm and the eyes on it are not a request for its neighbour, which lies within
    the correction's wide gaze tolerance of the eyes."""
    params = IntentParams(t_max=0.5, face_tilt_deg=TRUE_FACE_TILT)
    blue = CUPS[2][1]
    resting, confidence = keypoints(look_at=blue)
    eyes = (resting[R_EYE] + resting[L_EYE]) / 2
    held_at = eyes + 0.8 * (blue - eyes) + [0.0, 0.08, 0.1]
    held = [("green", held_at), CUPS[2]]
    tracker, time = _recognised_green(params)
    _, time = _run(tracker, time, params.smoothing_s + 0.5, resting, confidence, held)
    points, confidence = keypoints(look_at=held_at, point_with="left", point_at=held_at)
    states, _ = _run(tracker, time, 2.0, points, confidence, candidates=held)
    assert all(state.correction is None for state in states)
