"""The HSR's plant and limits for the planning tests (fixtures), and configurations by joint
name (`configuration`, imported by the tests)."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from hsr_handover.hsr import add_hsr
from hsr_handover.planning.timing import JointLimits, joint_limits


@pytest.fixture(scope="module")
def plant() -> MultibodyPlant:
    plant = MultibodyPlant(0.01)
    add_hsr(plant, Parser(plant))
    plant.Finalize()
    return plant


@pytest.fixture(scope="module")
def limits(plant) -> JointLimits:
    return joint_limits(plant)


def configuration(plant: MultibodyPlant, values: dict[str, float]) -> np.ndarray:
    """A vector over the plant's positions: the named joints' values, 0 elsewhere."""
    vector = np.zeros(plant.num_positions())
    for joint, value in values.items():
        vector[plant.GetJointByName(joint).position_start()] = value
    return vector
