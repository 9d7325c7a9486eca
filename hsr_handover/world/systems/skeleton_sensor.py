"""SkeletonSensor and RecordedSkeletonSource: the person's COCO-18 keypoints as a pose detector
reports them (paper 3.2), on the world's side of the station's ports.

The sensor simulates OpenPose on the head camera: it reads where the person's keypoint frames
really are (as a real detector sees the real person) at the camera's capture instants, and
reports 2-D keypoints as a detector would, noisy, with misses and occlusions seen in that
capture's depth image (`robot.perception.skeleton`). The recorded source plays OpenPose detections
back instead. The robot lifts either to 3-D with its own depth image (`SkeletonLifter`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import Context, LeafSystem, State
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS, NUM_KEYPOINTS
from hsr_handover.interface.keypoints import NO_DEPTH_IMAGE, Detection
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.world.sensors.detector_model import DetectorModel, DetectorState, advance
from hsr_handover.world.sensors.pose_detector import detect_keypoints

NO_CAPTURE = "no capture yet"
RECORDING_ENDED = "recording ended"


class SkeletonSensor(LeafSystem):
    """A simulated OpenPose detector on the head camera (paper 3.2).

    Every `period` s from 0 (and at initialisation), the camera's capture instants, it holds
    the person's true COCO-18 keypoints, read from `body_poses` (the plant's body poses
    output). Output `keypoints`: the Detection OpenPose reports for that capture, projected
    with `camera_pose` and occluded by `depth_image` (the camera's held frame of the same
    instant). The same capture gives the same detection whenever it is evaluated.

    The noise is reproducible: a capture draws from `np.random.default_rng([seed, t_us])`,
    t_us being its time in whole microseconds.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        person: ModelInstanceIndex,
        camera: PinholeCamera,
        period: float,
        model: DetectorModel | None = None,
        seed: int = 0,
        objects: Sequence[int] = (),
    ):
        super().__init__()
        if not period > 0:
            raise ValueError(f"period: expected a positive capture period, got {period}")
        self._camera, self._seed = camera, seed
        self._model = DetectorModel() if model is None else model
        self._objects = [int(index) for index in objects]
        frames = [plant.GetFrameByName(f"coco_{name}", person) for name in COCO18_KEYPOINTS]
        self._body_indices = [int(frame.body().index()) for frame in frames]
        self._p_BK = np.array([frame.GetFixedPoseInBodyFrame().translation() for frame in frames])
        self._body_poses = self.DeclareAbstractInputPort(
            "body_poses", AbstractValue.Make([RigidTransform()])
        )
        self._depth = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self._captured = self.DeclareDiscreteState(np.full(3 * NUM_KEYPOINTS + 1, np.nan))
        self._errors = self.DeclareAbstractState(AbstractValue.Make(DetectorState.start()))
        # A detection depends on the held capture and the images, not on the body's live pose:
        # without these tickets Drake recomputes it (and everything lifted from it) every step.
        self.DeclareAbstractOutputPort(
            "keypoints",
            lambda: AbstractValue.Make(Detection.missing(NO_CAPTURE)),
            self._detect,
            prerequisites_of_calc={
                self.discrete_state_ticket(self._captured),
                self.abstract_state_ticket(self._errors),
                self._depth.ticket(),
                self._pose.ticket(),
            },
        )
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, 0.0, self._capture)
        self.DeclareInitializationUnrestrictedUpdateEvent(self._capture)

    def keypoints_in_world(self, context: Context) -> np.ndarray:
        """The person's true COCO-18 keypoints (18, 3) now, from the `body_poses` input."""
        poses: list[RigidTransform] = self._body_poses.Eval(context)
        return np.array(
            [poses[b] @ p_BK for b, p_BK in zip(self._body_indices, self._p_BK, strict=True)]
        )

    def captured(self, context: Context) -> tuple[np.ndarray, float]:
        """The keypoints (18, 3) held from the last capture and its time (NaN before one)."""
        held = context.get_discrete_state(self._captured).get_value()
        return held[:-1].reshape(NUM_KEYPOINTS, 3), float(held[-1])

    def _capture(self, context: Context, state: State) -> None:
        keypoints_W, time = self.keypoints_in_world(context), context.get_time()
        state.get_mutable_discrete_state(self._captured).set_value(
            np.append(keypoints_W.ravel(), time)
        )
        poses: list[RigidTransform] = self._body_poses.Eval(context)
        objects_W = np.array([poses[b].translation() for b in self._objects]).reshape(-1, 3)
        rng = np.random.default_rng([self._seed, round(time * 1e6), 1])
        errors = context.get_abstract_state(self._errors).get_value()
        errors = advance(errors, keypoints_W, objects_W, time, self._model, rng)
        state.get_mutable_abstract_state(self._errors).set_value(errors)

    def _detect(self, context: Context, output: AbstractValue) -> None:
        keypoints_W, time = self.captured(context)
        if math.isnan(time):
            output.set_value(Detection.missing(NO_CAPTURE))
            return
        image: ImageDepth32F = self._depth.Eval(context)
        if image.size() == 0:
            output.set_value(Detection.missing(NO_DEPTH_IMAGE))
            return
        rng = np.random.default_rng([self._seed, round(time * 1e6)])
        X_WC = self._pose.Eval(context).GetAsMatrix4()
        depth = image.data[:, :, 0]
        errors = context.get_abstract_state(self._errors).get_value()
        output.set_value(
            detect_keypoints(keypoints_W, self._camera, X_WC, depth, self._model, rng, errors)
        )


class RecordedSkeletonSource(LeafSystem):
    """Plays recorded 2-D detections back (e.g. `read_openpose_frames`) in place of the
    simulated sensor.

    Frame k of `frames` holds from k / `frame_rate_hz` s until the next; after the last, the
    output `keypoints` is empty with status "recording ended". The recording must come from a
    camera with the robot's camera intrinsics.
    """

    def __init__(self, frames: Sequence[Detection], frame_rate_hz: float):
        super().__init__()
        if not frame_rate_hz > 0:
            raise ValueError(f"frame_rate_hz: expected a positive frame rate, got {frame_rate_hz}")
        self._frames, self._frame_rate = list(frames), frame_rate_hz
        self.DeclareAbstractOutputPort(
            "keypoints",
            lambda: AbstractValue.Make(Detection.missing(RECORDING_ENDED)),
            self._play,
            prerequisites_of_calc={self.time_ticket()},
        )

    def _play(self, context: Context, output: AbstractValue) -> None:
        # The small allowance keeps frame k at exactly k / rate despite rounding in the time.
        index = math.floor(context.get_time() * self._frame_rate + 1e-9)
        inside = 0 <= index < len(self._frames)
        output.set_value(self._frames[index] if inside else Detection.missing(RECORDING_ENDED))
