"""The intent experiment's trials (paper 4.2): each a copy of the user's scenario with the person
varied (`person.variation`), imprecise (`person.imprecision`), and given a new script; targets
cycle evenly over the objects; distractor trials hold no request. A trial is a self-contained
spec, its seed drawn from the experiment's, so the same seed gives the same trials wherever
they run.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.experiments.layouts import generate_layout
from hsr_handover.scenario import ActionConfig, Scenario, VariationConfig, object_center
from hsr_handover.world.station import person_pose

DISTRACTORS = ("gesture", "arm_on_table", "scratch_head", "look_only")
"""Trials with no request: talking with the hands, a straight arm resting toward the table,
a hand raised to scratch the head, looking at an object while the hands rest."""
CENTRE_HALF_WIDTH = 0.1
"""m: an object this near the person's midline (sideways) is in the centre."""
SETTLE_S = 1.0
"""s of simulation after the last scripted action ends, for a late recognition to land."""


LAYOUTS = ("scenario", "generated")
"""Where a trial's layout comes from: the scenario's own (its person varied,
`person.variation`), or a new one drawn for each trial (`layouts.generate_layout`)."""


@dataclasses.dataclass(frozen=True)
class IntentTrial:
    """One trial, self-contained: its index, kind ("request" or one of DISTRACTORS), the object
    asked for ("" on a distractor trial) and its side as the person sees it ("" on a
    distractor trial), the arm used, when the pointing starts, the whole scenario to run (its
    seed included), the layout drawn for it (empty unless generated) and where to write its
    replay and its scenario ("": none)."""

    index: int
    kind: str
    target: str
    arm: str
    pointing_onset: float
    scenario: Scenario
    record_percepts: bool = False
    replay_dir: str = ""
    position: str = ""
    layout: dict = dataclasses.field(default_factory=dict)
    scenario_dir: str = ""


def object_positions(scenario: Scenario) -> dict[str, str]:
    """Each object's side as the seated person sees it: "left", "centre" or "right"."""
    to_person = person_pose(scenario).inverse()
    sides = {}
    for obj in scenario.objects:
        lateral = (to_person @ object_center(scenario, obj))[1]  # +y: the person's left
        if abs(lateral) < CENTRE_HALF_WIDTH:
            sides[obj.name] = "centre"
        else:
            sides[obj.name] = "left" if lateral > 0 else "right"
    return sides


def make_trials(
    base: Scenario, trials: int, distractors: int, seed: int, layouts: str = "scenario"
) -> list[IntentTrial]:
    """`trials` requests with targets cycling over the objects, then `distractors` trials with no
    request, each with its own seed and person (and with `layouts` "generated", its own
    layout) drawn from `seed`."""
    rng = np.random.default_rng(seed)
    kinds = ["request"] * trials + [DISTRACTORS[i % len(DISTRACTORS)] for i in range(distractors)]
    return [_make_trial(base, index, kind, rng, layouts) for index, kind in enumerate(kinds)]


def trial_layout(
    base: Scenario, rng: np.random.Generator, layouts: str
) -> tuple[Scenario, Request, dict]:
    """One trial's scenario with its own seed, the person's request drawn, and the layout drawn
    (empty unless `layouts` is "generated"; else the scenario's person is varied)."""
    if layouts not in LAYOUTS:
        raise ValueError(f"layouts: expected one of {LAYOUTS}, got {layouts!r}")
    if layouts == "generated":
        seed = int(rng.integers(0, 2**32 - 1))
        scenario, drawn = generate_layout(base, rng)
        scenario.simulation.seed = seed
        return scenario, draw_request(scenario.person.variation, rng), drawn
    scenario = copy.deepcopy(base)
    return scenario, vary_person(scenario, rng), {}


def _uniform(rng: np.random.Generator, span: Sequence[float]) -> float:
    return float(rng.uniform(span[0], span[1]))


@dataclasses.dataclass(frozen=True)
class Request:
    """How one trial's person asks: with which `arm`, when the look starts (`onset`, s), how
    long it leads the pointing (`lead`, s) and how long the arm points (`duration`, s)."""

    arm: str
    onset: float
    lead: float
    duration: float

    @property
    def pointing_onset(self) -> float:
        return self.onset + self.lead


