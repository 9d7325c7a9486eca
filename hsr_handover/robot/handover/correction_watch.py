"""Watching for a correction while the robot lifts or carries: the person asks for another
object than the one fetched (paper 3.2's intent, read again once the robot acts). The intent
estimator rests once the robot acts (its camera frames cost the most), so the supervisor judges
the frames it reads anyway with a tracker that takes over from the estimator's
(`IntentTracker.correcting`), the objects where last seen."""

from __future__ import annotations

import dataclasses

import numpy as np

from hsr_handover.robot.handover.cycle_types import CycleRecord, Phase
from hsr_handover.robot.intent import IntentParams, IntentState, IntentTracker
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton

WATCHED_PHASES = (Phase.LIFT, Phase.CARRY)  # when a correction is heeded


@dataclasses.dataclass
class CorrectionWatch:
    """Made with the intent estimator's `params`; its tracker starts from the estimator's
    state the first time the cycle lifts."""

    params: IntentParams
    tracker: IntentTracker | None = None

    def update(
        self,
        time: float,
        record: CycleRecord,
        intent: IntentState,
        skeleton: Skeleton,
        detections: DetectionResult,
        held: np.ndarray | None = None,
    ) -> str | None:
        """Another object the person asks for at `time` (s) while the robot lifts or carries
        one (None before it lifts, once it has heeded one, and while none is asked for).
        `held`: where the hand holds the object fetched (m, world; from the robot's own
        joints), which the camera loses as it carries it: a person reaching for it there is
        not asking for what lies behind it."""
        if record.phase not in WATCHED_PHASES or record.first_target is not None:
            return None
        if self.tracker is None:
            self.tracker = IntentTracker.correcting(intent, self.params)
        known = {label for label, _ in self.tracker.state_.objects}
        seen = [(d.label, d.center) for d in detections.detections
                if d.label in known and np.all(np.isfinite(d.center))]  # fmt: skip
        if held is not None and record.target in known:
            seen = [item for item in seen if item[0] != record.target] + [(record.target, held)]
        state = self.tracker.update(
            time,
            skeleton.points,
            skeleton.confidence,
            seen,
            skeleton.torso_forward,
            skeleton.face_forward,
        )
        return state.correction
