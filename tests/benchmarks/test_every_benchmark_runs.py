"""Every script under benchmarks/ runs to the end with its smallest settings and prints its
figures: a benchmark that nothing runs breaks unseen. The heavy ones (whole trials or
simulations of several seconds) are marked slow; `bench_planning` has its own test."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"

# script -> (its smallest arguments, a line fragment its output must hold, slow)
SMALLEST = {
    "bench_active_perception.py": (
        ["--requests", "1", "--distractors", "0", "--handovers", "1", "--workers", "1"],
        "baseline", True,
    ),
    "bench_effectivity.py": (["--repeats", "1"], "", False),
    "bench_handover_trial.py": (["--trials", "0"], "", True),
    "bench_intent_rays.py": (["--requests", "1", "--workers", "1"], "", True),
    "bench_perception.py": (
        ["--repeats", "1", "--runs", "1", "--duration", "0.2"], "", True,
    ),
    "bench_scene_gng.py": (["--seeds", "0"], "", True),
    "bench_station.py": (["--repeats", "1", "--duration", "0.1"], "real-time factor", False),
    "bench_topology.py": (["--quick"], "", False),
    "sweep_detector.py": (
        ["--trials", "1", "--distractors", "0", "--detectors", "ideal", "--pointing", "7.3",
         "--workers", "1"],
        "", True,
    ),
    "sweep_intent.py": (["--trials", "1", "--distractors", "0", "--workers", "1"], "", True),
}  # fmt: skip


def test_every_benchmark_is_listed():
    scripts = {path.name for path in BENCHMARKS.glob("*.py")} - {"bench_planning.py"}
    assert scripts == set(SMALLEST)


@pytest.mark.parametrize(
    "script",
    [
        pytest.param(name, marks=[pytest.mark.slow] if slow else [])
        for name, (_, _, slow) in SMALLEST.items()
    ],
)
def test_the_benchmark_runs_with_its_smallest_settings(script, tmp_path):
    arguments, expected, _ = SMALLEST[script]
    result = subprocess.run(
        [sys.executable, str(BENCHMARKS / script), *arguments],
        capture_output=True, text=True, timeout=1200, check=False, cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip(), "printed nothing"
    assert expected in result.stdout
