"""`hsr-handover run` end to end, as a user runs it: a replay that holds the recording."""

from __future__ import annotations

import base64
import re
import subprocess
import sys

from tests.conftest import SCENARIOS

_BLOB = re.compile(rb"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)")


def _meshcat_commands(html: bytes) -> list[bytes]:
    return [base64.b64decode(blob) for blob in _BLOB.findall(html)]


def test_run_writes_a_replay_holding_the_recording(tmp_path):
    replay = tmp_path / "left.html"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "hsr_handover.cli",
            "run",
            str(SCENARIOS / "point_left.yaml"),
            "--html",
            str(replay),
            "--duration",
            "0.3",
            "--seed",
            "3",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    for label in ("sim time:", "wall time:", "real-time factor:", f"replay:      {replay}"):
        assert label in result.stdout
    assert "0.30 / 0.30 s simulated" in result.stderr  # the progress bar reached the end
    commands = _meshcat_commands(replay.read_bytes())
    animations = [c for c in commands if b"set_animation" in c]
    assert len(animations) == 1
    for path in (
        b"/drake/visualizer/red_cup",
        b"/drake/visualizer/person",
        b"/drake/visualizer/hsrb",
    ):
        assert path in animations[0]
    assert not list(tmp_path.glob(".*.tmp"))  # no temporary left behind
