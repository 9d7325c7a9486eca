"""Shared fixtures: bundled scenarios and a writer for modified copies of them."""

from __future__ import annotations

import base64
import copy
import re
from collections.abc import Callable
from pathlib import Path

import msgpack
import pytest
import yaml

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
