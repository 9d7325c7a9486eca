"""End to end on the staggered layout (a 0.80 m table, a 1.58 m person seated): from its lowest
the robot's camera never saw this person's pointing arm over the objects, and the request went
unrecognised. It now watches from a raised torso, its arm folded down, and
fetches the box and hands it over (about 40 s)."""

from __future__ import annotations

import math

from hsr_handover.experiments.handover.trial import run_handover_trial
from hsr_handover.experiments.handover.trials import make_trials
from hsr_handover.scenario import load_scenario
from tests.paths import SCENARIOS


def test_a_hidden_pointing_arm_is_seen_from_a_raised_torso_and_the_box_handed_over():
    base = load_scenario(SCENARIOS / "layouts" / "staggered_high_four.yaml")
    trial = make_trials(base, 12, 0, seed=1)[9]
    assert trial.target == "yellow_box"
    row = run_handover_trial(trial)
    assert row["watch_lift_m"] > 0.2  # the torso rose by half of that
    assert row["recognised"] == "yellow_box" and row["handed_over"], row
    assert not row["table_contact"] and not row["person_contact"] and not row["knocked"]
    assert math.isnan(row["dropped_s"])
