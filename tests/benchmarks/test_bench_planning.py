"""The planning benchmark's output, on one small scene: its figures (success, plan times,
clearance, collisions), seeded and unseeded in the same run, grasps and handovers from them."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_planning.py"
KEYS = ("success_rate", "median_plan_s", "p95_plan_s", "min_clearance_m", "collisions")


def test_the_benchmark_writes_its_figures_for_both_seeds(tmp_path):
    output = tmp_path / "planning.json"
    result = subprocess.run(
        [sys.executable, str(BENCH), "--targets", "2", "--per-scene", "2", "--workers", "1",
         "--json", str(output)],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    figures = json.loads(output.read_text())
    for key in KEYS:
        assert key in figures and key in figures["unseeded"], key
    assert figures["failed_scenes"] == []
    kinds = figures["by_kind"]
    assert kinds["grasp"]["plans"] == 2 and kinds["handover"]["plans"] == 2  # from each grasp
    assert figures["plans"] == 4
    assert kinds["grasp"]["success_rate"] == 1.0 and figures["collisions"] == 0
    assert figures["min_clearance_m"] >= 0.01
    # A plan that fails is counted with its reason (here the handovers may find no mutual area
    # past the table's unseen ends), never dropped.
    failed = [plan for plan in figures["plans_detail"] if not plan["ok"]]
    assert all(plan["reason"] for plan in failed)
    assert sum(figures["failures"].values()) == len([p for p in failed if p["variant"] == "seeded"])
    plans = figures["plans_detail"]
    assert {plan["variant"] for plan in plans} == {"seeded", "unseeded"}
    assert "seeded" in result.stdout and "unseeded" in result.stdout
