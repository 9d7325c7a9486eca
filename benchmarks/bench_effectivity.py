"""The arm's effectivity map (paper fig. 8): building it against loading it from the cache, and
the palm's error when the arm takes eq. 11's joints, at the nodes and at random reachable
targets.

    python benchmarks/bench_effectivity.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from hsr_handover.kinematics.hsr_arm import palm_position, sample_arm_joints
from hsr_handover.robot.effectivity import ArmMapParams, load_or_build


def _timed(call) -> tuple[float, object]:
    start = time.perf_counter()
    result = call()
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    params = ArmMapParams()
    builds, loads = [], []
    for _ in range(args.repeats):
        with tempfile.TemporaryDirectory() as folder:
            built, (arm_map, cached) = _timed(lambda: load_or_build(params, Path(folder)))
            assert not cached
            loaded, (_, cached) = _timed(lambda: load_or_build(params, Path(folder)))
            assert cached
        builds.append(built)
        loads.append(loaded)
    build, load = statistics.median(builds), statistics.median(loads)
    print(f"arm map, {arm_map.nodes.shape[0]} nodes from {params.samples} samples")
    print(f"build (baseline) {build * 1e3:8.1f} ms   load from cache {load * 1e3:6.1f} ms   "
          f"({build / load:.0f}x), medians of {args.repeats}")  # fmt: skip
    targets = palm_position(sample_arm_joints(5000, np.random.default_rng(1)))
    for name, points in (("at the nodes", arm_map.nodes), ("at random targets", targets)):
        errors = arm_map.palm_errors(points) * 100
        print(f"eq. 11 palm error {name:18s} median {np.median(errors):5.1f} cm, "
              f"p95 {np.percentile(errors, 95):5.1f} cm")  # fmt: skip
    share = arm_map.reachable(targets).mean()
    print(f"random reachable targets the map calls reachable: {share:.1%} "
          f"(tolerance {arm_map.resolution / 2 * 100:.1f} cm, half the median edge)")  # fmt: skip


if __name__ == "__main__":
    main()
