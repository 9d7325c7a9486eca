"""The handover experiment's trials (paper 4.3): each a copy of the user's scenario with the person
varied as in the intent experiment (`person.variation`), asking for one object by looking and
pointing (targets cycle evenly over the objects), and then taking it: after a reaction time
drawn per trial, sometimes with the receiving hand held out beforehand somewhere near the usual
place, and on "refusal" trials not at all (the robot must give up gracefully).

A trial is a self-contained spec, its seed drawn from the experiment's, so the same seed gives
the same trials wherever they run.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.experiments.intent.trials import script, trial_layout
from hsr_handover.robot.handover.look_round import LOOK_ROUND_S
from hsr_handover.scenario import ActionConfig, Scenario
from hsr_handover.world.person.body import side_sign
from hsr_handover.world.station import person_pose

TIME_LIMIT_S = 60.0
"""s from the pointing's onset for the whole cycle: recognise, fetch, present, wait up to the
robot's 12 s for a hand and retreat (about 35 s at most), and room for the one correction the
robot heeds: put the wrong object back and fetch the other, 20-25 s more. A handover not done
by then has timed out (HandoverSim's limit is 13 s, from a hand already held out with the
object in reach of a fixed arm)."""
HOLD_OUT = np.array([0.40, 0.0, -0.18])
"""Where a person holds out the receiving hand, from that shoulder (m, person frame: forward,
left, up): the forearm out over the table's edge, the palm below the shoulder."""


@dataclasses.dataclass(frozen=True)
class HandoverTrial:
    """One trial, self-contained: its index, the object asked for, the arm pointing, when the
    pointing starts, whether the person takes the object (`takes`), the reaction time drawn,
    where the hand is held out beforehand (world, m; empty when it is not), the whole
    scenario to run (its seed included) and where to write its replay ("": none)."""

    index: int
    target: str
    arm: str
    pointing_onset: float
    takes: bool
    reaction_s: float
    hold_out: tuple[float, ...]
    scenario: Scenario
    replay_dir: str = ""
    layout: dict = dataclasses.field(default_factory=dict)
    scenario_dir: str = ""


def make_trials(
    base: Scenario, trials: int, refusals: int, seed: int, layouts: str = "scenario"
) -> list[HandoverTrial]:
    """`trials` requests with targets cycling over the objects, then `refusals` more in which
    the person never takes the object, each with its own seed and person (and with `layouts`
    "generated", its own layout) drawn from `seed`."""
    rng = np.random.default_rng(seed)
    return [
        _make_trial(base, index, index < trials, rng, layouts) for index in range(trials + refusals)
    ]


def _make_trial(base: Scenario, index: int, takes: bool, rng, layouts: str) -> HandoverTrial:
    scenario, request, drawn = trial_layout(base, rng, layouts)
    names = [obj.name for obj in scenario.objects]
    target = names[index % len(names)]
    # The person asks once the robot has looked round the table, as it does on arriving:
    # requests made while its head swept past gave 4 wrong objects in 20 trials, against 2 for
    # the same people watched by a still head.
    request = dataclasses.replace(request, onset=request.onset + LOOK_ROUND_S)
    variation, person = scenario.person.variation, scenario.person
    reaction = float(rng.uniform(*variation.reaction_s))
    hold_out: tuple[float, ...] = ()
    if rng.random() < variation.hold_out_probability:
        offset = rng.normal(0.0, variation.hold_out_sd, 3)
        delay = float(rng.uniform(*variation.hold_out_delay_s))
        hold_out = tuple(_hold_out_point(scenario, offset))
    person.behavior = script(scenario, "request", target, request)
    if hold_out:
        start = request.pointing_onset + request.duration + delay
        arm = person.receiving.arm
        person.behavior.append(ActionConfig("reach_to", start, point=list(hold_out), arm=arm))
    person.receiving = dataclasses.replace(person.receiving, takes=takes, reaction_s=reaction)
    scenario.simulation.duration = request.pointing_onset + TIME_LIMIT_S
    scenario.perception.enabled = True
    scenario.handover.enabled = True
    scenario.perception.attention = []
    scenario.camera.render_label = False  # ground truth nobody scores here
    return HandoverTrial(index, target, request.arm, request.pointing_onset, takes, reaction,
                         hold_out, scenario, layout=drawn)  # fmt: skip


def _hold_out_point(scenario: Scenario, offset: np.ndarray) -> np.ndarray:
    """HOLD_OUT from the receiving shoulder, moved by `offset` (person frame), in the world."""
    person = scenario.person
    body = person.body()
    arm = person.receiving.arm
    local = body.shoulder(arm) + HOLD_OUT * [1.0, side_sign(arm), 1.0] + offset
    return person_pose(scenario) @ local
