"""OpenPose's output as OpenPose writes it: COCO-18 and BODY_25 (remapped by name), version
1.0's key, face/hand/3-D fields ignored, confidences above 1, normalised coordinates, models
that are refused, and folders of per-frame files in frame order with broken frames skipped."""

from __future__ import annotations

import json
import logging
import subprocess
import sys

import numpy as np
import pytest

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS, keypoint_index
from hsr_handover.interface.openpose_json import (
    natural_sort_key,
    openpose_frame_files,
    read_openpose_frames,
    read_openpose_json,
    read_openpose_recording,
)
from tests.openpose_files import (
    BODY25_ORDER,
    BODY25B_ORDER,
    MPI_ORDER,
    openpose_name,
    person_table,
    write_frame,
)

WIDTH, HEIGHT = 640, 480


def _pixels(table: np.ndarray) -> np.ndarray:
    """A COCO-18 table's pixels as a Detection holds them (NaN where missing)."""
    return np.where(table[:, 2:] > 0, table[:, :2], np.nan)


def test_coco18_file_reads_every_person_as_written(tmp_path):
    first = person_table(missing=("l_ear", "r_ankle"))
    second = person_table(neck_px=(100.0, 120.0), shoulder_px=40.0, confidence=0.5)
    path = write_frame(tmp_path / "coco_keypoints.json", [first, second])
    people = read_openpose_json(path)
    assert len(people) == 2
    for detection, table in zip(people, (first, second), strict=True):
        np.testing.assert_array_equal(detection.pixels, _pixels(table))
        np.testing.assert_array_equal(detection.confidence, table[:, 2])
    missing = keypoint_index("l_ear")
    assert people[0].confidence[missing] == 0 and np.isnan(people[0].pixels[missing]).all()


def test_body25_with_face_and_hands_is_remapped_to_coco18_by_name(tmp_path):
    coco = person_table()
    body25 = person_table(BODY25_ORDER)
    # BODY_25 is not COCO-18 with extra rows: MidHip sits at index 8, moving the hips and the
    # face, so cutting it to 18 rows would put MidHip where the right hip belongs.
    assert not np.array_equal(body25[:18], coco)
    path = write_frame(tmp_path / "body25_keypoints.json", [body25], extras=True)
    frame = json.loads(path.read_text())["people"][0]
    assert len(frame["face_keypoints_2d"]) == 210 and len(frame["hand_left_keypoints_2d"]) == 63
    (person,) = read_openpose_json(path)
    np.testing.assert_array_equal(person.pixels, _pixels(coco))
    r_hip = COCO18_KEYPOINTS.index("r_hip")
    np.testing.assert_array_equal(person.pixels[r_hip], coco[r_hip, :2])
    assert read_openpose_recording(path).model == "BODY_25"


def test_face_hand_and_3d_fields_are_ignored_whatever_they_hold(tmp_path):
    path = tmp_path / "odd_extras_keypoints.json"
    person = {
        "pose_keypoints_2d": person_table().ravel().tolist(),
        "face_keypoints_2d": "not numbers",
        "hand_left_keypoints_2d": [[1, 2], None],
        "pose_keypoints_3d": {"x": 1},
    }
    path.write_text(json.dumps({"version": 1.3, "people": [person], "part_candidates": [{}]}))
    (detection,) = read_openpose_json(path)
    np.testing.assert_array_equal(detection.pixels, _pixels(person_table()))


def test_empty_frame_has_no_people(tmp_path):
    path = write_frame(tmp_path / "empty_keypoints.json", [])
    assert read_openpose_json(path) == []
    (detection,) = read_openpose_frames([path])
    assert detection.status == "no person in the frame" and not detection.confidence.any()
    assert read_openpose_recording(path).model == "unknown"  # nobody to tell it by
    assert read_openpose_recording(path, model="BODY_25").model == "BODY_25"


def test_version_1_0_key_pose_keypoints_reads_like_pose_keypoints_2d(tmp_path):
    table = person_table(BODY25_ORDER)
    path = write_frame(tmp_path / "v1_keypoints.json", [table], key="pose_keypoints", version=1.0)
    (person,) = read_openpose_json(path)
    np.testing.assert_array_equal(person.pixels, _pixels(person_table()))


def test_confidences_slightly_above_one_are_clamped(tmp_path):
    table = person_table()
    table[keypoint_index("r_wrist"), 2] = 1.006  # as a real OpenPose file has it
    table[keypoint_index("nose"), 2] = 1.2
    (person,) = read_openpose_json(write_frame(tmp_path / "over_keypoints.json", [table]))
    assert person.confidence[keypoint_index("r_wrist")] == 1.0
    assert person.confidence[keypoint_index("nose")] == 1.0
    assert person.confidence[keypoint_index("neck")] == pytest.approx(0.8)


