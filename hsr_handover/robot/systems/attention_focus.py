"""AttentionFocus: where the robot attends, from its focus schedule and what it perceives."""

from __future__ import annotations

from collections.abc import Sequence

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, LeafSystem

from hsr_handover.robot.perception.attention import FocusChange, attended_regions, focus_at
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton


class AttentionFocus(LeafSystem):
    """Inputs `skeleton` (a Skeleton: lifted keypoints and confidences) and `detections` (a
    DetectionResult). Output `attention`: a tuple of AttentionRegion for the focus in force at
    the context's time (the scenario's script today; the handover supervisor later), located
    in the robot's own percepts. Either input may be left unconnected."""

    def __init__(self, schedule: Sequence[FocusChange]):
        super().__init__()
        self._schedule = tuple(sorted(schedule, key=lambda change: change.start))
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self.DeclareAbstractOutputPort(
            "attention", lambda: AbstractValue.Make(()), self._calc_attention
        )

    def _calc_attention(self, context: Context, output: AbstractValue) -> None:
        focus = focus_at(self._schedule, context.get_time())
        points = confidence = None
        if self._skeleton.HasValue(context):
            skeleton = self._skeleton.Eval(context)
            points, confidence = skeleton.points, skeleton.confidence
        detections = []
        if self._detections.HasValue(context):
            result = self._detections.Eval(context)
            detections = [(d.label, d.center) for d in result.detections]
        output.set_value(attended_regions(focus, points, confidence, detections))
