"""`hsr-handover effectivity` end to end: figs. 8 and 14 from what the robot
perceives of a bundled scene."""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys

import numpy as np

from tests.paths import SCENARIOS


def _effectivity(*arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "hsr_handover.cli", "effectivity", *arguments],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def _meshcat_paths(html: str) -> set[str]:
    """The Meshcat paths the replay's embedded commands name (each a base64 msgpack blob)."""
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return {path.decode() for blob in blobs
            for path in re.findall(rb"/drake/[\w/]+", base64.b64decode(blob))}  # fmt: skip


def test_the_figures_come_from_the_perceived_scene(tmp_path):
    plot, summary = tmp_path / "effectivity.png", tmp_path / "effectivity.json"
    replay = tmp_path / "effectivity.html"
    result = _effectivity(str(SCENARIOS / "intent_reference.yaml"), "--plot", str(plot),
                          "--json", str(summary), "--html", str(replay))  # fmt: skip
    assert result.returncode == 0, result.stderr
    figures = json.loads(summary.read_text())
    assert figures["status"] == "ok" and figures["arm_nodes"] >= 108
    assert figures["palm_error_median_m"]["nodes"] < 0.05
    arm = figures["person_arm"]
    # The perceived arm of the simulated adult (1.70 m: about 0.64 m shoulder to palm).
    assert 0.5 < arm["upper_m"] + arm["forearm_m"] + arm["hand_m"] < 0.8
    assert figures["mutual_nodes"] > 0
    point = np.array(figures["handover_point"])
    assert point[2] > 0.72 + 0.15  # above the table's top
    assert np.linalg.norm(point - np.array(figures["ideal_point"])) < 0.25
    assert plot.stat().st_size > 20_000 and "handover point" in result.stdout
    assert replay.stat().st_size > 100_000 and str(replay) in result.stdout
    drawn = _meshcat_paths(replay.read_text())
    for layer in ("arm_map", "person_range", "mutual_area", "handover_point"):
        assert f"/drake/effectivity/{layer}" in drawn


def test_a_bad_output_path_is_refused_before_anything_runs(tmp_path):
    result = _effectivity(str(SCENARIOS / "intent_reference.yaml"), "--plot",
                          str(tmp_path / "figure.jpg"))  # fmt: skip
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "--plot" in result.stderr and ".png or .svg or .pdf" in result.stderr
