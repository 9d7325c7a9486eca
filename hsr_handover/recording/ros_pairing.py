"""Two streams of stamped messages paired by their stamps: each message of one with the nearest
of the other within a tolerance, one to one, as ROS's approximate-time synchroniser pairs a
camera's colour and depth images."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np


@dataclasses.dataclass(frozen=True)
class Pairing:
    """`pairs`: (index in `first`, index in `second`), rising; `unpaired_first` and
    `unpaired_second`: the indices left without a partner."""

    pairs: tuple[tuple[int, int], ...]
    unpaired_first: tuple[int, ...]
    unpaired_second: tuple[int, ...]


def nearest_index(stamps: np.ndarray, time: float) -> int:
    """The index of the stamp nearest `time` in rising `stamps` (-1 when there are none)."""
    if len(stamps) == 0:
        return -1
    right = int(np.searchsorted(stamps, time))
    candidates = [index for index in (right - 1, right) if 0 <= index < len(stamps)]
    return min(candidates, key=lambda index: abs(stamps[index] - time))


def pair_stamps(first: Sequence[float], second: Sequence[float], tolerance: float) -> Pairing:
    """Pair each stamp of `first` with the nearest of `second` no more than `tolerance` s away;
    where two claim the same partner, the nearer keeps it. Both sequences must rise."""
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    candidates = []
    for i, stamp in enumerate(first):
        j = nearest_index(second, stamp)
        if j >= 0 and abs(second[j] - stamp) <= tolerance:
            candidates.append((abs(second[j] - stamp), i, j))
    taken: dict[int, int] = {}
    for _, i, j in sorted(candidates):
        if j not in taken:
            taken[j] = i
    pairs = tuple(sorted((i, j) for j, i in taken.items()))
    paired_first = {i for i, _ in pairs}
    return Pairing(
        pairs,
        tuple(i for i in range(len(first)) if i not in paired_first),
        tuple(j for j in range(len(second)) if j not in taken),
    )


def default_tolerance(stamps: Sequence[float], fallback_period: float = 1.0 / 30.0) -> float:
    """Half the stream's median period (half of `fallback_period` for fewer than 2 stamps)."""
    period = float(np.median(np.diff(stamps))) if len(stamps) > 1 else fallback_period
    return 0.5 * period
