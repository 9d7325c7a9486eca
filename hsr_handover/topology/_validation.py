"""Checks of parameters and input arrays, with errors that name what was expected."""

from __future__ import annotations

import numbers

import numpy as np

from hsr_handover.topology._batch_search import finite_rows as _finite_kernel


def check_int(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < minimum:
        raise ValueError(f"{name}: expected an integer >= {minimum}, got {value!r}")
    return int(value)


def check_real(
    name: str, value: object, low: float, high: float = np.inf, *, open_high: bool = False
) -> float:
    """A finite real in [low, high] (or [low, high) when open_high)."""
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if ok:
        value = float(value)
        ok = np.isfinite(value) and low <= value and (value < high if open_high else value <= high)
    if not ok:
        bracket = ")" if open_high else "]"
        raise ValueError(
            f"{name}: expected a finite number in [{low}, {high}{bracket}, got {value!r}"
        )
    return float(value)


def as_points(points: object, dim: int | None, name: str = "points") -> np.ndarray:
    """points as a float64 (n, d) array; d must equal dim when dim is known.

    An empty input of any shape becomes (0, dim).
    """
    array = np.asarray(points, dtype=np.float64)
    if array.size == 0:
        return np.empty((0, dim or 0))
    expected = f"(n, {dim})" if dim is not None else "(n, d)"
    if array.ndim != 2 or (dim is not None and array.shape[1] != dim):
        raise ValueError(f"{name}: expected shape {expected}, got {array.shape}")
    return array


def finite_rows(points: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """Mask of rows whose coordinates (and weight, if given) are all finite."""
    mask = _finite_kernel(np.ascontiguousarray(points))
    if weights is not None:
        mask &= np.isfinite(weights)
    return mask


def as_weights(weights: object, n: int) -> np.ndarray | None:
    if weights is None:
        return None
    array = np.asarray(weights, dtype=np.float64)
    if array.shape != (n,):
        raise ValueError(f"weights: expected shape ({n},), one per point, got {array.shape}")
    if np.any(array < 0):  # NaN compares False: NaN weights are dropped with their points
        raise ValueError("weights: expected non-negative sampling weights")
    return array


def draw_order(
    rng: np.random.Generator, n: int, n_signals: int | None, weights: np.ndarray | None
) -> np.ndarray:
    """Indices of the points to learn, in order.

    By default every point once in random order; with weights, n_signals (default n) draws
    with probability proportional to weight (attention).
    """
    if weights is None:
        if n_signals is None:
            return rng.permutation(n)
        return rng.integers(0, n, size=n_signals)
    cumulative = np.cumsum(weights)
    if cumulative[-1] <= 0.0:
        return np.empty(0, dtype=np.int64)
    size = n if n_signals is None else n_signals
    # Sorted draws (from exponential spacings) make searchsorted walk instead of jump; the
    # shuffle afterwards restores a random order of signals.
    spacings = np.cumsum(rng.exponential(size=size + 1))
    draws = spacings[:-1] * (cumulative[-1] / spacings[-1])
    picked = np.minimum(np.searchsorted(cumulative, draws, side="right"), n - 1)
    return rng.permutation(picked)
