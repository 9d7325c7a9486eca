"""Recognising the object a person asks for (paper 3.2): a straight arm (eq. 16) whose pointing
ray passes within `d_min` of an object, a face (eq. 17) turned toward the same object, and both
held for `t_max` seconds.

The face's direction is read as the robot's model of how people look: the head makes only part
of a gaze shift and the eyes the rest (Stiefelhagen and Zhu 2002: 69 %), so the face's turn
from the torso's forward direction is scaled by `head_gain` to give where the eyes look, and
its pitch from level likewise. The objects on a table lie side by side, so the horizontal
error chooses between them; vertically the eyes need only come down to the object, no more than
`gaze_pitch_tolerance_deg` above it: a person looking ahead over the table, an arm lying on it
toward a cup, is not asking. (Below is not checked: the pointing hand is there, and a face
normal reads low more often than high.) Rays of the last `smoothing_s` seconds are
averaged (the face's by its median heading and elevation), and the face whose pitch is checked
over the longer `pitch_smoothing_s`: the eq. 17 normal from three points a few cm apart swings
10-30 degrees a frame, now and then far more. The
pointing ray counts only while the arm holds still (`steady_deg_s`): a gesture is read in its
hold, not while the arm sweeps past other objects on its way.

Each frame is judged (`judge`); `IntentTracker` adds the dwell. Missing keypoints never make a
guess: a frame that lacks the face is judged with the face seen in the last `smoothing_s`
(OpenPose drops a face point in about a quarter of frames, and a request is not withdrawn by a
blink); with none seen in that window, the frame neither starts nor completes a recognition,
nor breaks a dwell that the arm keeps pointing through.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.intent.judging import (
    ARM_NOT_RAISED,
    ASKS_FOR_TARGET,
    GAZE_ELSEWHERE,
    NO_SKELETON,
    RECOGNISED,
    FrameJudgement,
    Observation,
    judge,
    nothing_to_judge,
    observe,
)
from hsr_handover.robot.intent.params import IntentParams
from hsr_handover.robot.intent.person_rays import gaze_ray, pitch_errors_deg
from hsr_handover.robot.intent.smoothing import RaySmoother
from hsr_handover.robot.intent.wrist_trail import WristTrail
from hsr_handover.robot.perception.facing import SteadyFacing
from hsr_handover.robot.perception.keypoint_filter import KeypointFilter


@dataclasses.dataclass(frozen=True)
class IntentState:
    """The recogniser's state after a frame: the recognised `target` (None until one is) with
    its `confidence` and `recognised_time` (s; NaN until then); the object the person is
    asking for now (`candidate`, since `candidate_since`); the frame's judgement; and, once a
    target is recognised, another object the person asks for afterwards in a new gesture
    (`correction`, at `correction_time`; see `IntentTracker`); and every object seen so far as
    (label, centre) where last seen (`objects`)."""

    target: str | None = None
    confidence: float = 0.0
    recognised_time: float = math.nan
    candidate: str | None = None
    candidate_since: float = math.nan
    frame: FrameJudgement = FrameJudgement(None, 0.0, NO_SKELETON)
    correction: str | None = None
    correction_time: float = math.nan
    objects: tuple[tuple[str, np.ndarray], ...] = ()

    @property
    def status(self) -> str:
        return RECOGNISED if self.target is not None else self.frame.status


@dataclasses.dataclass(frozen=True)
class _CorrectionWatch:
    """After the target is recognised: since when no arm has pointed at an object
    (`free_since`), whether a new gesture may now be read (`armed`), and its dwell
    (`candidate` since `since`)."""

    free_since: float = math.nan
    armed: bool = False
    candidate: str | None = None
    since: float = math.nan


class IntentTracker:
    """The dwell over frames: the first object asked for, with the face confirming it at the
    start and at the end, for `t_max` seconds, is the recognised target (latched).

    After that it watches for a correction: a person who sees the robot fetch the wrong object
    asks again. Once no arm has pointed at an object for `smoothing_s` (the first gesture's
    rays have left the window; a standing person's other arm may hang straight, pointing at
    nothing), a new gesture (its wrist risen to where it points: `WristTrail`) that asks
    for another object than the target, by the same dwell, with the eyes not on a point below
    it, is the `correction` (latched too). The objects are judged where they were last seen."""

    def __init__(self, params: IntentParams | None = None):
        self.params = IntentParams() if params is None else params
        self.state_ = IntentState()
        self._smoother = RaySmoother(
            self.params.smoothing_s, self.params.bent_gap_s, self.params.pitch_smoothing_s
        )
        self._chest = SteadyFacing()
        self._shoulders = SteadyFacing()
        self._correcting = _CorrectionWatch()
        self._objects: dict[str, np.ndarray] = {}  # each candidate where last seen
        self._wrists = WristTrail(self.params.rise_m, self.params.rise_s)
        self._correction_params = dataclasses.replace(
            self.params, gaze_tolerance_deg=self.params.correction_gaze_tolerance_deg
        )
        self._keypoints = KeypointFilter() if self.params.track_keypoints else None

    @classmethod
    def correcting(cls, state: IntentState, params: IntentParams | None = None) -> IntentTracker:
        """A tracker that takes over from one in `state` (its target recognised, its objects
        where last seen) to watch for a correction only."""
        tracker = cls(params)
        tracker.state_ = IntentState(
            state.target, state.confidence, state.recognised_time, objects=state.objects
        )
        tracker._objects = dict(state.objects)
        return tracker

    def __deepcopy__(self, memo: dict) -> IntentTracker:
        """The params and states are frozen and the facings are replaced, never changed in
        place: only the histories need copying."""
        clone = copy.copy(self)
        clone._smoother = copy.deepcopy(self._smoother, memo)
        clone._wrists = copy.deepcopy(self._wrists, memo)
        clone._keypoints = copy.deepcopy(self._keypoints, memo)
        return clone

    def steady_forward(self, observation: Observation, chest: np.ndarray | None) -> Observation:
        """A person at the table turns the head, not the torso: the chest's facing seen most
        often stands for the torso's direction (`perception.chest_plane`; the frames whose arm
        covered the chest are outvoted); until the chest is seen, the shoulders'
        direction seen most often while no arm points. The estimated gaze inherits
        (head_gain - 1) of the torso's error, and the shoulders' lifted points turn only a
        fifth as far as the person (see chest_plane)."""
        self._chest = self._chest.add(chest)
        if observation.pointing is None:
            self._shoulders = self._shoulders.add(observation.forward)
        for facing in (self._chest, self._shoulders):
            forward = facing.direction()
            if forward is not None:
                return dataclasses.replace(observation, forward=forward)
        return observation

    def update(
        self,
        time: float,
        points: np.ndarray,
        confidence: np.ndarray,
        candidates: Sequence[tuple[str, np.ndarray]],
        torso_forward: np.ndarray | None = None,
        face_forward: np.ndarray | None = None,
    ) -> IntentState:
        """Judge the frame captured at `time` (s), its rays smoothed over the recent frames,
        and advance the dwell. `torso_forward` is the chest's facing in this frame and
        `face_forward` the face's direction from the head's shape (the skeleton's; None or NaN
        when not seen). The candidates are every object seen so far,
        where last seen: the objects stay on the table while the robot looks at the person
        (a standing person's face and the table do not fit in the camera's view) or, fetching
        one, at where it carries it."""
        if self._keypoints is not None:
            points, confidence = self._keypoints.update(time, points, confidence)
        self._wrists.add(time, points, confidence)
        self._objects = self._objects | {label: center for label, center in candidates}
        candidates = list(self._objects.items())
        frame = nothing_to_judge(confidence, candidates)
        observed = None
        if frame is None:
            centers = np.array([center for _, center in candidates], dtype=float)
            seen = self.steady_forward(
                observe(points, confidence, centers, self.params, face_forward), torso_forward
            )
            observed = self._smoother.smooth(time, seen)
            frame = judge(observed, candidates, self.params)
        state = dataclasses.replace(self.state_, objects=tuple(self._objects.items()))
        if state.target is not None:
            self.state_ = self._correction(
                dataclasses.replace(state, frame=frame), time, observed, candidates
            )
            return self.state_
        frame = self._raised(frame, state.candidate, observed)
        candidate, since = _dwell(state.candidate, state.candidate_since, frame, time)
        target, recognised = None, math.nan
        if self._dwelt(candidate, since, frame, time):
            target, recognised = candidate, time
        self.state_ = IntentState(target, frame.clarity if target else 0.0, recognised, candidate,
                                  since, frame, objects=state.objects)  # fmt: skip
        return self.state_

    def _below(self, observed: Observation, center: np.ndarray) -> bool:
        """Whether the eyes look more than `correction_below_deg` below `center`: at a hand
        held out to receive, not at an object on the table (a held-out arm can pass 26 cm from
        a box, the gaze 16 degrees beside it and 15 below)."""
        face = observed.face_for_pitch or observed.face
        if face is None:
            return False
        level = gaze_ray(face, observed.forward, self.params)
        below = -pitch_errors_deg(level, center[None])[0]
        return below > self.params.correction_below_deg

    def _raised(
        self, frame: FrameJudgement, dwelling: str | None, observed: Observation | None
    ) -> FrameJudgement:
        """`frame`, or nothing asked for in it (ARM_NOT_RAISED) when it would start a dwell on
        another object than `dwelling` with an arm whose wrist has not just risen to where it
        points: a request is a gesture, and a forearm lying on the table toward the camera
        reads straight at a cup while the eyes rest on one."""
        new = frame.candidate is not None and frame.candidate != dwelling
        if new and observed is not None and not self._rose(observed):
            return dataclasses.replace(frame, candidate=None, status=ARM_NOT_RAISED)
        return frame

    def _rose(self, observed: Observation) -> bool:
        """Whether the pointing arm's wrist has just risen to where it is (a new gesture)."""
        if observed.arm is None or observed.pointing is None:
            return False
        return self._wrists.rose(observed.arm, observed.pointing.direction)

    def _dwelt(self, candidate: str | None, since: float, frame: FrameJudgement, time: float):
        """Whether `candidate` has been asked for `t_max` with the face seen now."""
        done = candidate is not None and time - since >= self.params.t_max - 1e-9
        return done and frame.face_seen

    def _correction(
        self,
        state: IntentState,
        time: float,
        observed: Observation | None,
        candidates: Sequence[tuple[str, np.ndarray]],
    ) -> IntentState:
        """`state` with a correction, once a new gesture has asked for another object than the
        target for `t_max`, its wrist risen to where it points when the dwell starts and the
        eyes no more than `correction_below_deg` below the object. The target is judged with
        the others: a person reaching for the object fetched, held up within their reach, is
        not asking for its neighbour (the eyes on it lie within the correction's wide gaze
        tolerance of the object beside it)."""
        watch = self._correcting
        if state.correction is not None:
            return state
        if not watch.armed:
            if observed is not None and observed.at_object:
                watch = _CorrectionWatch()  # the first gesture still points
            elif math.isnan(watch.free_since):
                watch = _CorrectionWatch(free_since=time)
            elif time - watch.free_since >= self.params.smoothing_s:
                watch = _CorrectionWatch(watch.free_since, armed=True)
            self._correcting = watch
            return state
        if observed is None:
            return state
        frame = judge(observed, candidates, self._correction_params)
        asked = None if frame.candidate is None else dict(candidates)[frame.candidate]
        if frame.candidate == state.target:
            frame = dataclasses.replace(frame, candidate=None, status=ASKS_FOR_TARGET)
        elif asked is not None and self._below(observed, asked):
            frame = dataclasses.replace(frame, candidate=None, status=GAZE_ELSEWHERE)
        else:
            frame = self._raised(frame, watch.candidate, observed)
        candidate, since = _dwell(watch.candidate, watch.since, frame, time)
        self._correcting = dataclasses.replace(watch, candidate=candidate, since=since)
        if not self._dwelt(candidate, since, frame, time):
            return state
        return dataclasses.replace(state, correction=candidate, correction_time=time)


def _dwell(
    candidate: str | None, since: float, frame: FrameJudgement, time: float
) -> tuple[str | None, float]:
    """The object asked for and since when, after `frame` at `time`: a new request starts
    only with the face seen; nothing asked for breaks the dwell."""
    if frame.candidate is None or (frame.candidate != candidate and not frame.face_seen):
        return None, math.nan
    if frame.candidate == candidate:
        return candidate, since
    return frame.candidate, time
