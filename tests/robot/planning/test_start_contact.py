"""A path from a start already nearer than the bound: only the parts of the HSR and the
obstacles the start touches may stay that near over the path's first stretch; every other pair
keeps the bound (a carry starting inside the held box's second detection would pass it 7 cm
through a neighbouring cup under one allowance for all; the base slid into a pillar licenses
no other part to come near it)."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.geometry import GeometryId

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.planning import solving, trajectory
from hsr_handover.robot.planning.paths import find_path
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planning_scene import NEAR, PlanningScene
from hsr_handover.robot.planning.trajectory import (
    COLLISION_BOUND,
    ESCAPE_SHARE,
    ESCAPE_SLACK,
    StartContact,
    optimize_path,
    start_contact,
)
from hsr_handover.robot.planning.verification import DIP_ALLOWANCE, path_dips
from tests.robot.planning.conftest import slid_until

TOUCHING = -0.02  # m: the start is 2 cm inside the pillar beside it
DENSE = 200


def _pillar(label: str, x: float, y: float, radius: float = 0.05) -> ObjectShape:
    size = np.array([2 * radius, 2 * radius])
    return ObjectShape(label, CYLINDER, np.array([x, y]), size, 0.0, 0.0, 1.2)


@pytest.fixture(scope="module")
def scene() -> PlanningScene:
    """Two pillars: one beside the base at its start, one just ahead on its way forward."""
    pillars = (_pillar("beside", 0.0, 0.4), _pillar("ahead", 0.5, -0.02))
    return PlanningScene(PerceivedScene(None, pillars))


@pytest.fixture(scope="module")
def start(scene) -> np.ndarray:
    """The base moved sideways until it is TOUCHING the pillar beside it."""
    scene.set_positions({})
    return slid_until(scene, scene.positions(), BASE_JOINTS[1], TOUCHING, (0.0, 0.2), "beside")


def _goal(scene, start) -> np.ndarray:
    goal = start.copy()
    goal[scene.index(BASE_JOINTS[0])] = 2.0
    return goal


def _least(scene, path, name: str, until: float = 1.0) -> float:
    times = np.linspace(path.start_time(), path.start_time() + until * (path.end_time() -
                        path.start_time()), DENSE)  # fmt: skip
    return min(scene.clearances_at(path.value(t).ravel()).get(name, np.inf) for t in times)


def test_the_allowance_is_for_the_pairs_touched_and_the_first_stretch():
    base, hand = GeometryId.get_new_id(), GeometryId.get_new_id()
    contact = StartContact({(base, "table"): -0.04})
    assert contact.names == ("table",) and contact.clearance == -0.04
    assert contact.bound((base, "table"), 0.0) == pytest.approx(-0.04 - ESCAPE_SLACK)
    # It rises to the bound over the first stretch: the path must get out, not stay as deep.
    halfway = (-0.04 - ESCAPE_SLACK + COLLISION_BOUND) / 2
    assert contact.bound((base, "table"), ESCAPE_SHARE / 2) == pytest.approx(halfway)
    assert contact.bound((base, "table"), ESCAPE_SHARE) == COLLISION_BOUND
    assert contact.bound((base, "cup"), 0.0) == COLLISION_BOUND
    assert contact.bound((hand, "table"), 0.0) == COLLISION_BOUND
    # 3 cm into the table at the start is within the base's allowance; 1 cm near the cup is
    # not, nor the hand 1 cm into the table.
    assert contact.dip({(base, "table"): -0.03, (base, "cup"): 0.05}, 0.02) < 0
    assert contact.dip({(base, "table"): -0.03}, ESCAPE_SHARE / 2) > 0
    near_cup = {(base, "table"): -0.03, (base, "cup"): 0.01}
    assert contact.dip(near_cup, 0.02) == pytest.approx(COLLISION_BOUND - 0.01)
    hand_in = {(base, "table"): -0.03, (hand, "table"): -0.01}
    assert contact.dip(hand_in, 0.02) == pytest.approx(COLLISION_BOUND + 0.01)
    assert contact.dip({}, 0.1) == -np.inf
    assert StartContact().bound((base, "table"), 0.0) == COLLISION_BOUND


def test_each_pair_touched_keeps_its_own_start_distance():
    """Fingers 5 cm inside the table and the palm 1 cm from it: the palm may not go as deep as
    the fingers started."""
    fingers, palm = GeometryId.get_new_id(), GeometryId.get_new_id()
    contact = StartContact({(fingers, "table"): -0.05, (palm, "table"): 0.01})
    assert contact.clearance == -0.05
    assert contact.bound((fingers, "table"), 0.0) == pytest.approx(-0.05 - ESCAPE_SLACK)
    assert contact.bound((palm, "table"), 0.0) == pytest.approx(0.01 - ESCAPE_SLACK)
    assert contact.dip({(fingers, "table"): -0.05, (palm, "table"): -0.03}, 0.0) > 0


def test_a_start_names_what_it_touches_and_with_which_parts(scene, start):
    contact = start_contact(scene, start)
    assert contact.names == ("beside",)
    assert contact.clearance == pytest.approx(TOUCHING, abs=1e-4)
    assert start_contact(scene, start, ignore=("beside",)) == StartContact()
    inspector = scene.scene_graph.model_inspector()
    bodies = {scene.plant.GetBodyFromFrameId(inspector.GetFrameId(part)).name()
              for part, _ in contact.pairs}  # fmt: skip
    assert bodies == {"base_link"}  # the base slid into it; the arm is clear


def test_the_constraints_see_only_the_pairs_touched_or_all_but_them(scene, start):
    contact = start_contact(scene, start)
    owner = {gid: name for name, ids in scene.geometry.items() for gid in ids}
    everything = set(scene.part_clearances_at(start))
    seen = {}
    for only in (True, False):
        root, context = scene.pairs_context(contact.pairs, only)
        query = scene.plant.get_geometry_query_input_port().Eval(context)
        pairs = query.ComputeSignedDistancePairwiseClosestPoints(NEAR)
        seen[only] = {(p.id_B, owner[p.id_A]) if p.id_A in owner else (p.id_A, owner[p.id_B])
                      for p in pairs}  # fmt: skip
        del root
    assert seen[True] == set(contact.pairs)
    assert seen[False] == everything - set(contact.pairs)


def test_a_start_touching_one_obstacle_never_licenses_another(scene, start):
    goal = _goal(scene, start)
    result = optimize_path(scene, start, goal)
    assert result.ok, result.reason
    assert _least(scene, result.path, "ahead") >= COLLISION_BOUND - DIP_ALLOWANCE
    assert _least(scene, result.path, "beside", ESCAPE_SHARE) >= TOUCHING - ESCAPE_SLACK - 0.012
    # The planner's check between samples holds it to the same bounds.
    path, reason = find_path(scene, start, goal, (), straight=False)
    assert path is not None, reason
    dips = path_dips(scene, path, (), start_contact(scene, start), DENSE)
    assert dips.max() <= DIP_ALLOWANCE


def test_one_allowance_for_every_obstacle_would_cut_through_the_one_ahead(
    scene, start, monkeypatch
):
    """The scene discriminates: granted to both pillars, the start's allowance lets the
    shortest path pass the pillar ahead nearer than any path may that keeps its bound."""
    both = StartContact({(part, name): TOUCHING for part in scene.moving_parts()
                         for name in ("ahead", "beside")})  # fmt: skip
    monkeypatch.setattr(trajectory, "start_contact", lambda *_: both)
    result = optimize_path(scene, start, _goal(scene, start))
    assert result.ok, result.reason
    assert _least(scene, result.path, "ahead") < COLLISION_BOUND - DIP_ALLOWANCE


def test_paths_solve_at_the_paths_effort(scene, start, monkeypatch):
    """A path past the pillar ahead needs more than one of SNOPT's major iterations: at a path
    effort of one, the solve stops at its limit (IK's effort is not what paths use)."""
    monkeypatch.setattr(solving, "PATH_EFFORT", solving.Effort(optimality=0.1, iterations=1))
    monkeypatch.setattr(solving, "IK_EFFORT", solving.Effort(optimality=0.01, iterations=1000))
    result = optimize_path(scene, start, _goal(scene, start))
    assert not result.ok and "kIterationLimit" in result.reason
