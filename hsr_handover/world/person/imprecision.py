"""How imprecise people are when they point and look (docs/design.md §3.3), as random draws.

- Pointing: the arm's direction misses the shoulder-to-target ray by an angle whose mean is
  `pointing_error_deg` (Breuer et al. 2010 measured 7.3 degrees from the forearm). Drawn per
  gesture as an isotropic 2-D normal error of the direction, so its size follows a Rayleigh law
  with that mean.
- Gaze: the head makes only part of a gaze shift, the eyes the rest (Stiefelhagen and Zhu 2002:
  68.9 % from the head); the fraction is drawn per person, so the face's direction misses the
  target by a person-specific margin.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.literature import (
    BREUER_POINTING_ERROR_DEG,
    HEAD_FRACTION_SD,
    STIEFELHAGEN_HEAD_FRACTION,
)


@dataclasses.dataclass(frozen=True)
class Imprecision:
    """pointing_error_deg: mean angle (deg) between the pointing arm and the shoulder-to-target
    ray, >= 0 (0: exact). head_turn_fraction: mean share of a gaze shift the head makes, in
    (0, 1]. head_turn_fraction_sd: its spread between people, >= 0."""

    pointing_error_deg: float = BREUER_POINTING_ERROR_DEG
    head_turn_fraction: float = STIEFELHAGEN_HEAD_FRACTION
    head_turn_fraction_sd: float = HEAD_FRACTION_SD


def draw_head_fraction(rng: np.random.Generator, imprecision: Imprecision) -> float:
    """One person's share of gaze shifts made by the head, kept within [0.3, 1]."""
    fraction = rng.normal(imprecision.head_turn_fraction, imprecision.head_turn_fraction_sd)
    return float(np.clip(fraction, 0.3, 1.0))


def pointing_sigma_deg(mean_deg: float) -> float:
    """The per-axis sd (deg) of a pointing error whose size has mean `mean_deg`: the size of an
    isotropic 2-D normal error follows a Rayleigh law, whose mean is sigma * sqrt(pi / 2)."""
    return mean_deg / math.sqrt(math.pi / 2)


def draw_pointing_error(rng: np.random.Generator, mean_deg: float) -> np.ndarray:
    """The angular error (rad) of one gesture about two axes perpendicular to the pointing
    direction: normal with `pointing_sigma_deg`, so that its size has mean `mean_deg`."""
    return rng.normal(0.0, math.radians(pointing_sigma_deg(mean_deg)), 2)


def perturb_direction(direction: np.ndarray, error: np.ndarray) -> np.ndarray:
    """`direction` turned by the 2-D angular `error` (rad): first about the horizontal axis
    across it (up/down), then about the vertical (left/right). Keeps its length."""
    direction = np.asarray(direction, dtype=float)
    length = float(np.linalg.norm(direction))
    yaw = math.atan2(direction[1], direction[0]) + error[1]
    pitch = math.asin(float(np.clip(direction[2] / length, -1.0, 1.0))) + error[0]
    return length * np.array(
        [math.cos(pitch) * math.cos(yaw), math.cos(pitch) * math.sin(yaw), math.sin(pitch)]
    )
