"""Generated layouts (`--layouts generated`): a new table, objects, person and robot placement
for every experiment trial, drawn from the scenario's `layouts` ranges (`LayoutsConfig`), so
results are measured on layouts nobody chose or tuned for.

Every layout is one a person could arrange: the table stands before the robot with its near
edge NEAR_EDGE m ahead of the robot's nominal base; the objects stand on it in a row across
it (or staggered, alternately STAGGER m nearer and farther), each its drawn spacing from the
last and EDGE_MARGIN inside the top; the person stands or sits across the table, facing it
within the drawn angle, a seated person on a seat that suits the table (`seat_for_table`; the
trial moves the chair back until their knees clear the table, `seating.sit_clear`); the
robot's base, moved and turned, stays clear of the table.
The same generator and seed give the same layouts wherever they run.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np

from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.scenario import ObjectConfig, Scenario
from hsr_handover.scenario.writing import write_scenario
from hsr_handover.world.person.behavior import OVER_TABLE
from hsr_handover.world.person.body import FOREARM_RADIUS, BodyDimensions

NEAR_EDGE = 0.65
"""m from the robot's nominal base to the table's near edge: the base moved 0.2 m toward it
leaves the tucked hand, 0.36 m ahead of the base's centre at a low table's height, 9 cm clear
(the bundled scenes' 0.55 m is 1 cm short for a base moved so)."""
ROW_IN = 0.25
"""m from the table's near edge to the objects' row: where the robot reaches them from its
side (the bundled scenes' row)."""
STAGGER = 0.06  # m each staggered object stands nearer or farther than the row
EDGE_MARGIN = 0.06  # m an object's centre keeps inside the table's sides
CUP_DIAMETER, CUP_HEIGHT = (0.06, 0.08), (0.09, 0.12)  # m
BOX_SIDE, BOX_HEIGHT = (0.05, 0.07), (0.09, 0.12)  # m
BOX_YAW = 0.5  # rad either way
SEATS = (0.35, 0.80)  # m: a low chair's seat to a bar stool's


def _uniform(rng: np.random.Generator, span) -> float:
    return float(rng.uniform(span[0], span[1]))


def generate_layout(base: Scenario, rng: np.random.Generator) -> tuple[Scenario, dict]:
    """A copy of `base` with a new layout drawn from `base.layouts`, and the drawn parameters
    (a flat dict, for each trial's row)."""
    ranges = base.layouts
    scenario = copy.deepcopy(base)
    table = scenario.table
    depth, width = _uniform(rng, ranges.table_depth), _uniform(rng, ranges.table_width)
    table.size, table.yaw = [depth, width], 0.0
    table.height = _uniform(rng, ranges.table_height)
    table.center = [NEAR_EDGE + depth / 2.0, 0.0]
    staggered = bool(rng.random() < ranges.staggered_probability)
    scenario.objects, spacing = _objects(rng, ranges, table.center, width, staggered)

    person = scenario.person
    person.posture = "standing" if rng.random() < ranges.standing_probability else "seated"
    person.height = _uniform(rng, ranges.person_height)
    seated = person.posture == "seated"
    if seated:
        person.seat_height = seat_for_table(person.height, table.height)
    back, along = _uniform(rng, ranges.person_back), _uniform(rng, ranges.person_along)
    facing = _uniform(rng, ranges.facing_deg)
    person.position = [NEAR_EDGE + depth + back, along]
    person.yaw = math.pi + math.radians(facing)

    dx, dy = (_uniform(rng, ranges.base_offset) for _ in range(2))
    yaw = _uniform(rng, ranges.base_yaw)
    scenario.robot.base_pose = [dx, dy, yaw]
    drawn = {
        "posture": person.posture, "person_height_m": person.height, "person_back_m": back,
        "person_along_m": along, "facing_deg": facing, "table_height_m": table.height,
        "table_depth_m": depth, "table_width_m": width, "objects": len(scenario.objects),
        "arrangement": "staggered" if staggered else "row", "spacing_m": spacing,
        "base_dx_m": dx, "base_dy_m": dy, "base_yaw_rad": yaw,
        "seat_height_m": person.seat_height if seated else None,
    }  # fmt: skip
    return scenario, drawn


def seat_for_table(height: float, table_height: float) -> float:
    """The seat (m, within SEATS) on which a seated person `height` m tall rests the forearms
    level just over a table `table_height` m high, the elbows clear of its top by the
    forearm's radius and OVER_TABLE: people sit so that a table is at their elbows (a bar
    table comes with bar stools). On a dining chair's 0.45 m at generated tables up to 0.85 m,
    a 1.50-1.65 m person's elbows were 10-20 cm under the top, and the hands, resting raised
    over it, hid the face from the robot."""
    body = BodyDimensions.from_height(height, seated=True, seat_height=0.0)
    # Over the seat, the upper arm hanging: the rest's, bent forward, is about 1 cm higher,
    # so the seat errs low, the safe side.
    elbow = body.shoulder_z - body.upper_arm
    return float(np.clip(table_height + FOREARM_RADIUS + OVER_TABLE - elbow, *SEATS))


def _objects(
    rng: np.random.Generator, ranges, center: list[float], width: float, staggered: bool
) -> tuple[list[ObjectConfig], float]:
    """The objects across the table, and their mean spacing (m): as many as drawn, fewer if
    their spacings do not fit on the table's width (never fewer than the least drawn)."""
    count = int(rng.integers(ranges.object_count[0], ranges.object_count[1] + 1))
    gaps = [_uniform(rng, ranges.object_spacing) for _ in range(count - 1)]
    room = width - 2.0 * EDGE_MARGIN
    while len(gaps) + 1 > ranges.object_count[0] and sum(gaps) > room:
        gaps.pop()
    slack = max(room - sum(gaps), 0.0)
    first = center[1] - sum(gaps) / 2.0 + _uniform(rng, (-slack / 2.0, slack / 2.0))
    ys = first + np.concatenate([[0.0], np.cumsum(gaps)])
    colors = [str(c) for c in rng.permutation(list(OBJECT_COLORS))[: len(ys)]]
    row = NEAR_EDGE + ROW_IN
    objects = []
    for index, (y, color) in enumerate(zip(ys, colors, strict=True)):
        x = row + (STAGGER * (1 if index % 2 else -1) if staggered else 0.0)
        objects.append(_object(rng, color, [float(x), float(y)]))
    return objects, float(np.mean(gaps)) if gaps else 0.0


def _object(rng: np.random.Generator, color: str, position: list[float]) -> ObjectConfig:
    if rng.random() < 0.5:
        size = [_uniform(rng, CUP_DIAMETER), _uniform(rng, CUP_HEIGHT)]
        return ObjectConfig(f"{color}_cup", "cup", size, color, position)
    size = [_uniform(rng, BOX_SIDE), _uniform(rng, BOX_SIDE), _uniform(rng, BOX_HEIGHT)]
    yaw = _uniform(rng, (-BOX_YAW, BOX_YAW))
    return ObjectConfig(f"{color}_box", "box", size, color, position, yaw)


def layout_columns(drawn: dict) -> dict:
    """A generated layout's parameters as a trial row's columns (`layout_<name>`)."""
    return {f"layout_{name}": value for name, value in drawn.items()}


def write_trial_scenario(directory: str, index: int, scenario: Scenario) -> None:
    """Write trial `index`'s scenario as it runs to `directory`/trial_NNN.yaml ("": nothing)."""
    if not directory:
        return
    comment = f"Trial {index} of an experiment, as it ran: `hsr-handover run` replays it alone."
    write_scenario(scenario, Path(directory) / f"trial_{index:03d}.yaml", comment)
