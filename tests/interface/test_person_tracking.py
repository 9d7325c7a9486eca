"""Following one person through OpenPose frames with several people in view: the person of
interest chosen in the first frame, then kept by keypoint distance when OpenPose lists the
people in another order, when they are missing for a frame, and when someone else stays."""

from __future__ import annotations

import numpy as np

from hsr_handover.interface.coco18 import keypoint_index
from hsr_handover.interface.openpose_format import to_detection
from hsr_handover.interface.openpose_json import read_openpose_frames
from hsr_handover.interface.person_tracking import (
    NO_PERSON,
    TRACKED_PERSON_ABSENT,
    PersonTracker,
    choose_person,
    faces_camera,
    track_person,
)
from tests.openpose_files import openpose_name, person_table, write_frame

NECK = keypoint_index("neck")


def _person(neck_u: float, neck_v: float = 150.0, shoulder_px: float = 80.0, **kwargs):
    table = person_table(neck_px=(neck_u, neck_v), shoulder_px=shoulder_px, **kwargs)
    return to_detection(table, "COCO")


def _neck_u(detection) -> float:
    return float(detection.pixels[NECK, 0])


def test_the_person_facing_the_camera_with_the_widest_shoulders_is_chosen():
    far = _person(100.0, shoulder_px=40.0)
    near = _person(300.0, shoulder_px=90.0)
    turned_away = _person(500.0, shoulder_px=120.0, facing_away=True)  # nearer, but facing away
    assert faces_camera(near) and not faces_camera(turned_away)
    assert choose_person([far, turned_away, near]) == 2
    # Nobody facing the camera (the eyes not seen): the widest shoulders.
    no_eyes = ("r_eye", "l_eye")
    people = [
        _person(100.0, shoulder_px=40.0, missing=no_eyes),
        _person(400.0, shoulder_px=70.0, missing=no_eyes),
    ]
    assert choose_person(people) == 1
    # Nor shoulders: the largest body.
    no_shoulders = ("r_shoulder", "l_shoulder")
    people = [
        _person(100.0, shoulder_px=30.0, missing=no_shoulders),
        _person(400.0, shoulder_px=90.0, missing=no_shoulders),
    ]
    assert choose_person(people) == 1
    assert choose_person([]) is None


def test_a_configured_image_point_chooses_the_person_nearest_it():
    people = [_person(100.0, shoulder_px=40.0), _person(400.0, shoulder_px=90.0)]
    assert choose_person(people, near_px=(120.0, 200.0)) == 0
    assert choose_person(people, near_px=(390.0, 100.0)) == 1


def test_the_same_person_is_kept_when_openpose_swaps_the_list_order():
    frames = []
    for k in range(8):
        ours = _person(200.0 + 3 * k, shoulder_px=90.0)
        other = _person(420.0 - 3 * k, shoulder_px=80.0)
        frames.append([ours, other] if k % 2 == 0 else [other, ours])
    tracked = track_person(frames)
    assert all(d.status == "ok" for d in tracked)
    np.testing.assert_array_equal([_neck_u(d) for d in tracked], 200.0 + 3 * np.arange(8))


def test_a_person_absent_for_a_frame_is_missing_there_and_found_again():
    ours = [_person(200.0 + 2 * k, shoulder_px=90.0) for k in range(5)]
    other = _person(290.0, shoulder_px=85.0)  # beside them, one shoulder width away
    frames = [[ours[0], other], [other, ours[1]], [other], [ours[3], other], [other, ours[4]]]
    tracked = track_person(frames)
    assert [d.status for d in tracked] == ["ok", "ok", TRACKED_PERSON_ABSENT, "ok", "ok"]
    assert not tracked[2].confidence.any()
    assert [_neck_u(d) for d in (tracked[0], tracked[1], tracked[3], tracked[4])] == [
        200.0, 202.0, 206.0, 208.0,
    ]  # fmt: skip


def test_nobody_in_view_says_so_and_a_long_absence_chooses_anew():
    tracker = PersonTracker(reselect_after_frames=3)
    assert tracker.update([]).status == NO_PERSON
    assert _neck_u(tracker.update([_person(200.0, shoulder_px=90.0)])) == 200.0
    newcomer = _person(500.0, shoulder_px=60.0)
    statuses = [tracker.update([newcomer]).status for _ in range(3)]
    assert statuses == [TRACKED_PERSON_ABSENT] * 3
    assert _neck_u(tracker.update([newcomer])) == 500.0  # gone for 3 frames: chosen anew


def test_replayed_frames_follow_one_person(tmp_path):
    """read_openpose_frames follows the person of interest, not the file's first person."""
    paths = []
    for k in range(4):
        ours = person_table(neck_px=(300.0 + 4 * k, 150.0), shoulder_px=90.0)
        other = person_table(neck_px=(80.0, 160.0), shoulder_px=50.0)
        people = [other, ours] if k % 2 == 0 else [ours, other]
        paths.append(write_frame(tmp_path / openpose_name(k), people))
    detections = read_openpose_frames(paths)
    assert [_neck_u(d) for d in detections] == [300.0, 304.0, 308.0, 312.0]
    near_the_other = read_openpose_frames(paths, near_px=(90.0, 150.0))
    assert [_neck_u(d) for d in near_the_other] == [80.0] * 4
