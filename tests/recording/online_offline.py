"""The check that a recording, replayed offline through `intent`, recognises what the robot did
online and when (the simulated `point_left.yaml`: red, at 30 Hz, 105 frames)."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import pytest
import yaml

from hsr_handover.cli import main
from tests.paths import SCENARIOS


def record_point_left(folder: Path, recording: Path, *options: str) -> str:
    """point_left.yaml at the experiments' 320 x 240, run with `--record recording` (and
    `options`) until just after the robot recognises the request; the run's printout."""
    scenario = yaml.safe_load((SCENARIOS / "point_left.yaml").read_text())
    scenario["camera"] = {"width": 320, "height": 240, "render_label": False}
    scenario["perception"] = {"enabled": True}
    scenario["simulation"]["duration"] = 3.5
    path = folder / "point_left.yaml"
    path.write_text(yaml.safe_dump(scenario))
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["run", str(path), "--record", str(recording), *options,
                     "--html", str(folder / "r.html")])  # fmt: skip
    assert code == 0
    return printed.getvalue()


def line(output: str, label: str) -> str:
    return next(line for line in output.splitlines() if line.startswith(label))


def assert_offline_as_online(recording: Path, printed: str, folder: Path, capsys) -> None:
    """`intent` on `recording` prints the target and time the run printed (`printed`), and its
    --json frame is the one of that time."""
    online = line(printed, "intent:")
    matched = re.fullmatch(r"intent:      red \(recognised at (\d\.\d\d) s\)", online)
    assert matched is not None, online
    summary = folder / "intent.json"
    assert main(["intent", str(recording), "--json", str(summary)]) == 0
    out = capsys.readouterr().out
    assert line(out, "intent:") == online
    assert line(out, "frames:") == "frames:      105 at 30 Hz"
    written = json.loads(summary.read_text())
    frame = written["frame"]
    assert written["target"] == "red"
    assert written["recognised_time"] == pytest.approx(frame / 30, abs=1e-6)
    assert f"{frame / 30:.2f}" == matched.group(1)
