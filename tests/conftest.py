"""Shared fixtures: bundled scenarios, a writer for modified copies of them, and the demo run
once for every test that looks at it (its cycle, its truth, its replay)."""

from __future__ import annotations

import base64
import copy
import re
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import msgpack
import pytest
import yaml
from pydrake.geometry import Meshcat

from hsr_handover.experiments.handover.scoring import HandoverScorer, TrialScore
from hsr_handover.replay.meshcat_replay import write_replay
from hsr_handover.scenario import Scenario, load_scenario
from hsr_handover.simulation import RunReport, run_scenario

REPO = Path(__file__).resolve().parents[1]
SCENARIOS = REPO / "scenarios"


_BLOB = re.compile(rb"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)")


def meshcat_commands(html: str | bytes) -> list[dict]:
    """The Meshcat commands a static HTML replay holds (base64 msgpack blobs), decoded."""
    html = html.encode() if isinstance(html, str) else html
    return [
        msgpack.unpackb(base64.b64decode(blob), raw=False, strict_map_key=False)
        for blob in _BLOB.findall(html)
    ]


def replay_commands(meshcat: Meshcat, folder: Path) -> list[dict]:
    """Stop the recording, write the replay HTML into `folder` and decode its commands."""
    return meshcat_commands(write_replay(meshcat, folder / "replay.html").read_bytes())


def hidden_paths(commands: list[dict]) -> set[str]:
    """Paths whose last `visible` setting in the scene is False."""
    visible = {
        c["path"]: c["value"]
        for c in commands
        if c["type"] == "set_property" and c["property"] == "visible"
    }
    return {path for path, value in visible.items() if value is False}


def animation_keys(commands: list[dict], track_name: str) -> dict[str, list[tuple[float, object]]]:
    """Each animated path's keyframes on one track (".visible", ".position", ...) as (time s,
    value)."""
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    keys = {}
    for entry in animation["animations"]:
        clip = entry["clip"]
        for track in clip["tracks"]:
            if track["name"] == track_name:
                keys[entry["path"]] = [(k["time"] / clip["fps"], k["value"]) for k in track["keys"]]
    return keys


def visibility_keys(commands: list[dict]) -> dict[str, list[tuple[float, bool]]]:
    """Each animated path's `visible` keyframes as (time s, value)."""
    return animation_keys(commands, ".visible")


def bundled_scenarios() -> list[Path]:
    return sorted(SCENARIOS.rglob("*.yaml"))


@pytest.fixture(scope="session")
def point_left_data() -> dict:
    return yaml.safe_load((SCENARIOS / "point_left.yaml").read_text())


@pytest.fixture
def write_scenario(tmp_path: Path, point_left_data: dict) -> Callable[..., Path]:
    """Write point_left.yaml, changed by `mutate(data)`, into a temporary file."""

    def write(mutate: Callable[[dict], None] | None = None, name: str = "scenario.yaml") -> Path:
        data = copy.deepcopy(point_left_data)
        if mutate is not None:
            mutate(data)
        path = tmp_path / name
        path.write_text(yaml.safe_dump(data, sort_keys=False))
        return path

    return write


class DemoRun(NamedTuple):
    scenario: Scenario
    report: RunReport
    score: TrialScore  # the truth scorer's, for the box the person asks for
    replay: Path


@pytest.fixture(scope="session")
def demo(tmp_path_factory: pytest.TempPathFactory) -> DemoRun:
    """The bundled demo, run once (about 2 minutes) with the truth scorer watching and its
    replay written."""
    scenario = load_scenario(SCENARIOS / "demo.yaml")
    scorers: list[HandoverScorer] = []

    def scorer(simulation) -> HandoverScorer:
        scorers.append(HandoverScorer(simulation, "yellow_box", scenario.table.height))
        return scorers[-1]

    replay = tmp_path_factory.mktemp("demo") / "demo.html"
    report = run_scenario(scenario, replay=replay, monitor_factory=scorer)
    return DemoRun(scenario, report, scorers[0].score, replay)
