"""When a solve counts as solved: SNOPT proves optimality, or stops short of it (info 41, "the
current point cannot be improved", which the path-length cost's kink provokes) at a point that
satisfies every constraint. A planner needs a feasible answer, not a certificate."""

from __future__ import annotations

from pydrake.solvers import MathematicalProgram, MathematicalProgramResult

FEASIBILITY_TOLERANCE = 1e-4  # of each constraint's bounds (m, rad, or the constraint's own units)


def solved(prog: MathematicalProgram, result: MathematicalProgramResult) -> bool:
    """Whether the result can be used: optimal, or feasible within FEASIBILITY_TOLERANCE.
    Evaluate inside the same collision-filter block as the solve."""
    if result.is_success():
        return True
    return not result.GetInfeasibleConstraintNames(prog, FEASIBILITY_TOLERANCE)
