"""Where the repository and its bundled scenarios are."""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SCENARIOS = REPO / "scenarios"


def bundled_scenarios() -> list[Path]:
    return sorted(SCENARIOS.rglob("*.yaml"))
