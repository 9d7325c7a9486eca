"""`hsr-handover effectivity` end to end: figs. 8 and 14 from what the robot
perceives of a bundled scene, and drawn in its replay as the paper draws them."""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest

from hsr_handover.replay.overlays import (
    ARM_MAP,
    HANDOVER_POINT,
    MUTUAL_AREA,
    OVERLAYS,
    PERSON_RANGE,
    PLANNED_ROBOT,
    SCENE_MAP,
    Overlay,
)
from tests.browser import changed_pixels, open_replay
from tests.paths import SCENARIOS

OVERLAY_PIXELS = 20  # changed pixels that say an overlay is drawn (a 640 x 480 view)


def _effectivity(*arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "hsr_handover.cli", "effectivity", *arguments],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def _meshcat_paths(html: str) -> set[str]:
    """The Meshcat paths the replay's embedded commands name (each a base64 msgpack blob)."""
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return {path.decode() for blob in blobs
            for path in re.findall(rb"/overlays/[\w/]+", base64.b64decode(blob))}  # fmt: skip


class Figures(NamedTuple):
    result: subprocess.CompletedProcess
    plot: Path
    summary: Path
    replay: Path


@pytest.fixture(scope="module")
def figures(tmp_path_factory: pytest.TempPathFactory) -> Figures:
    """The command run once on the intent reference scene, with every output."""
    folder = tmp_path_factory.mktemp("effectivity")
    plot, summary = folder / "effectivity.png", folder / "effectivity.json"
    replay = folder / "effectivity.html"
    result = _effectivity(str(SCENARIOS / "intent_reference.yaml"), "--plot", str(plot),
                          "--json", str(summary), "--html", str(replay))  # fmt: skip
    return Figures(result, plot, summary, replay)


def test_the_figures_come_from_the_perceived_scene(figures: Figures):
    result, plot, summary, replay = figures
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
    for layer in ("arm_map/nodes", "arm_map/edges", "person_range/nodes", "mutual_area/nodes",
                  "handover_point/mark"):  # fmt: skip
        assert f"{OVERLAYS}/{layer}" in drawn
    assert any(path.startswith(f"{OVERLAYS}/planned_robot/") for path in drawn)


def _drawn(replay, overlay: Overlay) -> int:
    """Pixels the overlay changes in the replay's opening view: drawn, then switched off."""
    on = replay.frame(1.0)
    replay.set_visible(overlay.path, False)
    off = replay.frame(1.0)
    replay.set_visible(overlay.path, True)
    return changed_pixels(on, off)


def test_the_replay_draws_the_map_round_the_robot_at_its_handover_pose(figures: Figures):
    assert figures.result.returncode == 0, figures.result.stderr
    layers = (SCENE_MAP, ARM_MAP, PERSON_RANGE, MUTUAL_AREA, HANDOVER_POINT, PLANNED_ROBOT)
    with open_replay(figures.replay) as replay:
        replay.wait_for_viewer()
        rows = replay.page.locator("#overlay-legend li").evaluate_all(
            "items => items.map(item => item.dataset.overlay)"
        )
        drawn = {overlay.name: _drawn(replay, overlay) for overlay in layers}
        edges = replay.evaluate(
            "() => viewer.scene_tree.children.overlays.children.arm_map.children.edges"
            ".children['<object>'].object.geometry.attributes.position.count"
        )
        assert replay.errors == []
    print(f"effectivity replay, pixels on/off: {drawn}; arm map edge ends: {edges}")
    assert rows == [overlay.name for overlay in layers]
    assert all(count > OVERLAY_PIXELS for count in drawn.values()), drawn
    summary = json.loads(figures.summary.read_text())
    assert summary["handover_base"] is not None and edges > summary["arm_nodes"]


def test_a_bad_output_path_is_refused_before_anything_runs(tmp_path):
    result = _effectivity(str(SCENARIOS / "intent_reference.yaml"), "--plot",
                          str(tmp_path / "figure.jpg"))  # fmt: skip
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert "--plot" in result.stderr and ".png or .svg or .pdf" in result.stderr
