"""Fixtures every test may use: a writer for modified copies of a bundled scenario. Nothing here
imports Drake, so the numpy algorithms' tests run without it; whole simulations have their own
fixtures in `tests/integration/conftest.py`."""

from __future__ import annotations

import copy
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml

from tests.paths import SCENARIOS


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
