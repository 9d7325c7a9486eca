"""Shared fixtures: bundled scenarios and a writer for modified copies of them."""

from __future__ import annotations

import copy
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
SCENARIOS = REPO / "scenarios"


def bundled_scenarios() -> list[Path]:
    return sorted(SCENARIOS.glob("*.yaml"))


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
