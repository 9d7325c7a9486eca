"""Speed and quality of the topology core (GNG, Growing Cell Structures), one run, printed.

    python benchmarks/bench_topology.py [--quick]

Prints: numba compile time of the first calls (cold cache, in a subprocess); GNG signals/s on
the 3-box surface workload (median of runs after a warm-up) with quantisation and topographic
error, beside a plain numpy per-signal GNG on the same workload; a 200 x 200 attention frame
(5,000 signals + labels for 40,000 points); the attention density ratio against sampling
weight; the HSR arm's Growing Cell Structures (forward-kinematics error of payloads, eq. 11
joints and reachability).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.spatial import cKDTree

from hsr_handover.kinematics.hsr_arm import palm_position, sample_arm_joints
from hsr_handover.topology import GrowingCellStructures, GrowingNeuralGas, metrics
from hsr_handover.topology.synthetic import (
    THREE_BOX_CENTRES,
    THREE_BOX_SIZES,
    box_surface_area,
    box_surface_points,
)

PARAMS = dict(max_nodes=300, lam=100, mu1=0.05, mu2=0.006, a_max=50, alpha=0.5, beta=0.0005)
N_SIGNALS = 50_000

COMPILE_SNIPPET = """
import time
t0 = time.perf_counter()
import numpy as np
from hsr_handover.topology import GrowingCellStructures, GrowingNeuralGas
t1 = time.perf_counter()
points = np.random.default_rng(0).random((2000, 3))
gas = GrowingNeuralGas(max_nodes=20, random_state=0).fit(points)
t2 = time.perf_counter()
gas.nearest(points)
t3 = time.perf_counter()
GrowingCellStructures(max_nodes=20, random_state=0).fit(points, points).payload_at(points)
t4 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3)
"""


def first_call_seconds(cache_dir: str) -> list[float]:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    out = subprocess.run(
        [sys.executable, "-c", COMPILE_SNIPPET], env=env, capture_output=True, text=True, check=True
    )
    return [float(v) for v in out.stdout.split()]


def report_compile_time() -> None:
    with tempfile.TemporaryDirectory() as cache:
        cold = first_call_seconds(cache)
        warm = first_call_seconds(cache)
    for label, (imp, fit, near, cells) in (("cold cache", cold), ("warm cache", warm)):
        print(
            f"first call, {label}: import {imp:.2f} s, GNG fit {fit:.2f} s, "
            f"nearest {near:.2f} s, cell structures fit+payload_at {cells:.2f} s"
        )


def numpy_gas(points: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Plain numpy GNG, one signal at a time (Fritzke's steps, the same parameters)."""
    cap = PARAMS["max_nodes"]
    w = np.zeros((cap, points.shape[1]))
    error = np.zeros(cap)
    age = np.full((cap, cap), -1)  # -1: no edge
    alive = np.zeros(cap, dtype=bool)
    w[:2] = points[rng.integers(0, len(points), 2)]
    alive[:2] = True
    for t, p in enumerate(points[rng.permutation(len(points))], start=1):
        dist = np.where(alive, np.sum((w - p) ** 2, axis=1), np.inf)
        s1, s2 = np.argpartition(dist, 1)[:2]
        error[s1] += dist[s1]
        age[s1, s2] = age[s2, s1] = 0
        linked = age[s1] >= 0
        w[linked] += PARAMS["mu2"] * (p - w[linked])
        w[s1] += PARAMS["mu1"] * (p - w[s1])
        age[s1, linked] += 1
        age[linked, s1] += 1
        old = age[s1] > PARAMS["a_max"]
        age[s1, old] = age[old, s1] = -1
        alive &= (age >= 0).any(axis=1)
        if t % PARAMS["lam"] == 0 and alive.sum() < cap:
            q = np.argmax(np.where(alive, error, -1))
            f = np.argmax(np.where(age[q] >= 0, error, -1))
            r = np.argmin(alive)
            w[r], alive[r] = 0.5 * (w[q] + w[f]), True
            age[q, f] = age[f, q] = -1
            age[q, r] = age[r, q] = age[f, r] = age[r, f] = 0
            error[[q, f]] *= 1 - PARAMS["alpha"]
            error[r] = 0.5 * (error[q] + error[f])
        error *= 1 - PARAMS["beta"]
    return w[alive]


def median_rate(run, n_signals: int, repeats: int) -> tuple[float, object]:
    result = run()  # warm-up
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - start)
    return n_signals / float(np.median(times)), result


def report_gas(repeats: int, baseline_repeats: int) -> GrowingNeuralGas:
    rng = np.random.default_rng(0)
    train, held_out = box_surface_points(N_SIGNALS, rng), box_surface_points(20_000, rng)
    rate, gas = median_rate(
        lambda: GrowingNeuralGas(**PARAMS, random_state=1).fit(train), N_SIGNALS, repeats
    )
    qe = metrics.quantisation_error(gas.nodes, held_out)
    te = metrics.topographic_error(gas.nodes, gas.edges, held_out)
    print(f"GNG 3-box, {N_SIGNALS} signals, {gas.n_nodes} nodes, median of {repeats} runs:")
    print(f"  numba: {rate:,.0f} signals/s, quantisation error {qe:.4f} m, topographic {te:.4f}")
    base_rate, base_nodes = median_rate(
        lambda: numpy_gas(train, np.random.default_rng(1)), N_SIGNALS, baseline_repeats
    )
    base_qe = metrics.quantisation_error(base_nodes, held_out)
    print(f"  numpy per-signal baseline: {base_rate:,.0f} signals/s (median of "
          f"{baseline_repeats}), quantisation error {base_qe:.4f} m")  # fmt: skip
    print(f"  speed ratio numba / numpy: {rate / base_rate:.1f}x")
    return gas


