"""`hsr-handover run` end to end, as a user runs it: a replay that holds the recording."""

from __future__ import annotations

import subprocess
import sys

from tests.conftest import SCENARIOS, meshcat_commands


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
    commands = meshcat_commands(replay.read_bytes())
    (animation,) = [c for c in commands if c.get("type") == "set_animation"]
    animated = {entry["path"] for entry in animation["animations"]}
    for model in ("red_cup", "person", "hsrb", "table"):
        assert any(path.startswith(f"/drake/visualizer/{model}/") for path in animated), model
    clip = animation["animations"][0]["clip"]
    assert clip["fps"] == 20 and max(key["time"] for key in clip["tracks"][0]["keys"]) >= 5
    assert not list(tmp_path.glob(".*.tmp"))  # no temporary left behind
