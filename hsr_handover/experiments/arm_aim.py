"""Where the simulated person's arm really pointed on a request: the object its line passes
nearest, and how far off the target it was, from the trial's own script and draws (the world's
truth); and the object the arm's and the face's true directions together most likely ask for
under the person model. It says how hard a trial was for any recogniser: a gesture whose arm
points nearer a neighbour can only be read right from the gaze, and one whose arm and face
together point to a neighbour cannot be read right from them at all. For scoring only; the
robot never sees it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.intent.rays import angle_deg
from hsr_handover.scenario import ImprecisionConfig, Scenario, object_center
from hsr_handover.world.person.behavior import aim_head, rest_posture, target_posture
from hsr_handover.world.person.body import PERSON_JOINTS
from hsr_handover.world.person.imprecision import pointing_sigma_deg
from hsr_handover.world.station.world import person_actions, person_pose

NECK_YAW = PERSON_JOINTS.index("neck_yaw")
FACE_READING_SD_DEG = 0.5
"""How exactly the face's turn is taken to be read (deg): the head's shape reads it within
0.5 degrees a frame (docs/perception.md). It keeps the face's likelihood finite for objects
straight ahead, where the head's share of the turn says nothing."""


@dataclasses.dataclass(frozen=True)
class ArmAim:
    """`nearest`: the object whose centre lies nearest the pointing arm's line, by the angle
    at the shoulder; `error_deg`: the angle between the arm and the shoulder-to-target line;
    `most_likely`: the object the arm's line and the face's turn most likely ask for
    (`most_likely_asked`)."""

    nearest: str
    error_deg: float
    most_likely: str


def most_likely_asked(
    arm_deg: np.ndarray, face_yaw: float, object_yaws: np.ndarray, imprecision: ImprecisionConfig
) -> int:
    """The index of the object most likely asked for, given the arm's angle from each object
    (deg, at the shoulder) and the face's yaw and each object's yaw from the head's rest (rad),
    under the person model: the arm misses by an isotropic normal error whose size has mean
    `pointing_error_deg` (density exp(-a^2 / 2 sigma^2), sigma `pointing_sigma_deg`); the
    head turns a share of the gaze shift drawn from N(`head_turn_fraction`,
    `head_turn_fraction_sd`), so the face's yaw toward an object at yaw y is normal about
    share * y with sd share_sd * |y| (and `FACE_READING_SD_DEG`). The most any recogniser that
    reads the arm and the face's turn exactly could do is to choose this object."""
    pointing_sd = max(pointing_sigma_deg(imprecision.pointing_error_deg), 1e-3)
    face_sd = np.hypot(imprecision.head_turn_fraction_sd * np.abs(object_yaws),
                       math.radians(FACE_READING_SD_DEG))  # fmt: skip
    miss = (face_yaw - imprecision.head_turn_fraction * object_yaws) / face_sd
    log_likelihood = -0.5 * (np.asarray(arm_deg) / pointing_sd) ** 2 - 0.5 * miss**2
    return int(np.argmax(log_likelihood - np.log(face_sd)))


def arm_aim(scenario: Scenario) -> ArmAim | None:
    """The first pointing gesture of the scenario's script as the person makes it (with the
    drawn pointing error and head share), None when the script holds none."""
    body = scenario.person.body()
    to_person = person_pose(scenario).inverse()
    rest_yaw = rest_posture(body)[NECK_YAW]
    for action in person_actions(scenario, body):
        if action.kind != "point_at" or action.point is None:
            continue
        shoulder = body.shoulder(action.arm)
        aim = action.point if action.arm_point is None else action.arm_point
        names = [obj.name for obj in scenario.objects]
        centers = [to_person @ object_center(scenario, obj) for obj in scenario.objects]
        arm = np.array([angle_deg(aim - shoulder, center - shoulder) for center in centers])
        yaws = np.array([aim_head(body, center)[0] for center in centers]) - rest_yaw
        face_yaw = target_posture(body, action)[NECK_YAW] - rest_yaw
        likely = most_likely_asked(arm, face_yaw, yaws, scenario.person.imprecision)
        error = angle_deg(aim - shoulder, action.point - shoulder)
        return ArmAim(names[int(np.argmin(arm))], error, names[likely])
    return None


def with_arm_aims(rows: list[dict], scenarios: Sequence[Scenario]) -> list[dict]:
    """The trials' rows, each given where its person's arm really pointed: `arm_nearest` and
    `arm_error_deg`, and what arm and face together most likely asked for (`cues_most_likely`)
    (empty and NaN without a pointing gesture)."""
    for row, scenario in zip(rows, scenarios, strict=True):
        aim = arm_aim(scenario)
        row["arm_nearest"] = aim.nearest if aim else ""
        row["arm_error_deg"] = aim.error_deg if aim else math.nan
        row["cues_most_likely"] = aim.most_likely if aim else ""
    return rows
