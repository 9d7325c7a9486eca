"""Where the simulated person's arm really pointed on a request: the object its line passes
nearest, and how far off the target it was, from the trial's own script and draws (the world's
truth). It says how hard a trial was for any recogniser: a gesture whose arm points nearer a
neighbour can only be read right from the gaze. For scoring only; the robot never sees it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.scenario import Scenario, object_center
from hsr_handover.world.person.body import BodyDimensions
from hsr_handover.world.station.world import person_actions, person_pose


@dataclasses.dataclass(frozen=True)
class ArmAim:
    """`nearest`: the object whose centre lies nearest the pointing arm's line, by the angle
    at the shoulder; `error_deg`: the angle between the arm and the shoulder-to-target line."""

    nearest: str
    error_deg: float


def arm_aim(scenario: Scenario) -> ArmAim | None:
    """The first pointing gesture of the scenario's script as the person makes it (with the
    drawn pointing error), None when the script holds none."""
    body = BodyDimensions.from_height(scenario.person.height, scenario.person.posture == "seated")
    to_person = person_pose(scenario).inverse()
    for action in person_actions(scenario, body):
        if action.kind != "point_at" or action.point is None:
            continue
        shoulder = body.shoulder(action.arm)
        aim = action.point if action.arm_point is None else action.arm_point
        angles = {
            obj.name: angle_deg(aim - shoulder, to_person @ object_center(scenario, obj) - shoulder)
            for obj in scenario.objects
        }
        return ArmAim(
            min(angles, key=angles.get), angle_deg(aim - shoulder, action.point - shoulder)
        )
    return None


def with_arm_aims(rows: list[dict], scenarios: Sequence[Scenario]) -> list[dict]:
    """The trials' rows, each given where its person's arm really pointed: `arm_nearest` and
    `arm_error_deg` (empty and NaN without a pointing gesture)."""
    for row, scenario in zip(rows, scenarios, strict=True):
        aim = arm_aim(scenario)
        row["arm_nearest"] = aim.nearest if aim else ""
        row["arm_error_deg"] = aim.error_deg if aim else math.nan
    return rows
