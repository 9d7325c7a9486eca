"""A session recorded from the simulation (`run --record`) and perceived offline (`intent`):
the same target at the same time as the robot recognised online; bad folders refused with one
line and exit status 2, before anything is written."""

from __future__ import annotations

import contextlib
import io
import json
import re

import pytest
import yaml

from hsr_handover.cli import main
from tests.paths import SCENARIOS


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """point_left.yaml at the experiments' 320 x 240, run with --record until just after the
    robot recognises the request; the run's printout and the session folder."""
    folder = tmp_path_factory.mktemp("offline")
    scenario = yaml.safe_load((SCENARIOS / "point_left.yaml").read_text())
    scenario["camera"] = {"width": 320, "height": 240, "render_label": False}
    scenario["perception"] = {"enabled": True}
    scenario["simulation"]["duration"] = 3.5
    path = folder / "point_left.yaml"
    path.write_text(yaml.safe_dump(scenario))
    session, printed = folder / "session", io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["run", str(path), "--record", str(session), "--html", str(folder / "r.html")])
    assert code == 0
    return folder, session, printed.getvalue()


def _line(output: str, label: str) -> str:
    return next(line for line in output.splitlines() if line.startswith(label))


def test_offline_intent_recognises_what_the_robot_did_online_and_when(recorded, capsys):
    folder, session, printed = recorded
    online = _line(printed, "intent:")
    matched = re.fullmatch(r"intent:      red \(recognised at (\d\.\d\d) s\)", online)
    assert matched is not None, online
    summary = folder / "intent.json"
    assert main(["intent", str(session), "--json", str(summary)]) == 0
    out = capsys.readouterr().out
    assert _line(out, "intent:") == online
    assert _line(out, "frames:") == "frames:      105 at 30 Hz"
    written = json.loads(summary.read_text())
    frame = written["frame"]
    assert written["target"] == "red" and written["recognised_time"] == pytest.approx(frame / 30)
    assert f"{frame / 30:.2f}" == matched.group(1)


def test_run_refuses_to_record_over_another_session(recorded, tmp_path, capsys):
    _, session, _ = recorded
    replay = tmp_path / "never.html"
    code = main(["run", str(SCENARIOS / "point_left.yaml"), "--record", str(session),
                 "--html", str(replay)])  # fmt: skip
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    assert captured.err.strip() == (
        f"error: --record: expected a new or empty directory, {str(session)!r} is not"
    )
    assert not replay.exists()


def test_intent_refuses_a_folder_that_is_not_a_session(tmp_path, capsys):
    output = tmp_path / "out.json"
    code = main(["intent", str(tmp_path), "--json", str(output)])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    assert captured.err.strip() == (
        f"error: {tmp_path}: expected a recorded session (camera_info.yaml not found)"
    )
    assert not output.exists()
