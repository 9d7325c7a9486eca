"""A collision-free path between two configurations: the straight line when it is clear,
else an optimised one from each first guess in turn, kept only once it is verified between its
samples (`verification`)."""

from __future__ import annotations

import numpy as np
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.planning.base_route import route_around
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.trajectory import (
    COLLISION_SAMPLES,
    CONTROL_POINTS,
    StartContact,
    Target,
    optimize_path,
    route_guess,
    start_contact,
    straight_guess,
)
from hsr_handover.robot.planning.verification import DIP_ALLOWANCE, VERIFY_PER_SAMPLE, path_dips

MAX_SAMPLES = 4 * COLLISION_SAMPLES
"""A path that dips between its samples is optimised again from itself at twice the samples,
up to this many. (A 22 s carry round the table at 30 samples swept the held cup 16 cm into
the perceived table between two of them.)"""


def find_path(
    scene: PlanningScene,
    q_from: np.ndarray,
    q_to: np.ndarray,
    ignore: tuple[str, ...],
    straight: bool,
    target: Target | None = None,
) -> tuple[BsplineTrajectory | None, str]:
    """From `q_from` to `q_to` (plant positions), touching nothing but `ignore`: a straight
    line when `straight` asks for one and it is clear (of the `target` by its bound), else an
    optimised path from the guesses in turn (`_guesses`); and "ok", or None and why not."""
    if straight:
        line = BsplineTrajectory(BsplineBasis(4, CONTROL_POINTS), straight_guess(q_from, q_to))
        if path_dips(scene, line, ignore, StartContact(), COLLISION_SAMPLES, target).max() <= 0:
            return line, "ok"
    reasons = []
    for name, guess in _guesses(scene, q_from, q_to):
        path, reason = _verified_path(scene, q_from, q_to, guess, ignore, target)
        if path is not None:
            return path, reason
        reasons.append(f"{name}: {reason}")
    return None, "; ".join(reasons)


def _verified_path(scene, q_from, q_to, guess, ignore, target: Target | None):
    """An optimised path from `guess` that comes no more than DIP_ALLOWANCE inside its
    samples' bounds between them too, its samples doubled while it does (up to MAX_SAMPLES);
    (None, why) if none."""
    samples, contact = COLLISION_SAMPLES, start_contact(scene, q_from, ignore)
    while True:
        result = optimize_path(scene, q_from, q_to, guess, ignore, samples, target)
        if not result.ok:
            return None, result.reason
        dips = path_dips(scene, result.path, ignore, contact, VERIFY_PER_SAMPLE * samples,
                         target)  # fmt: skip
        if dips.max() <= DIP_ALLOWANCE:
            return result.path, result.reason
        if samples * 2 > MAX_SAMPLES:
            worst = 100 * dips.max()
            return None, f"dips {worst:.1f} cm inside its bounds between {samples} samples"
        samples *= 2
        guess = np.hstack(result.path.control_points())


def _guesses(scene, q_from, q_to):
    """(name, control points) to start the optimiser from: the straight line and the arm stowed
    while the base drives (round the table if its straight line crosses it). The stowed way
    goes first when the base's line crosses the table: from a line through the table SNOPT
    takes seconds, up to half a minute, to give up."""
    base = [scene.index(joint) for joint in BASE_JOINTS[:2]]
    route = route_around(q_from[base], q_to[base], scene.scene.table)
    line = ("straight", straight_guess(q_from, q_to))
    stowed = ("round", route_guess(scene, q_from, q_to, route))
    return [line, stowed] if len(route) == 2 else [stowed, line]
