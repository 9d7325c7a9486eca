"""The HSR's plant and limits for the planning tests (fixtures), configurations by joint name
(`configuration`), the base slid until it is a given distance from an obstacle
(`slid_until`) and a cup standing between the hand's pads (`cup_in_hand`), imported by the
tests."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pytest
import scipy.optimize

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

    from hsr_handover.robot.planning.timing import JointLimits

# Drake is imported by the fixtures that need it: the Drake-free tests in this folder
# (tests/test_unit_without_drake.py) load this file too.


@pytest.fixture(scope="module")
def plant() -> MultibodyPlant:
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    from hsr_handover.hsr import add_hsr

    plant = MultibodyPlant(0.01)
    add_hsr(plant, Parser(plant))
    plant.Finalize()
    return plant


@pytest.fixture(scope="module")
def limits(plant) -> JointLimits:
    from hsr_handover.robot.planning.timing import joint_limits

    return joint_limits(plant)


def configuration(plant: MultibodyPlant, values: dict[str, float]) -> np.ndarray:
    """A vector over the plant's positions: the named joints' values, 0 elsewhere."""
    vector = np.zeros(plant.num_positions())
    for joint, value in values.items():
        vector[plant.GetJointByName(joint).position_start()] = value
    return vector


def slid_until(
    scene, q: np.ndarray, joint: str, clearance: float, bracket: tuple[float, float],
    obstacle: str | None = None,
) -> np.ndarray:  # fmt: skip
    """`q` (plant positions of the PlanningScene `scene`) with the base `joint` moved within
    `bracket` (m) until the HSR is `clearance` (m, negative inside) from `obstacle`, or from
    the nearest obstacle when None."""
    q = q.copy()
    i = scene.index(joint)

    def off(value: float) -> float:
        q[i] = value
        if obstacle is None:
            return scene.clearance_at(q) - clearance
        return scene.clearances_at(q)[obstacle] - clearance

    q[i] = scipy.optimize.brentq(off, *bracket, xtol=1e-5)
    return q


def cup_in_hand(scene, q: np.ndarray, label: str = "red"):
    """The cup (a 7 cm cylinder 10 cm high) as it stands between the pads of the hand of the
    PlanningScene `scene` at `q`."""
    from hsr_handover.hsr import PALM_FRAME
    from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape

    scene.plant.SetPositions(scene.plant_context, q)
    palm = scene.plant.GetFrameByName(PALM_FRAME, scene.robot).CalcPoseInWorld(scene.plant_context)
    pads = palm.translation() + 0.03 * palm.rotation().matrix()[:, 2]
    return ObjectShape(label, CYLINDER, pads[:2], np.array([0.07, 0.07]), 0.0, pads[2] - 0.05,
                       0.10)  # fmt: skip
