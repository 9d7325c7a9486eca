"""The planning benchmark's output, on one small scene: its figures (success, plan times,
clearance, collisions) for every plan kind the handover cycle makes, the kinds the arm's map
seeds planned seeded and unseeded in the same run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_planning.py"
KEYS = ("success_rate", "median_plan_s", "p95_plan_s", "min_clearance_m", "collisions")
KINDS = ("grasp", "carry", "follow", "put back", "retreat", "back off", "posture")


def test_the_benchmark_writes_its_figures_for_every_kind(tmp_path):
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
    assert tuple(kinds) == KINDS
    for kind in KINDS:
        assert {"success_rate", "median_plan_s", "p95_plan_s", "plans"} <= set(kinds[kind])
        assert kinds[kind]["plans"] >= 1, kind
    assert kinds["grasp"]["plans"] == 2 and kinds["posture"]["plans"] == 2
    assert kinds["carry"]["plans"] == 2  # from each grasp
    assert set(figures["unseeded"]["by_kind"]) == {"grasp", "carry"}  # what the map seeds
    assert figures["plans"] == sum(kinds[kind]["plans"] for kind in KINDS)
    assert kinds["grasp"]["success_rate"] == 1.0 and figures["collisions"] == 0
    assert figures["min_clearance_m"] >= 0.01
    # A plan that fails is counted with its reason and judged, never dropped.
    failed = [plan for plan in figures["plans_detail"] if not plan["ok"]]
    assert all(plan["reason"] for plan in failed)
    planned = [plan for plan in failed if "plan_s" in plan]  # not "no person perceived"
    assert all(plan["judged"] in ("missed", "unreachable") for plan in planned)
    seeded = [plan for plan in planned if plan["variant"] == "seeded"]
    assert sum(figures["failures"].values()) == len(seeded)
    plans = figures["plans_detail"]
    assert {plan["variant"] for plan in plans} == {"seeded", "unseeded"}
    assert "baseline" in result.stdout and "posture" in result.stdout


def test_generated_layouts_are_planned_in(tmp_path):
    sys.path.insert(0, str(BENCH.parent))
    try:
        import bench_planning
    finally:
        sys.path.remove(str(BENCH.parent))
    specs = bench_planning.scene_specs(6, 2, 0, "both")
    assert [spec.generated for spec in specs] == [False, True, False]
    first, again = (bench_planning.scene_scenario(specs[1]) for _ in range(2))
    assert first.table.size == again.table.size  # the same seed, the same layout
    bundled = bench_planning.load_scenario(bench_planning.ROOT / specs[1].scenario)
    assert first.table.size != bundled.table.size
