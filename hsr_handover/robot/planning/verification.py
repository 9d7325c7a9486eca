"""Whether a path keeps clear: its clearance, and how far it dips inside its bounds, checked
densely between the optimiser's samples (docs/design.md §6: the samples alone let a path cut
corners between them)."""

from __future__ import annotations

import math

import numpy as np

from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    COLLISION_SAMPLES,
    StartContact,
    Target,
)
from hsr_handover.robot.planning.upright import SLACK, path_keeps_upright

CHECK_STEP = 0.01  # s between clearance checks of a timed trajectory
VERIFY_PER_SAMPLE = 4  # an optimised path is checked at this many times its optimiser's samples
DIP_ALLOWANCE = COLLISION_BOUND - 0.01
"""m a path may come nearer between its samples than at them: 1 cm clear where the
optimiser kept COLLISION_BOUND."""


def path_clearances(
    scene: PlanningScene, path, ignore: tuple[str, ...], samples: int
) -> np.ndarray:
    """The clearance (m) at `samples` evenly spaced times along a path or trajectory with
    `value(t)` and `start_time()`, `end_time()`."""
    times = np.linspace(path.start_time(), path.end_time(), samples)
    return np.array([scene.clearance_at(path.value(t).ravel(), ignore) for t in times])


def path_dips(
    scene: PlanningScene,
    path,
    ignore: tuple[str, ...],
    contact: StartContact,
    samples: int,
    target: Target | None = None,
) -> np.ndarray:
    """How far (m) a path (`value(t)`, `start_time()`, `end_time()`) from a start touching
    `contact` comes inside its bounds (StartContact.bound, by part and obstacle; the `target`'s own,
    though it is one of `ignore`) at `samples` evenly spaced times; negative where it keeps
    clear of them all."""
    spots = np.linspace(0.0, 1.0, samples)
    return np.array([_dip(scene, path, ignore, contact, spot, target) for spot in spots])


def verified(scene: PlanningScene, path, ignore: tuple[str, ...], contact: StartContact) -> bool:
    """Whether a path that no optimiser made (a way taken as it came, the stowed way) is as
    clear as an optimised one must be: no more than DIP_ALLOWANCE inside its bounds and the
    object held up (`upright.SLACK`) at VERIFY_PER_SAMPLE times the optimiser's samples."""
    samples = VERIFY_PER_SAMPLE * COLLISION_SAMPLES
    dips = path_dips(scene, path, ignore, contact, samples)
    return dips.max() <= DIP_ALLOWANCE and path_keeps_upright(scene, path, samples, SLACK)


def keeps_bounds(
    scene: PlanningScene,
    path,
    ignore: tuple[str, ...],
    contact: StartContact,
    samples: int,
    target: Target | None = None,
) -> bool:
    """Whether `path_dips` would find the path inside no bound at `samples` evenly spaced
    times, checked coarse to fine (every 16th sample, then every 4th, then the rest) and given
    up at the first sample inside: a path that is not clear is mostly not clear over long
    stretches, and a check costs about a millisecond."""
    spots = np.linspace(0.0, 1.0, samples)
    order = dict.fromkeys([*range(0, samples, 16), *range(0, samples, 4), *range(samples)])
    return all(_dip(scene, path, ignore, contact, spots[i], target) <= 0 for i in order)


def _dip(scene, path, ignore, contact: StartContact, spot: float, target: Target | None):
    """How far (m) the path comes inside its bounds at `spot` (0 to 1) along it."""
    name = "" if target is None else target.name
    seen = tuple(other for other in ignore if other != name)
    t = path.start_time() + spot * (path.end_time() - path.start_time())
    # Every bound is at most COLLISION_BOUND: an obstacle farther than that dips nowhere.
    clearances = scene.part_clearances_at(path.value(t).ravel(), seen, within=COLLISION_BOUND)
    to_target = min((d for (_, obstacle), d in clearances.items() if obstacle == name),
                    default=math.inf)  # fmt: skip
    others = {pair: d for pair, d in clearances.items() if pair[1] != name}
    dip = contact.dip(others, spot)
    return dip if target is None else max(dip, target.bound - to_target)


def timed_clearance(scene: PlanningScene, motion: Motion, step: float = CHECK_STEP) -> float:
    """The least clearance (m) of a timed motion checked every `step` s (docs/design.md §6: the
    optimiser's samples alone let the path dip between them)."""
    _, positions = motion.sample(step)
    return min(scene.clearance_at(q, motion.ignore) for q in positions)