@pytest.mark.parametrize("confidence", [-0.1, 1.6, 312.0])
def test_negative_or_absurd_confidences_are_refused_naming_file_and_key(tmp_path, confidence):
    table = person_table()
    table[3, 2] = confidence
    path = write_frame(tmp_path / "bad_confidence.json", [person_table(), table])
    expected = (
        r"bad_confidence\.json: people\[1\]\.pose_keypoints_2d: expected every third number "
        rf"\(confidence\) in \[0, 1\.5\], got {confidence:g} at keypoint 3"
    )
    with pytest.raises(ValueError, match=expected):
        read_openpose_json(path)


@pytest.mark.parametrize(
    ("scale", "to_file"),
    [
        ("unit", lambda px, size: px / (size - 1)),  # --keypoint_scale 3
        ("signed_unit", lambda px, size: px * 2 / (size - 1) - 1),  # --keypoint_scale 4
    ],
)
def test_normalised_coordinates_are_converted_to_pixels(tmp_path, scale, to_file):
    table = person_table(missing=("l_ear",))
    normalised = table.copy()
    seen = table[:, 2] > 0
    normalised[seen, 0] = to_file(table[seen, 0], WIDTH)
    normalised[seen, 1] = to_file(table[seen, 1], HEIGHT)
    path = write_frame(tmp_path / f"{scale}_keypoints.json", [normalised])
    (person,) = read_openpose_json(path, keypoint_scale=scale, image_size=(WIDTH, HEIGHT))
    np.testing.assert_allclose(person.pixels, _pixels(table), atol=1e-9)
    with pytest.raises(ValueError, match=r"image_size: expected \(width, height\)"):
        read_openpose_json(path, keypoint_scale=scale)


def test_normalised_file_read_as_pixels_asks_for_the_scale(tmp_path):
    table = person_table()
    table[:, :2] = table[:, :2] / [WIDTH - 1, HEIGHT - 1]
    path = write_frame(tmp_path / "unit_keypoints.json", [table])
    with pytest.raises(ValueError) as raised:
        read_openpose_json(path)
    message = str(raised.value)
    assert message.startswith(f"{path}: pose_keypoints_2d: expected pixel coordinates")
    assert "declare keypoint_scale unit ([0, 1]) or signed_unit ([-1, 1])" in message
    assert "\n" not in message
    folder = tmp_path / "frames"
    folder.mkdir()
    for index in range(3):
        write_frame(folder / openpose_name(index), [table])
    with pytest.raises(ValueError, match=f"^{folder}: pose_keypoints_2d: expected pixel"):
        read_openpose_recording(folder)


def test_declared_scale_that_does_not_fit_the_file_is_refused(tmp_path):
    path = write_frame(tmp_path / "pixels_keypoints.json", [person_table()])
    with pytest.raises(ValueError, match=r"expected coordinates in \[0, 1\] for keypoint_scale"):
        read_openpose_json(path, keypoint_scale="unit", image_size=(WIDTH, HEIGHT))


def test_body25b_is_refused_only_on_strong_stated_evidence(tmp_path, caplog):
    """Two people whose keypoint 15 lies a body's height from the nose (BODY_25B's ankle, not
    BODY_25's eye) are strong evidence: refused, the evidence stated. One such person, or, with
    no ankle seen, doubtful necks and mid-hips, are read as BODY_25 with a one-line note."""
    path = write_frame(tmp_path / "b25b_keypoints.json", [person_table(BODY25B_ORDER)] * 2)
    with pytest.raises(ValueError) as raised:
        read_openpose_json(path)
    message = str(raised.value)
    assert message.startswith(f"{path}: people[0].pose_keypoints_2d: expected COCO or BODY_25")
    assert "got BODY_25B: in 2 of 2 people keypoint 15 lies far from the nose" in message
    assert "\n" not in message
    path = write_frame(path, [person_table(BODY25B_ORDER)])
    with caplog.at_level(logging.WARNING):
        assert len(read_openpose_json(path)) == 1
    assert "read as BODY_25 (OpenPose's default), though in 1 of 1 people" in caplog.text
    # Seated behind a table, hips and ankles hidden: the neck off its shoulders is a doubt only.
    hidden = ("l_hip", "r_hip", "mid_hip", "l_ankle", "r_ankle")
    recording = read_openpose_recording(
        write_frame(path, [person_table(BODY25B_ORDER, missing=hidden)])
    )
    assert (
        recording.model == "BODY_25" and "necks and mid-hips lie off midway" in recording.model_note
    )
    path = write_frame(path, [person_table(BODY25_ORDER, missing=hidden)])
    assert read_openpose_recording(path).model_note == ""


