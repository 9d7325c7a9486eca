"""GazeController: the robot turns its head to find the person and keep them in view
(`perception.active_gaze`)."""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import BasicVector, Context, LeafSystem, State

from hsr_handover.hsr import COMMANDED_JOINTS, HEAD_JOINTS
from hsr_handover.robot.perception.active_gaze import (
    ActiveGaze,
    FieldOfView,
    GazeParams,
    GazeState,
    HeadMove,
)
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton

GAZE_PERIOD_S = 0.1
"""s between the gaze's decisions, at the handover supervisor's instants: both read the same
frame, so the camera renders no frame for the gaze alone (one in three while the robot acts)."""
HEAD_ROWS = [COMMANDED_JOINTS.index(joint) for joint in HEAD_JOINTS]


class GazeController(LeafSystem):
    """Inputs: `skeleton` (Skeleton, lifted), `detections` (DetectionResult), `camera_pose`
    (RigidTransform X_WC of the frame they come from), `hsr_state_measured` ([q; v] of
    COMMANDED_JOINTS) and optionally `attention` (AttentionFocus's regions, fixated first).
    Outputs: `head_command` ([pan, tilt, pan rate, tilt rate]: the move to the gaze's goal,
    evaluated at every step) and `gaze` (GazeState).

    Every GAZE_PERIOD_S it decides where to look from the latest frame (`ActiveGaze`); before
    its first decision it holds `start_head`."""

    def __init__(
        self,
        view: FieldOfView,
        limits: tuple[tuple[float, float], tuple[float, float]],
        start_head: tuple[float, float],
        params: GazeParams | None = None,
    ):
        super().__init__()
        params = GazeParams() if params is None else params
        n = len(COMMANDED_JOINTS)
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "none"))
        )
        self._pose = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self._state = self.DeclareVectorInputPort("hsr_state_measured", 2 * n)
        # Optional: AttentionFocus's regions, fixated first; unconnected, none.
        self._attention = self.DeclareAbstractInputPort("attention", AbstractValue.Make(()))
        start = (float(start_head[0]), float(start_head[1]))
        self._gaze = self.DeclareAbstractState(AbstractValue.Make(ActiveGaze(view, limits, params)))
        self._move = self.DeclareAbstractState(
            AbstractValue.Make(HeadMove(0.0, start, start, params.speed))
        )
        self.DeclareVectorOutputPort(
            "head_command", 4, self._calc_command,
            prerequisites_of_calc={self.abstract_state_ticket(self._move)},
        )  # fmt: skip
        self.DeclareAbstractOutputPort(
            "gaze", lambda: AbstractValue.Make(GazeState()), self._calc_gaze,
            prerequisites_of_calc={self.abstract_state_ticket(self._gaze)},
        )  # fmt: skip
        self.DeclarePeriodicUnrestrictedUpdateEvent(GAZE_PERIOD_S, 0.0, self._decide)

    def _decide(self, context: Context, state: State) -> None:
        gaze: ActiveGaze = state.get_mutable_abstract_state(self._gaze).get_value()
        skeleton = self._skeleton.Eval(context)
        pose = self._pose.Eval(context)
        head = self._state.Eval(context)[HEAD_ROWS]
        detections = [(d.label, d.center) for d in self._detections.Eval(context).detections]
        attended = ()
        if self._attention.HasValue(context):
            attended = [region.center for region in self._attention.Eval(context)]
        decided = gaze.update(
            context.get_time(), pose.rotation().matrix(), pose.translation(),
            (float(head[0]), float(head[1])), skeleton.points, skeleton.confidence, detections,
            attended,
        )  # fmt: skip
        if decided.goal is not None:
            move = context.get_abstract_state(self._move).get_value()
            updated = move.toward(context.get_time(), decided.goal, (head[0], head[1]))
            state.get_mutable_abstract_state(self._move).set_value(updated)

    def _calc_command(self, context: Context, output: BasicVector) -> None:
        move: HeadMove = context.get_abstract_state(self._move).get_value()
        q, v = move.at(context.get_time())
        output.SetFromVector(np.concatenate([q, v]))

    def _calc_gaze(self, context: Context, output: AbstractValue) -> None:
        output.set_value(context.get_abstract_state(self._gaze).get_value().state_)
