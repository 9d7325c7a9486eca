"""What an experiment's watch perceives: the scene planned in keeps what the look round saw."""

import dataclasses

import numpy as np

from hsr_handover.experiments.layouts import generate_layout
from hsr_handover.experiments.watch import WATCH_S, watch
from hsr_handover.scenario import load_scenario
from tests.paths import SCENARIOS


def test_an_object_seen_only_in_the_look_round_is_in_the_watched_scene():
    """A generated layout whose purple cup is 39 degrees to the robot's left: seen from the look
    round's left stop, out of the view the head turns back to. The last frame lacks it; the
    scene watched keeps it where it stands (within 2 cm)."""
    base = load_scenario(SCENARIOS / "intent_reference.yaml")
    scenario, _ = generate_layout(base, np.random.default_rng(579362556))
    joints = {**scenario.robot.joints, "head_tilt_joint": -0.1}  # level, as the benchmark looks
    scenario = dataclasses.replace(
        scenario, robot=dataclasses.replace(scenario.robot, joints=joints)
    )
    purple = next(obj for obj in scenario.objects if obj.color == "purple")

    watched = watch(scenario, WATCH_S, look_around=True)

    last_frame = {shape.label for shape in watched.percept("perceived_scene").objects}
    kept = {shape.label: shape for shape in watched.scene.objects}
    assert "purple" not in last_frame
    assert "purple" in kept
    np.testing.assert_allclose(kept["purple"].center[:2], purple.position, atol=0.02)
    assert {obj.color for obj in scenario.objects} <= set(kept)
