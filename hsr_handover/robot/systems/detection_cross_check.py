"""DetectionCrossCheck: object detections confirmed (or not) by the scene map."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, LeafSystem

from hsr_handover.robot.perception.cloud_map import GraphSnapshot
from hsr_handover.robot.perception.cross_check import support_of
from hsr_handover.robot.perception.object_detection import DetectionResult


class DetectionCrossCheck(LeafSystem):
    """Inputs `detections` (DetectionResult) and `graph` (GraphSnapshot); output
    `detection_support`: a tuple of DetectionSupport, one per detection, in the same order."""

    def __init__(self):
        super().__init__()
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self._graph = self.DeclareAbstractInputPort(
            "graph", AbstractValue.Make(GraphSnapshot.empty())
        )
        self.DeclareAbstractOutputPort(
            "detection_support", lambda: AbstractValue.Make(()), self._calc_support
        )

    def _calc_support(self, context: Context, output: AbstractValue) -> None:
        result = self._detections.Eval(context)
        pairs = [(detection.label, detection.center) for detection in result.detections]
        output.set_value(support_of(pairs, self._graph.Eval(context)))