def vary_person(scenario: Scenario, rng: np.random.Generator) -> Request:
    """Draw a new seed and person for one trial (in place, within `person.variation`) and how
    they will ask."""
    variation, person = scenario.person.variation, scenario.person
    scenario.simulation.seed = int(rng.integers(0, 2**32 - 1))
    person.height = float(np.clip(rng.normal(person.height, variation.height_sd), 1.45, 2.0))
    person.position = [float(v) for v in rng.normal(person.position, variation.position_sd)]
    person.yaw = float(person.yaw + math.radians(rng.normal(0.0, variation.yaw_sd_deg)))
    return draw_request(variation, rng)


def draw_request(variation: VariationConfig, rng: np.random.Generator) -> Request:
    """How the person will ask: the arm and the request's timing, within `variation`."""
    arm = "left" if rng.random() < variation.left_arm_probability else "right"
    onset = _uniform(rng, variation.onset_s)
    lead = _uniform(rng, variation.look_lead_s)
    return Request(arm, onset, lead, _uniform(rng, variation.point_duration_s))


def _make_trial(base: Scenario, index: int, kind: str, rng, layouts: str) -> IntentTrial:
    scenario, request, drawn = trial_layout(base, rng, layouts)
    names = [obj.name for obj in scenario.objects]
    target = names[index % len(names)] if kind == "request" else ""
    look_target = str(rng.choice(names))
    scenario.person.behavior = script(scenario, kind, target or look_target, request)
    scenario.simulation.duration = request.pointing_onset + request.duration + SETTLE_S
    scenario.perception.enabled = True
    scenario.handover.enabled = False  # the robot watches; it does not act
    scenario.perception.attention = []
    scenario.camera.render_label = False  # ground truth nobody scores here
    # The side as the person was placed, before this trial's variation of them.
    placed = base if layouts == "scenario" else scenario
    position = object_positions(placed)[target] if target else ""
    return IntentTrial(index, kind, target, request.arm, request.pointing_onset, scenario,
                       position=position, layout=drawn)  # fmt: skip


def script(scenario: Scenario, kind: str, target: str, request: Request) -> list[ActionConfig]:
    """The person's behaviour for one trial: look at `target` from the request's onset, point
    at it `lead` later for `duration` (a "request"), or one of the DISTRACTORS for as long."""
    arm, onset, lead, duration = request.arm, request.onset, request.lead, request.duration
    look = ActionConfig("look_at", onset, target=target)
    if kind == "request":
        point = ActionConfig("point_at", onset + lead, duration, target=target, arm=arm)
        return [look, point]
    if kind == "look_only":
        return [ActionConfig("look_at", onset, lead + duration, target=target)]
    if kind == "gesture":
        return [ActionConfig("gesture", onset, lead + duration, arm=arm)]
    where = _table_rest_point if kind == "arm_on_table" else _head_side
    reach = where(scenario, arm)
    return [ActionConfig("touch", onset, lead + duration, point=list(reach), arm=arm)]


def _table_rest_point(scenario: Scenario, arm: str) -> np.ndarray:
    """On the table top, 5 cm inside its edge, nearest the arm's shoulder: where an arm laid
    straight on the table rests."""
    body = scenario.person.body()
    shoulder = person_pose(scenario) @ body.shoulder(arm)
    table = scenario.table
    c, s = math.cos(table.yaw), math.sin(table.yaw)
    local = np.array([[c, s], [-s, c]]) @ (shoulder[:2] - np.asarray(table.center))
    half = np.asarray(table.size) / 2 - 0.05
    inside = np.clip(local, -half, half)
    xy = np.asarray(table.center) + np.array([[c, -s], [s, c]]) @ inside
    return np.array([*xy, table.height + 0.03])


def _head_side(scenario: Scenario, arm: str) -> np.ndarray:
    """Beside the head on the arm's side: where a hand goes to scratch it."""
    body = scenario.person.body()
    sign = 1.0 if arm == "left" else -1.0
    beside = body.head_center() + np.array([0.0, sign * (body.head_radius + 0.04), 0.0])
    return person_pose(scenario) @ beside
