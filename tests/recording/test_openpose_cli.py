"""`hsr-handover openpose check` as a user runs it: a summary per file or folder and its JSON,
or one error line (exit 2) and nothing written for input that is not OpenPose output."""

from __future__ import annotations

import json

import pytest

from hsr_handover.cli import main
from tests.openpose_files import BODY25_ORDER, openpose_name, person_table, write_frame


def _ours(u: float):
    return person_table(neck_px=(u, 150.0), shoulder_px=90.0)


def _other():
    return person_table(neck_px=(460.0, 160.0), shoulder_px=70.0)


@pytest.fixture
def recording(tmp_path):
    """Six frames of two people, listed in either order; ours moves 3 px a frame. Frame 2 is
    broken and frame 3 has nobody in it."""
    folder = tmp_path / "session"
    folder.mkdir()
    people = {0: [_ours(200), _other()], 1: [_other(), _ours(203)], 3: [],
              4: [_ours(212), _other()], 5: [_other(), _ours(215)]}  # fmt: skip
    for index, tables in people.items():
        write_frame(folder / openpose_name(index), tables)
    (folder / openpose_name(2)).write_text('{"people": [')
    return folder


def _one_error_line(capsys) -> str:
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    return lines[0]


def test_check_summarises_folders_and_files(tmp_path, recording, capsys):
    single = write_frame(tmp_path / "body25_keypoints.json", [person_table(BODY25_ORDER)])
    summary = tmp_path / "check.json"
    code = main(["openpose", "check", str(recording), str(single), "--json", str(summary)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.err == ""
    lines = captured.out.splitlines()
    assert lines[0] == f"{recording}: COCO, pixels, 6 frames"
    assert lines[1] == "  people per frame: min 0, median 2, max 2"
    assert lines[2].startswith(f"  skipped: 1 (1 unparseable JSON); first: {recording}/")
    assert lines[3] == (
        "  tracked person: seen in 4 frames; jump between frames median 3 px, p95 3 px (2 pairs)"
    )
    assert lines[4] == f"{single}: BODY_25, pixels, 1 frame"
    assert lines[-1] == f"wrote {summary}"
    first, second = json.loads(summary.read_text())["paths"]
    assert first["path"] == str(recording) and first["model"] == "COCO"
    assert first["keypoint_scale"] == "pixels" and first["frames"] == 6
    assert first["people_per_frame"] == {"min": 0, "median": 2.0, "max": 2}
    assert first["skipped"] == 1 and first["skipped_reasons"] == {"unparseable JSON": 1}
    (example,) = first["skipped_examples"]
    assert example["file"] == str(recording / openpose_name(2))
    assert example["reason"].startswith(f"{recording / openpose_name(2)}: expected OpenPose JSON")
    assert first["tracked_frames"] == 4
    assert first["jump_px"] == {"median": 3.0, "p95": 3.0, "pairs": 2}
    assert second["model"] == "BODY_25" and second["frames"] == 1
    assert second["jump_px"] == {"median": None, "p95": None, "pairs": 0}


def test_input_that_is_not_openpose_output_is_one_error_line(tmp_path, recording, capsys):
    summary = tmp_path / "check.json"
    other = tmp_path / "coco_annotations.json"
    other.write_text(json.dumps({"images": [], "annotations": []}))
    code = main(["openpose", "check", str(recording), str(other), "--json", str(summary)])
    assert code == 2
    assert _one_error_line(capsys) == (
        f"error: {other}: people: expected a list of people (OpenPose's --write_json output)"
    )
    empty = tmp_path / "no_frames"
    empty.mkdir()
    assert main(["openpose", "check", str(empty), "--json", str(summary)]) == 2
    assert _one_error_line(capsys) == (
        f"error: {empty}: expected OpenPose JSON frames (*_keypoints.json or *.json), found none"
    )
    assert not summary.exists()  # no partial output


@pytest.mark.parametrize(
    ("option", "expected"),
    [
        (["--json", "missing/check.json"], "--json: expected an existing directory"),
        (["--json", "check.txt"], "--json: expected a path ending in .json"),
        (["--model", "BODY_25B"], "--model: expected one of auto, COCO, BODY_25, got 'BODY_25B'"),
        (["--keypoint-scale", "unit"], "--image-size: expected (width, height) in pixels"),
        (["--near", "nan", "nan"], "--near: expected a finite pixel U V, got nan nan"),
        (["--near", "10", "inf"], "--near: expected a finite pixel U V, got 10.0 inf"),
    ],
)
def test_bad_options_are_one_error_line_and_write_nothing(
    tmp_path, recording, capsys, monkeypatch, option, expected
):
    monkeypatch.chdir(tmp_path)
    assert main(["openpose", "check", str(recording), *option]) == 2
    assert _one_error_line(capsys).startswith(f"error: {expected}")
    assert sorted(path.name for path in tmp_path.iterdir()) == ["session"]
