"""SkeletonSensor and RecordedSkeletonSource: COCO-18 keypoints of the person (paper 3.2).

The sensor simulates OpenPose on the head camera: it reads where the person's keypoint frames
really are (as a real detector sees the real person) and reports them as a detector would,
noisy, with misses and occlusions (`perception.skeleton`). The replay source reads recorded
OpenPose detections instead. Both lift the 2-D keypoints with the live depth image, so what
follows them cannot tell them apart; only their `skeleton` output is for the robot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.perception.coco18 import COCO18_KEYPOINTS
from hsr_handover.perception.pinhole import PinholeCamera
from hsr_handover.perception.skeleton import (
    STATUS_OK,
    Detection,
    Skeleton,
    SkeletonNoise,
    lift_keypoints,
    simulate_keypoints,
)

NO_DEPTH_IMAGE = "no depth image"
RECORDING_ENDED = "recording ended"


class _SkeletonFromDepth(LeafSystem):
    """Inputs `depth_image` (ImageDepth32F, m) and `camera_pose` (RigidTransform X_WC); output
    `skeleton` (Skeleton), computed by `_calc_from_image` whenever it is evaluated."""

    def __init__(self, camera: PinholeCamera):
        super().__init__()
        self._camera = camera
        self._depth_port = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose_port = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self.DeclareAbstractOutputPort(
            "skeleton",
            lambda: AbstractValue.Make(Skeleton.missing(NO_DEPTH_IMAGE)),
            self._calc_skeleton,
        )

    def _calc_skeleton(self, context: Context, output: AbstractValue) -> None:
        image: ImageDepth32F = self._depth_port.Eval(context)
        if image.size() == 0:
            output.set_value(Skeleton.missing(NO_DEPTH_IMAGE))
            return
        X_WC = self._pose_port.Eval(context).GetAsMatrix4()
        output.set_value(self._calc_from_image(context, image.data[:, :, 0], X_WC))

    def _calc_from_image(self, context: Context, depth: np.ndarray, X_WC: np.ndarray) -> Skeleton:
        raise NotImplementedError


class SkeletonSensor(_SkeletonFromDepth):
    """A simulated OpenPose detector on the head camera (paper 3.2).

    Inputs: `body_poses` (the plant's `get_body_poses_output_port()`), `depth_image`,
    `camera_pose`, and optionally `image_time` (float, s; the HeadCamera's output). Output
    `skeleton`: the person's COCO-18 keypoints as `simulate_keypoints` reports them.

    The noise is stateless and reproducible: each evaluation draws from
    `np.random.default_rng([seed, frame_index])`, frame_index being the image time (or, when
    `image_time` is not connected, the context time) in whole microseconds. The same frame
    gives the same detection however often and in whatever order it is evaluated.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        person: ModelInstanceIndex,
        camera: PinholeCamera,
        noise: SkeletonNoise | None = None,
        seed: int = 0,
    ):
        super().__init__(camera)
        self._noise = SkeletonNoise() if noise is None else noise
        self._seed = seed
        frames = [plant.GetFrameByName(f"coco_{name}", person) for name in COCO18_KEYPOINTS]
        self._body_indices = [int(frame.body().index()) for frame in frames]
        self._p_BK = np.array([frame.GetFixedPoseInBodyFrame().translation() for frame in frames])
        self._body_poses_port = self.DeclareAbstractInputPort(
            "body_poses", AbstractValue.Make([RigidTransform()])
        )
        self._image_time_port = self.DeclareAbstractInputPort(
            "image_time", AbstractValue.Make(float("nan"))
        )

    def keypoints_in_world(self, context: Context) -> np.ndarray:
        """The person's true COCO-18 keypoints (18, 3), from the `body_poses` input."""
        poses: list[RigidTransform] = self._body_poses_port.Eval(context)
        return np.array(
            [poses[b] @ p_BK for b, p_BK in zip(self._body_indices, self._p_BK, strict=True)]
        )

    def frame_index(self, context: Context) -> int:
        """The image time (or the context time) in whole microseconds: the noise's key."""
        time = math.nan
        if self._image_time_port.HasValue(context):
            time = self._image_time_port.Eval(context)
        if not math.isfinite(time):
            time = context.get_time()
        return round(time * 1e6)

    def _calc_from_image(self, context: Context, depth: np.ndarray, X_WC: np.ndarray) -> Skeleton:
        rng = np.random.default_rng([self._seed, self.frame_index(context)])
        keypoints_W = self.keypoints_in_world(context)
        return simulate_keypoints(keypoints_W, self._camera, X_WC, depth, self._noise, rng)


class RecordedSkeletonSource(_SkeletonFromDepth):
    """Replays recorded 2-D detections (e.g. `read_openpose_frames`), lifted with the live
    depth image through the same `lift_keypoints` as the simulated sensor (paper 3.2).

    Frame k of `frames` holds from k / `frame_rate_hz` s until the next; after the last, the
    output is empty with status "recording ended". Inputs `depth_image`, `camera_pose`; output
    `skeleton`. The recording must come from a camera with `camera`'s intrinsics.
    """

    def __init__(self, frames: Sequence[Detection], frame_rate_hz: float, camera: PinholeCamera):
        if not frame_rate_hz > 0:
            raise ValueError(f"frame_rate_hz: expected a positive frame rate, got {frame_rate_hz}")
        super().__init__(camera)
        self._frames, self._frame_rate = list(frames), frame_rate_hz

    def _calc_from_image(self, context: Context, depth: np.ndarray, X_WC: np.ndarray) -> Skeleton:
        # The small allowance keeps frame k at exactly k / rate despite rounding in the time.
        index = math.floor(context.get_time() * self._frame_rate + 1e-9)
        if index >= len(self._frames):
            return Skeleton.missing(RECORDING_ENDED)
        frame = self._frames[index]
        if frame.status != STATUS_OK:
            return Skeleton.missing(frame.status)
        return lift_keypoints(frame.pixels, frame.confidence, depth, self._camera, X_WC)