def test_several_people_partly_seen_and_an_odd_first_frame_read_as_body25(tmp_path):
    """OpenPose's default is never refused for a few odd people: eight people, some cut off by
    the image's edge (no neck, no eye), and a sequence whose first frame holds one person whose
    keypoints happen to look like BODY_25B's."""
    partial = [("neck",), ("r_eye", "l_eye", "nose"), ("r_shoulder", "neck"), ()]
    people = [person_table(BODY25_ORDER, neck_px=(60.0 + 70 * k, 150.0), shoulder_px=30.0,
                           missing=partial[k % 4]) for k in range(8)]  # fmt: skip
    path = write_frame(tmp_path / "crowd_keypoints.json", people)
    assert len(read_openpose_json(path)) == 8
    folder = tmp_path / "sequence"
    folder.mkdir()
    write_frame(folder / openpose_name(0), [person_table(BODY25B_ORDER)])
    for index in range(1, 5):
        write_frame(folder / openpose_name(index), [person_table(BODY25_ORDER)])
    recording = read_openpose_recording(folder)
    assert recording.model == "BODY_25" and "in 1 of 5 people" in recording.model_note


def test_body25_geometry_allows_detection_noise(tmp_path):
    rng = np.random.default_rng(4)
    tables = []
    for _ in range(5):
        table = person_table(BODY25_ORDER, shoulder_px=60.0)
        table[:, :2] += rng.normal(0.0, 3.0, (25, 2))  # OpenPose's few pixels of jitter
        tables.append(table)
    path = write_frame(tmp_path / "noisy_keypoints.json", tables)
    assert len(read_openpose_json(path)) == 5


def test_a_declared_body25_is_read_without_the_geometry_check(tmp_path):
    path = write_frame(tmp_path / "b25b_keypoints.json", [person_table(BODY25B_ORDER)])
    (person,) = read_openpose_json(path, model="BODY_25")
    assert person.confidence.all()  # read as BODY_25: the user said so


@pytest.mark.parametrize(
    ("order", "named"),
    [
        (MPI_ORDER, "got 15 (OpenPose's MPI model), not supported"),
        (MPI_ORDER * 9, "got 135 (OpenPose's BODY_135 model), not supported"),
        (MPI_ORDER[:10] * 2, "got 20 (no OpenPose model this reader knows), not supported"),
    ],
)
def test_other_models_are_refused_naming_the_model(tmp_path, order, named):
    path = write_frame(tmp_path / "other_keypoints.json", [person_table(order)])
    expected = "people[0].pose_keypoints_2d: expected COCO's 18 or BODY_25's 25 keypoints"
    with pytest.raises(ValueError) as raised:
        read_openpose_json(path)
    assert str(raised.value) == f"{path}: {expected}, {named}"


def test_a_declared_model_is_checked_and_unsupported_ones_are_named(tmp_path):
    path = write_frame(tmp_path / "body25_keypoints.json", [person_table(BODY25_ORDER)])
    with pytest.raises(ValueError, match=r"expected 18 keypoints for model COCO, got 25"):
        read_openpose_json(path, model="COCO")
    expected = (
        "model: expected one of auto, COCO, BODY_25, got 'BODY_25B': OpenPose's BODY_25B model "
        "is not supported"
    )
    with pytest.raises(ValueError) as raised:
        read_openpose_json(path, model="BODY_25B")
    assert str(raised.value) == expected


def test_a_json_file_that_is_not_openpose_output_is_an_error_naming_it(tmp_path):
    path = tmp_path / "annotations.json"
    path.write_text(json.dumps({"images": [], "annotations": []}))
    expected = f"{path}: people: expected a list of people (OpenPose's --write_json output)"
    for read in (read_openpose_json, read_openpose_recording):
        with pytest.raises(ValueError) as raised:
            read(path)
        assert str(raised.value) == expected


def test_natural_order_puts_frame_2_before_frame_10():
    names = ["img10_keypoints.json", "img2_keypoints.json", "IMG1_keypoints.json"]
    assert sorted(names, key=natural_sort_key) == [
        "IMG1_keypoints.json", "img2_keypoints.json", "img10_keypoints.json",
    ]  # fmt: skip


@pytest.mark.parametrize("naming", ["openpose", "images"])
def test_folder_is_read_in_frame_order(tmp_path, naming):
    """Frame k's person stands at u = 100 + 10 k; the files are written out of order."""
    order = [10, 2, 0, 1, 11, 3, 9, 4, 8, 5, 7, 6]
    for index in order:
        name = openpose_name(index) if naming == "openpose" else f"img{index}_keypoints.json"
        write_frame(tmp_path / name, [person_table(neck_px=(100.0 + 10 * index, 150.0))])
    (tmp_path / "notes.txt").write_text("not a frame")
    (tmp_path / "camera.json").write_text("{}")  # not a *_keypoints.json: left out
    assert len(openpose_frame_files(tmp_path)) == len(order)
    recording = read_openpose_recording(tmp_path)
    necks = [d.pixels[keypoint_index("neck"), 0] for d in recording.detections]
    np.testing.assert_array_equal(necks, 100.0 + 10 * np.arange(len(order)))
    assert not recording.skipped


