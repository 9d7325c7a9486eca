"""A collision-free path between two configurations: the straight line when it is clear,
else an optimised one from each first guess in turn, kept only once it is verified between its
samples (`verification`). A carry first tries the stowed way, shortened (`stowed_way`), which
needs no optimiser. When every first guess fails, `search_path` falls back: a solve that
stopped short of a verdict (SNOPT's iteration limit, its numerical trouble) goes on from where
it stopped, then the base drives first, the arm moves first, or the arm rises over the way; a
path that fails them all says whether SNOPT found every guess infeasible or stopped short."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np
from pydrake.math import BsplineBasis
from pydrake.trajectories import BsplineTrajectory

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.planning.base_route import route_around
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.solving import INFEASIBLE_CODE, verdict
from hsr_handover.robot.planning.stopwatch import Stopwatch
from hsr_handover.robot.planning.stowed_way import stowed_way
from hsr_handover.robot.planning.trajectory import (
    COLLISION_SAMPLES,
    CONTROL_POINTS,
    StartContact,
    Target,
    optimize_path,
    route_guess,
    start_contact,
    straight_guess,
    through,
)
from hsr_handover.robot.planning.upright import SLACK, path_keeps_upright
from hsr_handover.robot.planning.verification import (
    DIP_ALLOWANCE,
    VERIFY_PER_SAMPLE,
    keeps_bounds,
    path_dips,
)

RETRY = "retry"  # the Stopwatch stage of the fallbacks
RAISE_M = 0.2  # m the arm lift rises over the way for the "raised" fallback
LINE_STEP = 0.01  # m or rad: the most any joint moves between two checks of a straight line
STOWED_WAY = "stowed way"  # the path search's name for the shortened stowed way
MAX_SAMPLES = 4 * COLLISION_SAMPLES
"""A path that dips between its samples is optimised again from itself at twice the samples,
up to this many. (A 22 s carry round the table at 30 samples swept the held cup 16 cm into
the perceived table between two of them.)"""


@dataclasses.dataclass(frozen=True, kw_only=True)
class PathSearch(Outcome):
    """`ok` with the `path` found by the guess named `found_by`, `retried` when a fallback
    found it; or not, the `reason` led by `solving.verdict`: infeasible or solver trouble."""

    path: BsplineTrajectory | None = None
    found_by: str = ""
    retried: bool = False


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
    path, reason, _, _ = _first_tries(scene, q_from, q_to, ignore, straight, target)
    return path, reason


def search_path(
    scene: PlanningScene,
    q_from: np.ndarray,
    q_to: np.ndarray,
    ignore: tuple[str, ...],
    straight: bool,
    watch: Stopwatch,
    target: Target | None = None,
    first: Sequence[tuple[str, np.ndarray]] = (),
    stowed_first: bool = False,
) -> PathSearch:
    """`find_path` from the guesses `first` (name, control points; a previous plan's way)
    and then its own, after the shortened stowed way when `stowed_first` asks for it (a
    carry's), timed as "optimisation" on `watch`; failing those, the fallbacks
    (`_fallbacks`), timed as RETRY. Not ok: the reason says "infeasible" when SNOPT found every
    guess infeasible, else "solver trouble", and what each guess came to."""
    with watch.stage("optimisation"):
        path, reason, found_by, stopped = _first_tries(scene, q_from, q_to, ignore, straight,
                                                      target, first, stowed_first)  # fmt: skip
    if path is not None:
        return PathSearch(ok=True, reason=reason, path=path, found_by=found_by)
    reasons = [reason]
    with watch.stage(RETRY):
        for name, guess in _fallbacks(scene, q_from, q_to, stopped):
            path, why, _ = _verified_path(scene, q_from, q_to, guess, ignore, target)
            if path is not None:
                return PathSearch(ok=True, reason=why, path=path, found_by=name, retried=True)
            reasons.append(f"{name}: {why}")
    joined = "; ".join(reasons)
    return PathSearch(ok=False, reason=f"{verdict(joined)}: {joined}")


def _first_tries(scene, q_from, q_to, ignore, straight, target, first=(), stowed_first=False):
    """(path or None, reason, the name of the guess that found it, the last points of the
    first solve that stopped short of a verdict or None)."""
    line = BsplineTrajectory(BsplineBasis(4, CONTROL_POINTS), straight_guess(q_from, q_to))
    if straight:
        dips = path_dips(scene, line, ignore, StartContact(), COLLISION_SAMPLES, target)
        if dips.max() <= 0 and path_keeps_upright(scene, line, COLLISION_SAMPLES):
            return line, "ok", "line", None
    elif _line_clear(scene, line, q_from, q_to, ignore, target):
        return line, "ok", "line", None
    reasons, stopped = [], None
    if stowed_first:
        path, reason = stowed_way(scene, q_from, q_to, ignore)
        if path is not None:
            return path, reason, STOWED_WAY, None
        reasons.append(f"{STOWED_WAY}: {reason}")
    for name, guess in [*first, *_guesses(scene, q_from, q_to)]:
        path, reason, last = _verified_path(scene, q_from, q_to, guess, ignore, target)
        if path is not None:
            return path, reason, name, None
        reasons.append(f"{name}: {reason}")
        if stopped is None and last is not None and INFEASIBLE_CODE not in reason:
            stopped = last
    return None, "; ".join(reasons), "", stopped


def _line_clear(scene, line, q_from, q_to, ignore, target) -> bool:
    """Whether the straight line keeps every bound (the start's contact allowed, as for any
    path) at samples no joint moves more than LINE_STEP apart (a rad taken as a metre of arm):
    then no optimiser is needed, and the line is as short as a path in joint space gets. A
    posture's raise or a retreat's fold is mostly such a line; optimised from it, each took
    0.2-0.4 s to come back to about where it started."""
    span = float(np.abs(q_to - q_from).max())
    samples = max(VERIFY_PER_SAMPLE * COLLISION_SAMPLES, int(np.ceil(span / LINE_STEP)) + 1)
    contact = start_contact(scene, q_from, ignore)
    clear = keeps_bounds(scene, line, ignore, contact, samples, target)
    return clear and path_keeps_upright(scene, line, samples)


def _fallbacks(scene: PlanningScene, q_from: np.ndarray, q_to: np.ndarray, stopped):
    """(name, control points) to try once the first guesses failed: on from where a solve
    stopped short ("continued"), the base driving first with the arm as it starts ("base
    first"), the arm moving first with the base where it starts ("arm first"), and the arm
    raised RAISE_M over the way ("raised")."""
    if stopped is not None:
        yield "continued", stopped
    base = [scene.index(joint) for joint in BASE_JOINTS]
    if not np.allclose(q_from[base], q_to[base]):  # else both are the straight line
        driven, turned = q_from.copy(), q_to.copy()
        driven[base], turned[base] = q_to[base], q_from[base]
        yield "base first", through([q_from, driven, q_to])
        yield "arm first", through([q_from, turned, q_to])
    lift = scene.index("arm_lift_joint")
    top = scene.plant.GetPositionUpperLimits()[lift]
    raised_from, raised_to = q_from.copy(), q_to.copy()
    for q in (raised_from, raised_to):
        q[lift] = min(top, max(q_from[lift], q_to[lift]) + RAISE_M)
    yield "raised", through([q_from, raised_from, raised_to, q_to])


def _verified_path(scene, q_from, q_to, guess, ignore, target: Target | None):
    """An optimised path from `guess` that comes no more than DIP_ALLOWANCE inside its
    samples' bounds between them too, its samples doubled while it does (up to MAX_SAMPLES);
    (path, "ok", None), or (None, why, the solver's last control points or None)."""
    samples, contact = COLLISION_SAMPLES, start_contact(scene, q_from, ignore)
    while True:
        result = optimize_path(scene, q_from, q_to, guess, ignore, samples, target)
        if not result.ok:
            return None, result.reason, result.last
        verify = VERIFY_PER_SAMPLE * samples
        dips = path_dips(scene, result.path, ignore, contact, verify, target)
        kept_up = path_keeps_upright(scene, result.path, verify, SLACK)
        if dips.max() <= DIP_ALLOWANCE and kept_up:
            return result.path, result.reason, None
        guess = np.hstack(result.path.control_points())
        if samples * 2 > MAX_SAMPLES:
            worst = 100 * dips.max()
            dipped = dips.max() > DIP_ALLOWANCE
            why = f"dips {worst:.1f} cm inside its bounds" if dipped else "tilts the object held"
            return None, f"{why} between {samples} samples", guess
        samples *= 2


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
