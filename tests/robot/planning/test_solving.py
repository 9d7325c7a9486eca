"""The planner's solve: SNOPT with its tolerance and iteration limit; when a result counts."""

import numpy as np
from pydrake.solvers import MathematicalProgram, SolutionResult

from hsr_handover.robot.planning import solving


def _rosenbrock() -> tuple[MathematicalProgram, np.ndarray]:
    """A nonconvex program SNOPT needs a few dozen major iterations for, with a constraint so
    that it is not sent to an unconstrained solver."""
    prog = MathematicalProgram()
    x = prog.NewContinuousVariables(2, "x")
    prog.AddCost((1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2)
    prog.AddConstraint(x[0] ** 2 + x[1] ** 2 <= 4.0)
    return prog, x


def test_solve_converges_to_the_optimum():
    prog, x = _rosenbrock()
    result = solving.solve(prog, np.array([-1.2, 1.0]))
    assert result.get_solver_id().name() == "SNOPT"
    assert result.is_success()
    np.testing.assert_allclose(result.GetSolution(x), [1.0, 1.0], atol=0.05)


def test_the_iteration_limit_stops_snopt_and_a_feasible_point_still_counts(monkeypatch):
    monkeypatch.setattr(solving, "IK_EFFORT", solving.Effort(1e-2, 2))
    prog, x = _rosenbrock()
    result = solving.solve(prog, np.array([-1.2, 1.0]))
    assert result.get_solution_result() == SolutionResult.kIterationLimit
    assert solving.solved(prog, result)  # inside the disc: feasible, so usable


def test_an_infeasible_point_does_not_count(monkeypatch):
    monkeypatch.setattr(solving, "IK_EFFORT", solving.Effort(1e-2, 1))
    prog, x = _rosenbrock()
    prog.AddLinearConstraint(x[0] + x[1] >= 2.5)
    result = solving.solve(prog, np.array([-1.5, -1.5]))
    assert not result.is_success()
    assert not solving.solved(prog, result)
