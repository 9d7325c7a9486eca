"""A session recorded from the simulation (`run --record`) and perceived offline (`intent`):
the same target at the same time as the robot recognised online; bad folders refused with one
line and exit status 2, before anything is written."""

from __future__ import annotations

import pytest

from hsr_handover.cli import main
from tests.paths import SCENARIOS
from tests.recording.online_offline import assert_offline_as_online, record_point_left


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """point_left.yaml recorded as a session folder: the run's printout and the folder."""
    folder = tmp_path_factory.mktemp("offline")
    session = folder / "session"
    return folder, session, record_point_left(folder, session)


def test_offline_intent_recognises_what_the_robot_did_online_and_when(recorded, capsys):
    folder, session, printed = recorded
    assert_offline_as_online(session, printed, folder, capsys)


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