def region_of_small_box(points: np.ndarray) -> np.ndarray:
    low = THREE_BOX_CENTRES[1] - THREE_BOX_SIZES[1] / 2 - 0.02
    high = THREE_BOX_CENTRES[1] + THREE_BOX_SIZES[1] / 2 + 0.02
    return np.all((points > low) & (points < high), axis=1)


def report_frame(gas: GrowingNeuralGas, repeats: int) -> None:
    frame = box_surface_points(200 * 200, np.random.default_rng(5))
    weights = np.where(region_of_small_box(frame), 16.0, 1.0)
    times, learn, label = [], [], []
    for _ in range(repeats + 1):
        start = time.perf_counter()
        gas.partial_fit(frame, n_signals=5000, weights=weights)
        middle = time.perf_counter()
        gas.nearest(frame)
        end = time.perf_counter()
        times.append(end - start)
        learn.append(middle - start)
        label.append(end - middle)
    ms = [1e3 * float(np.median(v[1:])) for v in (times, learn, label)]
    print(f"200 x 200 attention frame, median of {repeats}: {ms[0]:.2f} ms "
          f"(5,000 signals {ms[1]:.2f} ms + 40,000 labels {ms[2]:.2f} ms)")  # fmt: skip


def density_ratio(weight: float, **params) -> tuple[float, int]:
    points = box_surface_points(50_000, np.random.default_rng(3))
    inside = region_of_small_box(points)
    gas = GrowingNeuralGas(**params, random_state=3)
    for _ in range(10):
        gas.partial_fit(points, n_signals=10_000, weights=np.where(inside, weight, 1.0))
    areas = box_surface_area(THREE_BOX_SIZES)
    dense, sparse = metrics.node_density(
        gas.nodes, region_of_small_box(gas.nodes), areas[1], areas.sum() - areas[1]
    )
    return dense / sparse, gas.n_nodes


def report_attention() -> None:
    print("attention: node density on the small box / elsewhere (nodes), 100,000 signals")
    settings = {
        "Fritzke (beta 5e-4, e_min 0)": dict(),
        "adaptive (beta 5e-5, e_min 0.07)": dict(beta=5e-5, e_min=0.07),
    }
    for name, params in settings.items():
        curve = []
        for weight in (1, 2, 4, 8, 16, 32, 64):
            ratio, nodes = density_ratio(float(weight), **params)
            curve.append(f"w{weight}: {ratio:.2f} ({nodes})")
        print(f"  {name}: " + ", ".join(curve))


def summary(errors: np.ndarray) -> str:
    return f"mean {100 * errors.mean():.1f} cm, p95 {100 * np.percentile(errors, 95):.1f} cm"


def report_arm_cells() -> None:
    rng = np.random.default_rng(11)
    joints = sample_arm_joints(20_000, rng)
    positions = palm_position(joints)
    start = time.perf_counter()
    cells = GrowingCellStructures(max_nodes=108, mu3=30.0, random_state=0)
    cells.fit(positions, joints, n_signals=40_000)
    seconds = time.perf_counter() - start
    nodes = cells.nodes
    print(f"HSR arm cell structures: 20,000 samples, {cells.n_nodes} nodes, mu3 30/m, "
          f"fit {1e3 * seconds:.0f} ms")  # fmt: skip
    at_nodes = np.linalg.norm(palm_position(cells.payload) - nodes, axis=1)
    eq11_nodes = np.linalg.norm(palm_position(cells.payload_at(nodes)) - nodes, axis=1)
    targets = palm_position(sample_arm_joints(5000, rng))
    eq11_targets = np.linalg.norm(palm_position(cells.payload_at(targets)) - targets, axis=1)
    print(f"  FK error of node payloads at nodes: {summary(at_nodes)}")
    print(f"  FK error of eq. 11 joints at nodes: {summary(eq11_nodes)}")
    print(f"  FK error of eq. 11 joints at random reachable targets: {summary(eq11_targets)}")
    dense = cKDTree(palm_position(sample_arm_joints(1_000_000, rng)))
    boxes = rng.uniform(nodes.min(0) - 0.15, nodes.max(0) + 0.15, size=(5000, 3))
    truth = dense.query(boxes)[0] < 0.01
    for tol in (0.06, 0.08, 0.10):
        accuracy = np.mean(cells.reachable(boxes, tol) == truth)
        print(f"  reachable(tol={tol}) accuracy vs FK ground truth: {accuracy:.3f} "
              f"({truth.mean():.2f} of 5,000 box targets reachable)")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, no compile run")
    args = parser.parse_args()
    if not args.quick:
        report_compile_time()
    gas = report_gas(repeats=3 if args.quick else 7, baseline_repeats=1 if args.quick else 5)
    report_frame(gas, repeats=5 if args.quick else 21)
    report_attention()
    report_arm_cells()


if __name__ == "__main__":
    main()
