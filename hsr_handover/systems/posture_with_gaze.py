"""PostureWithGaze: a robot that only watches holds its posture and turns its head."""

from __future__ import annotations

import numpy as np
from pydrake.systems.framework import BasicVector, Context, LeafSystem

from hsr_handover.hsr import COMMANDED_JOINTS
from hsr_handover.systems.gaze_controller import HEAD_ROWS


class PostureWithGaze(LeafSystem):
    """Input `head_command` ([pan, tilt, pan rate, tilt rate], the GazeController's). Output
    `hsr_desired_state`: `posture` ([q; v] of COMMANDED_JOINTS) with the head's rows taken
    from the input."""

    def __init__(self, posture: np.ndarray):
        super().__init__()
        self._posture = np.array(posture, dtype=float)
        n = len(COMMANDED_JOINTS)
        if self._posture.shape != (2 * n,):
            raise ValueError(f"posture: expected {2 * n} values, got {self._posture.shape}")
        self._rows = [*HEAD_ROWS, *(n + row for row in HEAD_ROWS)]
        self._head = self.DeclareVectorInputPort("head_command", 4)
        self.DeclareVectorOutputPort("hsr_desired_state", 2 * n, self._calc_state)

    def _calc_state(self, context: Context, output: BasicVector) -> None:
        command = self._posture.copy()
        command[self._rows] = self._head.Eval(context)
        output.SetFromVector(command)