def test_broken_and_empty_frames_are_skipped_counted_and_the_sequence_goes_on(tmp_path):
    tables = [[person_table(neck_px=(100.0 + 10 * k, 150.0))] for k in range(6)]
    for index, people in enumerate(tables):
        write_frame(tmp_path / openpose_name(index), people)
    (tmp_path / openpose_name(1)).write_text('{"version": 1.3, "people": [{"pose_keyp')
    (tmp_path / openpose_name(3)).write_text("")
    write_frame(tmp_path / openpose_name(4), [person_table(MPI_ORDER)])
    recording = read_openpose_recording(tmp_path)
    statuses = [d.status for d in recording.detections]
    assert statuses == [
        "ok", "frame skipped: unparseable JSON", "ok", "frame skipped: empty file",
        "frame skipped: keypoint count differs from the recording's", "ok",
    ]  # fmt: skip
    assert [item.file for item in recording.skipped] == [
        str(tmp_path / openpose_name(k)) for k in (1, 3, 4)
    ]
    reason = recording.skipped[0].reason
    assert reason.startswith(f"{tmp_path / openpose_name(1)}: expected OpenPose JSON, could not")
    assert recording.detections[5].pixels[keypoint_index("neck"), 0] == 150.0
    assert len(read_openpose_frames(recording.files)) == 6


def test_frames_nested_too_deep_or_with_huge_numbers_are_skipped_with_their_file(tmp_path):
    """JSON that Python cannot read (200,000 nested arrays; a number of 5,000 digits) is a
    broken frame like any other: skipped in a folder, an error naming a lone file."""
    for index in range(3):
        write_frame(tmp_path / openpose_name(index), [person_table()])
    (tmp_path / openpose_name(1)).write_text("[" * 200_000)
    huge = '{"people": [{"pose_keypoints_2d": [' + "9" * 5000 + "]}]}"
    (tmp_path / openpose_name(2)).write_text(huge)
    recording = read_openpose_recording(tmp_path)
    assert [d.status for d in recording.detections] == [
        "ok", "frame skipped: unparseable JSON", "frame skipped: unparseable JSON",
    ]  # fmt: skip
    first, second = (item.reason for item in recording.skipped)
    assert first == f"{tmp_path / openpose_name(1)}: expected OpenPose JSON, got arrays or " + (
        "objects nested too deeply to read"
    )
    assert second.startswith(f"{tmp_path / openpose_name(2)}: expected OpenPose JSON, could not")
    assert "5000 digits" in second and "sys.set_int_max_str_digits" not in second
    with pytest.raises(ValueError, match="nested too deeply"):
        read_openpose_recording(tmp_path / openpose_name(1))


def test_folder_with_no_frames_or_only_broken_ones_is_an_error_naming_it(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("")
    with pytest.raises(ValueError) as raised:
        read_openpose_recording(empty)
    assert str(raised.value) == (
        f"{empty}: expected OpenPose JSON frames (*_keypoints.json or *.json), found none"
    )
    broken = tmp_path / "broken"
    broken.mkdir()
    for index in range(3):
        (broken / openpose_name(index)).write_text("{" if index else "")
    with pytest.raises(ValueError) as raised:
        read_openpose_recording(broken)
    message = str(raised.value)
    assert message.startswith(f"{broken}: expected OpenPose JSON frames, none of the 3 could be")
    assert f"(first: {broken / openpose_name(0)}: expected OpenPose JSON, the file is empty)" in (
        message
    )
    with pytest.raises(ValueError, match="expected an OpenPose JSON file or a folder of them"):
        read_openpose_recording(tmp_path / "absent")


def test_a_lone_broken_file_is_an_error_not_a_skipped_frame(tmp_path):
    path = tmp_path / "frame_keypoints.json"
    path.write_text("")
    with pytest.raises(ValueError, match=r"frame_keypoints\.json: expected OpenPose JSON, the"):
        read_openpose_recording(path)


def test_the_readers_are_numpy_only():
    """Layer 1: reading, tracking and summarising OpenPose output loads no Drake."""
    code = (
        "import sys, hsr_handover.recording.openpose_check; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('pydrake', 'cv2')))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True
    )
    assert result.stdout.strip() == "[]"
