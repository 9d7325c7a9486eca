"""A Scenario written back as a scenario file, which `load_scenario` reads to the same
Scenario (an experiment's generated layouts, each replayable alone with `run`)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from hsr_handover.scenario.schema import Scenario
from hsr_handover.scenario.typed_yaml import YAML_KEY


def _plain(value: Any) -> Any:
    """Dataclasses as mappings of their YAML keys, with None (a default) left out."""
    if dataclasses.is_dataclass(value):
        return {
            spec.name: _plain(getattr(value, spec.name))
            for spec in dataclasses.fields(value)
            if spec.metadata.get(YAML_KEY, True) and getattr(value, spec.name) is not None
        }
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    if isinstance(value, bool | str):
        return value
    if isinstance(value, int | np.integer):
        return int(value)
    return float(value)  # numpy's floats too, which YAML cannot write


def write_scenario(scenario: Scenario, path: Path, comment: str = "") -> None:
    """Write `scenario` to `path` as YAML, `comment` (one or more lines) at its head."""
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    body = yaml.safe_dump(_plain(scenario), sort_keys=False, default_flow_style=None, width=100)
    path.write_text(head + body)
