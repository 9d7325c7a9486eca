"""How the planner solves and when a solve counts as solved: SNOPT proves optimality, or stops
short of it (info 41, "the current point cannot be improved", which the path-length cost's kink
provokes) at a point that satisfies every constraint. A planner needs a feasible answer, not a
certificate.

SNOPT's default optimality tolerance (1e-6) spends most of a path's solve polishing a path
that is already feasible and within a few per cent of its final duration: at 1e-2 the planning
benchmark's grasps took 4x less optimisation for timed paths 1 % longer (docs/design.md §6 has
it at the default), and at PATH_EFFORT's 1e-1 its carries took half the time again for paths
3 % longer. Feasibility is not loosened. A long carry round the table could take SNOPT 10 s or
more to converge; after its major iterations limit its point is used if feasible, and the
planner's next guess tried if not. Inverse kinematics keeps IK_EFFORT: a palm goal's solve is
short, and at the paths' looser effort the back off lost most of its goals.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.solvers import (
    MathematicalProgram,
    MathematicalProgramResult,
    SnoptSolver,
    Solve,
    SolverOptions,
)

FEASIBILITY_TOLERANCE = 1e-4  # of each constraint's bounds (m, rad, or the constraint's own units)


@dataclasses.dataclass(frozen=True)
class Effort:
    """How hard SNOPT works at one solve: its "Major optimality tolerance" and its "Major
    iterations limit"."""

    optimality: float
    iterations: int


IK_EFFORT = Effort(optimality=1e-2, iterations=150)
PATH_EFFORT = Effort(optimality=1e-1, iterations=50)


def solve(
    prog: MathematicalProgram, guess: np.ndarray | None = None, effort: Effort | None = None
) -> MathematicalProgramResult:
    """Drake's Solve (SNOPT for the planner's nonlinear programs) at `effort` (IK_EFFORT when
    None)."""
    effort = IK_EFFORT if effort is None else effort
    options, snopt = SolverOptions(), SnoptSolver().solver_id()
    options.SetOption(snopt, "Major optimality tolerance", effort.optimality)
    options.SetOption(snopt, "Major iterations limit", effort.iterations)
    return Solve(prog, guess, options)


def solved(prog: MathematicalProgram, result: MathematicalProgramResult) -> bool:
    """Whether the result can be used: optimal, or feasible within FEASIBILITY_TOLERANCE.
    Evaluate inside the same collision-filter block as the solve."""
    if result.is_success():
        return True
    return not result.GetInfeasibleConstraintNames(prog, FEASIBILITY_TOLERANCE)


INFEASIBLE = "infeasible"  # SNOPT's verdict: no feasible point near where it started
SOLVER_TROUBLE = "solver trouble"  # it stopped short of a verdict: iteration limit, numerics
INFEASIBLE_CODE = "kInfeasibleConstraints"


def verdict(reasons: str) -> str:
    """INFEASIBLE when every failed solve named in `reasons` ("no path (...)", "no IK solution
    (...)", "dips ...", "tilts ...") ended in SNOPT's verdict of infeasibility, a local one
    (from another guess there may be a way), else SOLVER_TROUBLE."""
    failures = ("no path", "no IK solution", "dips", "tilts")
    tried = sum(reasons.count(failure) for failure in failures)
    return INFEASIBLE if tried and reasons.count(INFEASIBLE_CODE) == tried else SOLVER_TROUBLE
