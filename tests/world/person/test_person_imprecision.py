"""The simulated person is as imprecise as people are (docs/design.md §3.3), reproducibly per
seed."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.scenario import load_scenario
from hsr_handover.world.person.aiming import pointing_arm_angles
from hsr_handover.world.person.behavior import (
    Action,
    aim_head,
    posture_changes,
    rest_posture,
    target_posture,
)
from hsr_handover.world.person.body import ARM_JOINT_SUFFIXES, PERSON_JOINTS, BodyDimensions
from hsr_handover.world.person.imprecision import perturb_direction
from hsr_handover.world.station.world import person_actions
from tests.paths import SCENARIOS

BODY = BodyDimensions.from_height(1.70, seated=True)


def _pointing_and_looking(seed: int, scenario=None):
    scenario = scenario or load_scenario(SCENARIOS / "point_left.yaml")
    scenario.simulation.seed = seed
    exact = person_actions(_exact(scenario), BODY)
    scenario.simulation.seed = seed
    return person_actions(scenario, BODY), exact


def _exact(scenario):
    exact = copy.deepcopy(scenario)
    exact.person.imprecision.pointing_error_deg = 0.0
    exact.person.imprecision.head_turn_fraction = 1.0
    exact.person.imprecision.head_turn_fraction_sd = 0.0
    return exact


def test_pointing_errors_have_the_literature_mean_and_head_turns_fall_short():
    errors, fractions = [], []
    for seed in range(300):
        actions, exact = _pointing_and_looking(seed)
        point, true = actions[-1], exact[-1]
        shoulder = BODY.shoulder(point.arm)
        errors.append(angle_deg(point.arm_point - shoulder, true.point - shoulder))
        fractions.append(point.head_fraction)
    assert np.mean(errors) == pytest.approx(7.3, abs=0.6)  # Breuer et al. 2010
    assert np.mean(fractions) == pytest.approx(0.689, abs=0.02)  # Stiefelhagen and Zhu 2002
    assert 0.3 <= min(fractions) and max(fractions) <= 1.0


def test_the_same_seed_gives_the_same_person():
    first, _ = _pointing_and_looking(4)
    again, _ = _pointing_and_looking(4)
    other, _ = _pointing_and_looking(5)
    np.testing.assert_array_equal(first[-1].arm_point, again[-1].arm_point)
    assert not np.array_equal(first[-1].arm_point, other[-1].arm_point)


def test_the_head_makes_its_fraction_of_the_turn():
    actions, _ = _pointing_and_looking(2)
    look = actions[0]
    changes = dict(posture_changes(BODY, actions))
    neck = [PERSON_JOINTS.index("neck_yaw"), PERSON_JOINTS.index("neck_pitch")]
    rest = rest_posture(BODY)[neck]
    turned = changes[look.start][neck]
    full = aim_head(BODY, look.point)
    np.testing.assert_allclose(turned - rest, look.head_fraction * (full - rest), atol=1e-12)


def test_the_eyes_stay_on_the_target_while_the_arm_misses_it():
    actions, exact = _pointing_and_looking(3)
    point = actions[-1]
    np.testing.assert_allclose(point.point, exact[-1].point)  # looked at: the object itself
    assert angle_deg(point.arm_point - BODY.shoulder(point.arm), point.point) > 0.1
    posture = target_posture(BODY, point)
    neck = [PERSON_JOINTS.index("neck_yaw"), PERSON_JOINTS.index("neck_pitch")]
    rest = rest_posture(BODY)[neck]
    full = aim_head(BODY, point.point)
    np.testing.assert_allclose(posture[neck] - rest, point.head_fraction * (full - rest))
    arm = [PERSON_JOINTS.index(f"{point.arm[0]}_{s}") for s in ARM_JOINT_SUFFIXES]
    aimed = pointing_arm_angles(point.arm_point - BODY.shoulder(point.arm))
    np.testing.assert_allclose(posture[arm], aimed)


def test_perturbing_keeps_length_and_turns_by_the_error():
    direction = np.array([0.5, -0.3, -0.4])
    turned = perturb_direction(direction, np.radians([3.0, 4.0]))
    assert np.linalg.norm(turned) == pytest.approx(np.linalg.norm(direction))
    assert 4.0 <= angle_deg(turned, direction) <= 7.0


def test_gesturing_never_straightens_the_elbow():
    changes = posture_changes(BODY, [Action("gesture", 0.5, 3.0, None, "left")])
    elbow = PERSON_JOINTS.index("l_elbow")
    beats = [q[elbow] for t, q in changes if 0.5 <= t <= 3.0]
    assert len(beats) >= 4 and max(beats) < -0.9  # bent by more than 50 degrees throughout
    assert changes[-1][0] == 3.0  # back to rest at the end
