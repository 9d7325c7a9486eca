"""The active gaze's decisions (`perception.active_gaze`), on synthetic skeletons and poses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.interface.coco18 import NUM_KEYPOINTS, keypoint_index
from hsr_handover.robot.perception.active_gaze import (
    FRAMING,
    POINTED_AHEAD,
    SEARCH,
    ActiveGaze,
    FieldOfView,
    GazeParams,
    HeadMove,
    angles,
    face_estimate,
    fit,
    pointed_at,
)

VIEW = FieldOfView(math.radians(30.0), math.radians(23.4))  # the Xtion's 60 x 47 degrees
LIMITS = ((-3.84, 1.75), (-1.57, 0.52))
CAMERA = np.array([0.0, 0.0, 0.97])


def camera_rotation(pan: float, tilt: float) -> np.ndarray:
    """A camera frame (x right, y down, z forward) panned about z and tilted up by `tilt`."""
    forward = np.array([math.cos(tilt) * math.cos(pan), math.cos(tilt) * math.sin(pan),
                        math.sin(tilt)])  # fmt: skip
    right = np.array([math.sin(pan), -math.cos(pan), 0.0])
    down = np.cross(forward, right)
    return np.column_stack([right, down, forward])


def skeleton(points: dict[str, np.ndarray | None]) -> tuple[np.ndarray, np.ndarray]:
    """18 x 3 points and confidences with the named keypoints seen (those given None not)."""
    lifted = np.full((NUM_KEYPOINTS, 3), np.nan)
    confidence = np.zeros(NUM_KEYPOINTS)
    for name, point in points.items():
        if point is None:  # not seen
            continue
        lifted[keypoint_index(name)] = point
        confidence[keypoint_index(name)] = 0.9
    return lifted, confidence


def standing_person(x: float = 1.4, y: float = 0.0, height: float = 1.86) -> dict:
    eyes = 0.93 * height
    return {
        "nose": np.array([x - 0.1, y, eyes - 0.04]),
        "r_eye": np.array([x - 0.09, y - 0.03, eyes]),
        "l_eye": np.array([x - 0.09, y + 0.03, eyes]),
        "neck": np.array([x, y, 0.82 * height]),
        "r_shoulder": np.array([x, y - 0.2, 0.81 * height]),
        "l_shoulder": np.array([x, y + 0.2, 0.81 * height]),
        "r_wrist": np.array([x - 0.2, y - 0.25, 0.5 * height]),
        "l_wrist": np.array([x - 0.2, y + 0.25, 0.5 * height]),
    }


def in_view(pan: float, tilt: float, point: np.ndarray, margin: float = 0.0) -> bool:
    heading, elevation = angles(CAMERA, point)
    return (abs(heading - pan) <= VIEW.half_width - margin
            and abs(elevation - tilt) <= VIEW.half_height - margin)  # fmt: skip


def test_fit_keeps_the_first_wanted_and_drops_what_does_not_fit_with_it():
    # 0.0 first; 0.3 fits within half 0.2 of an axis at 0.1-0.2; -0.5 does not, and is dropped.
    assert fit([0.0, 0.3, -0.5], 0.2) == pytest.approx(0.15)
    assert fit([0.0], 0.2) == pytest.approx(0.0)
    assert fit([], 0.2) is None


def test_a_face_not_seen_is_placed_above_the_shoulders():
    person = standing_person()
    body = {name: person[name] for name in ("neck", "r_shoulder", "l_shoulder")}
    face = face_estimate(*skeleton(body))
    # The highest of what the neck (0.22 m below the eyes) and shoulders (0.27) say.
    assert face[2] == pytest.approx(person["r_shoulder"][2] + 0.27)
    assert face_estimate(*skeleton({})) is None


def test_it_searches_its_fixations_in_turn_while_no_one_is_seen():
    params = GazeParams(search=((0.0, 0.2), (0.6, 0.2)), dwell_s=0.5, speed=1.0)
    gaze = ActiveGaze(VIEW, LIMITS, params)
    nobody = skeleton({})
    head = (0.0, 0.0)
    goals = []
    for step in range(30):
        state = gaze.update(0.1 * step, camera_rotation(*head), CAMERA, head, *nobody)
        goals.append(state.goal)
        head = state.goal  # a head that is where it is told
    assert state.mode == SEARCH
    # (0, 0.2) for 0.2 + 0.5 s, then (0.6, 0.2) for 0.6 + 0.5 s, then (0, 0.2) again.
    assert goals[0] == (0.0, 0.2) and goals[8] == (0.6, 0.2) and goals[20] == (0.0, 0.2)


def test_a_standing_face_above_the_view_is_framed_and_the_table_dropped():
    gaze = ActiveGaze(VIEW, LIMITS)
    person = standing_person()
    head = (0.0, 0.0)
    assert not in_view(*head, person["r_eye"])  # the level view misses the face
    table_cup = ("red", np.array([0.8, 0.0, 0.81]))
    for step in range(5):
        state = gaze.update(0.1 * step, camera_rotation(*head), CAMERA, head,
                            *skeleton(person), [table_cup])  # fmt: skip
        head = state.goal
    assert state.mode == FRAMING and state.found_at == 0.0
    margin = math.radians(GazeParams().margin_deg) - 1e-6
    for name in ("nose", "r_eye", "l_eye", "r_wrist", "l_wrist"):
        assert in_view(*head, person[name], margin), name
    # The cup 16 degrees below level does not fit with a face 30 degrees above: dropped.
    assert not in_view(*head, table_cup[1])
    assert state.objects[0][0] == "red"  # but remembered


def test_a_seated_person_is_framed_with_the_objects():
    gaze = ActiveGaze(VIEW, LIMITS)
    person = {name: point - [0.0, 0.0, 0.55] for name, point in standing_person(1.7).items()}
    cups = [("red", np.array([0.8, -0.2, 0.77])), ("blue", np.array([0.8, 0.2, 0.77]))]
    head = (0.0, 0.0)
    for step in range(3):
        state = gaze.update(0.1 * step, camera_rotation(*head), CAMERA, head,
                            *skeleton(person), cups)  # fmt: skip
        head = state.goal
    for point in [person["r_eye"], *(center for _, center in cups)]:
        assert in_view(*head, point)


def test_it_follows_a_person_who_moves_and_searches_once_they_are_lost():
    params = GazeParams(lost_s=1.0)
    gaze = ActiveGaze(VIEW, LIMITS, params)
    head = (0.0, 0.0)
    for step, y in enumerate(np.linspace(0.0, 1.2, 13)):  # walks to the robot's left
        state = gaze.update(0.1 * step, camera_rotation(*head), CAMERA, head,
                            *skeleton(standing_person(1.4, y)))  # fmt: skip
        head = state.goal
    assert in_view(*head, standing_person(1.4, 1.2)["r_eye"])
    assert head[0] > 0.5  # turned left after them
    nobody = skeleton({})
    held = gaze.update(1.5, camera_rotation(*head), CAMERA, head, *nobody)
    assert held.mode == FRAMING and held.goal == head  # a blink: the aim holds
    lost = gaze.update(2.3, camera_rotation(*head), CAMERA, head, *nobody)
    assert lost.mode == SEARCH and lost.goal == params.search[0]


def test_goals_stay_within_the_head_limits():
    gaze = ActiveGaze(VIEW, ((-0.5, 0.5), (-0.2, 0.2)))
    state = gaze.update(0.0, camera_rotation(0.0, 0.0), CAMERA, (0.0, 0.0),
                        *skeleton(standing_person(0.6, 1.0)))  # fmt: skip
    assert state.goal == (0.5, 0.2)


def test_the_head_moves_at_its_speed_on_a_straight_line_and_holds_at_the_goal():
    move = HeadMove(1.0, (0.0, 0.0), (0.8, -0.4), 0.8)
    q, v = move.at(1.5)
    assert q == pytest.approx([0.4, -0.2]) and v == pytest.approx([0.8, -0.4])
    q, v = move.at(3.0)
    assert q == pytest.approx([0.8, -0.4]) and v == pytest.approx([0.0, 0.0])
    turned = move.toward(1.5, (0.0, 0.0))
    assert turned.start == pytest.approx((0.4, -0.2)) and turned.start_time == 1.5
    assert move.toward(2.0, (0.8, -0.4)) is move
    assert move.toward(2.0, (0.8, -0.4), measured=(0.79, -0.4)) is move  # following it
    taken = move.toward(2.0, (0.8, -0.4), measured=(-0.5, 0.2))  # commanded elsewhere meanwhile
    assert taken.start == (-0.5, 0.2) and taken.start_time == 2.0


def test_out_of_range_params_are_refused_by_name():
    with pytest.raises(ValueError, match="speed"):
        GazeParams(speed=2.0)
    with pytest.raises(ValueError, match="search"):
        GazeParams(search=())


def test_what_attention_selects_is_fixated_as_near_as_the_person_allows():
    person = {name: point - [0.0, 0.0, 0.55] for name, point in standing_person(1.7).items()}
    cup = np.array([0.8, 0.3, 0.77])
    head = (0.0, 0.0)
    framed = ActiveGaze(VIEW, LIMITS).update(
        0.0, camera_rotation(*head), CAMERA, head, *skeleton(person), [("red", cup)]
    )
    fixated = ActiveGaze(VIEW, LIMITS).update(
        0.0, camera_rotation(*head), CAMERA, head, *skeleton(person), [("red", cup)], [cup]
    )
    heading, elevation = angles(CAMERA, cup)
    # Turned toward the cup (nearer its bearing and elevation), the face still in view.
    assert abs(fixated.goal[0] - heading) < abs(framed.goal[0] - heading)
    assert abs(fixated.goal[1] - elevation) <= abs(framed.goal[1] - elevation)
    assert in_view(*fixated.goal, person["r_eye"])
    assert fit([0.0, 0.1], 0.2, toward=0.25) == pytest.approx(0.2)  # as near as the rest allows


def _seated_pointing_at(target: np.ndarray) -> dict:
    """A seated person 1.7 m ahead, the right arm held out straight toward `target` (its wrist
    0.45 m out from the shoulder, lifted 3 cm low as on the hand's surface)."""
    person = {name: point - [0.0, 0.0, 0.55] for name, point in standing_person(1.7).items()}
    shoulder = person["r_shoulder"]
    toward = (target - shoulder) / np.linalg.norm(target - shoulder)
    person["r_elbow"] = shoulder + 0.25 * toward
    person["r_wrist"] = shoulder + 0.5 * toward - [0.0, 0.0, 0.03]
    return person


def test_the_point_an_arm_points_at_lies_ahead_of_the_wrist_on_its_heading():
    target = np.array([0.85, -0.6, 0.77])
    person = _seated_pointing_at(target)
    pointed = pointed_at(*skeleton(person), 0.77)
    assert pointed[2] == 0.77
    wrist, shoulder = person["r_wrist"], person["r_shoulder"]
    assert np.linalg.norm(pointed[:2] - wrist[:2]) == pytest.approx(POINTED_AHEAD)
    heading, ahead = (wrist - shoulder)[:2], pointed[:2] - wrist[:2]
    assert heading[0] * ahead[1] - heading[1] * ahead[0] == pytest.approx(0.0, abs=1e-9)
    assert heading @ ahead > 0.0
    resting = {**person, "r_wrist": shoulder + [-0.2, 0.0, -0.25]}  # forearm on the table
    assert pointed_at(*skeleton(resting), 0.77) is None
    # A forearm lying on the table, held out as far as the pointing arm, the elbow bent square:
    # no pointing; nor an arm whose elbow is not seen.
    elbow = shoulder + [0.0, 0.0, -0.3]
    bent = {**person, "r_elbow": elbow, "r_wrist": elbow + (person["r_wrist"] - elbow) * [1, 1, 0]}
    assert np.hypot(*(bent["r_wrist"] - shoulder)[:2]) > 0.4
    assert pointed_at(*skeleton(bent), 0.4) is None
    assert pointed_at(*skeleton(person | {"r_elbow": None}), 0.77) is None
    assert pointed_at(*skeleton(person), 1.5) is None  # the wrist is not over that level


def test_an_object_out_of_view_comes_into_view_once_the_person_points_toward_it():
    gaze = ActiveGaze(VIEW, LIMITS)
    cups = [("red", np.array([0.8, 0.0, 0.77])), ("blue", np.array([0.8, 0.25, 0.77]))]
    hidden = np.array([0.8, -0.6, 0.77])  # never seen yet: 37 degrees to the right
    person = _seated_pointing_at(hidden)
    head = (0.0, 0.0)
    assert not in_view(*head, hidden)
    for step in range(3):
        state = gaze.update(0.1 * step, camera_rotation(*head), CAMERA, head,
                            *skeleton(person), cups)  # fmt: skip
        head = state.goal
    assert in_view(*head, hidden) and in_view(*head, person["r_eye"])
    resting = {**person, "r_wrist": person["r_shoulder"] + [-0.2, 0.0, -0.25]}
    still = gaze.update(1.0, camera_rotation(*head), CAMERA, head, *skeleton(resting), cups)
    assert not in_view(*still.goal, hidden)  # no pointing: the seen cups and the face
