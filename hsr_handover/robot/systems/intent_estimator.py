"""IntentEstimator: which object the person asks for, from the robot's skeleton and detections."""

from __future__ import annotations

import math

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, LeafSystem, State

from hsr_handover.robot.intent import IntentParams, IntentState, IntentTracker
from hsr_handover.robot.perception.cross_check import confirmed_candidates
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.systems.watching import declare_watching_input, is_watching
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S


class IntentEstimator(LeafSystem):
    """The pointing-and-gaze recogniser (paper 3.2, eqs. 16-17) on the robot's percepts.

    Inputs: `skeleton` (Skeleton, lifted), `detections` (DetectionResult), and optionally
    `detection_support` (DetectionSupport per detection, from the map cross-check: when
    connected, only confirmed detections are candidates), `image_time` (s, the capture
    time, which times the dwell; unconnected, the update's own time stands in) and `watching`
    (optional: while it is 0 no frame is judged and the intent stays as it was, see
    `watching`).
    Outputs: `intent` (IntentState: the recognised target or None, its confidence and the time
    it was recognised, the current request and the frame's judgement) and `rays` (the frame's
    pointing and gaze Rays, each None when not seen), for the replay.

    It judges one frame every `period` s, `delay` s after each capture: after the scene map has
    learnt the same frame (see `frame_timing`).
    """

    def __init__(
        self,
        period: float,
        params: IntentParams | None = None,
        delay: float = 2 * PROCESSING_DELAY_S,
    ):
        super().__init__()
        if not 0 < delay < period:
            raise ValueError(f"delay: expected 0 < delay < period ({period} s), got {delay}")
        self._params = IntentParams() if params is None else params
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self._support = self.DeclareAbstractInputPort("detection_support", AbstractValue.Make(()))
        self._image_time = self.DeclareAbstractInputPort("image_time", AbstractValue.Make(math.nan))
        self._watching = declare_watching_input(self)
        self._tracker = self.DeclareAbstractState(AbstractValue.Make(IntentTracker(self._params)))
        self.DeclareAbstractOutputPort(
            "intent", lambda: AbstractValue.Make(IntentState()), self._calc_intent
        )
        self.DeclareAbstractOutputPort("rays", lambda: AbstractValue.Make((None, None)), self._rays)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, delay, self._judge)

    def _candidates(self, context: Context) -> list:
        detections = self._detections.Eval(context).detections
        if not self._support.HasValue(context):
            return [(d.label, d.center) for d in detections]
        return confirmed_candidates(detections, self._support.Eval(context))

    def _judge(self, context: Context, state: State) -> None:
        if not is_watching(self._watching, context):
            return
        tracker: IntentTracker = state.get_mutable_abstract_state(self._tracker).get_value()
        time = self._image_time.Eval(context) if self._image_time.HasValue(context) else math.nan
        if not math.isfinite(time):
            time = context.get_time()
        skeleton = self._skeleton.Eval(context)
        candidates = self._candidates(context)
        tracker.update(
            time,
            skeleton.points,
            skeleton.confidence,
            candidates,
            skeleton.torso_forward,
            skeleton.face_forward,
        )

    def _state(self, context: Context) -> IntentState:
        return context.get_abstract_state(self._tracker).get_value().state_

    def _calc_intent(self, context: Context, output: AbstractValue) -> None:
        output.set_value(self._state(context))

    def _rays(self, context: Context, output: AbstractValue) -> None:
        frame = self._state(context).frame
        output.set_value((frame.pointing, frame.gaze))
