"""How the simulated OpenPose errs: a detector model calibrated to OpenPose's measured errors.

OpenPose against marker-based motion capture (Nakano et al. 2020, Frontiers in Sports and Active
Living 2:50) errs at the body's joints by under 20 mm in 47 % of cases, under 30 mm in 80 % and
over 40 mm in 10 %, the largest from an object taken for a body segment or one segment swapped
for another; Needham et al. 2021 (Scientific Reports 11:20673) report errors of the same order.
This model gives each keypoint an error in the image plane, in metres at the keypoint, so it is
the same whatever the camera's resolution or distance (converted to pixels with the focal length
over the keypoint's depth: at 640 x 480, f = 525 px and 1.75 m, 1 px is 3.3 mm):

- **Size.** Per axis, Gaussian with sd `joint_error_m` x the keypoint's share. The shares are
  COCO's per-keypoint sigmas (the annotators' spread, the keypoints OpenPose learnt from:
  nose 0.026, eyes 0.025, ears 0.035, shoulders 0.079, elbows 0.072, wrists 0.062, hips 0.107,
  knees 0.087, ankles 0.089) over their mean at Nakano's six joints, so a wrist errs by 0.75 of
  the joints' mean and an eye by 0.30 (the neck takes the shoulders'). 17.5 mm is the
  least-squares fit of the two-axis error's distribution to the 47 % and 80 % figures: 50 %
  under 20 mm, 77 % under 30, 8.5 % over 40; the swaps and spurious keypoints below make up
  the rest of the 10 %. (Nakano's errors are 3-D, from several cameras: one camera's image-plane
  error is no smaller; its depth error comes from lifting with the depth image.)
- **Persistence.** A share `bias_share` of that variance is a bias that persists, the rest
  jitter drawn anew each frame. A detector errs the same way on images that look the same, so
  the bias decorrelates with time (`bias_time_s`) and faster as the keypoint moves
  (`bias_motion_m`: a limb moved a forearm's length looks different): an Ornstein-Uhlenbeck
  process whose step factor is exp(-(dt / bias_time_s + moved / bias_motion_m)). A held
  pointing gesture (1-2 s) keeps most of its bias, so the recogniser's averaging over a second
  does not remove it, while a new gesture draws a new one.
- **Misses in runs.** Each keypoint goes missing for runs (mean `miss_run_s`) covering a share
  of frames: the face's points and the wrists most often (`miss_rate`).
- **Swaps.** Now and then (`swap_rate` of frames, runs of `swap_run_s`) the two arms' labels are
  exchanged: the right shoulder, elbow and wrist reported as the left ones and the other way.
- **Spurious keypoints.** A wrist within `spurious_reach_m` of an object is sometimes
  (`spurious_rate` of such frames, runs of `spurious_run_s`) reported on the object instead,
  with a lower confidence.

Confidences are OpenPose-like: 0.9 inside the image falling to 0.6 at its border, less a random
share of up to `confidence_spread`; a spurious keypoint's is lower (0.2-0.5 of that). `ideal()`
is a kind detector: independent 2 px jitter and face points dropped independently, nothing
else. `scaled(k)` multiplies every error size and rate by k (the robustness sweep's 1.5x, 2x).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hsr_handover.interface.coco18 import COCO18_KEYPOINTS, FACE_KEYPOINTS, NUM_KEYPOINTS
from hsr_handover.interface.coco18 import keypoint_index as _index

# COCO's per-keypoint sigmas (Lin et al. 2014, the cocoapi's keypoint OKS constants).
_COCO_SIGMAS = {
    "nose": 0.026, "eye": 0.025, "ear": 0.035, "shoulder": 0.079, "elbow": 0.072,
    "wrist": 0.062, "hip": 0.107, "knee": 0.087, "ankle": 0.089,
}  # fmt: skip
_NAKANO_JOINTS = ("shoulder", "elbow", "wrist", "hip", "knee", "ankle")


def _part(name: str) -> str:
    return {"neck": "shoulder"}.get(name, name.split("_")[-1])


KEYPOINT_SHARE = np.array([_COCO_SIGMAS[_part(name)] for name in COCO18_KEYPOINTS]) / np.mean(
    [_COCO_SIGMAS[joint] for joint in _NAKANO_JOINTS]
)
"""(18,) each keypoint's error as a share of `joint_error_m` (COCO's sigmas over the mean at
Nakano's joints)."""

MISS_GROUPS = ("face", "wrist", "elbow", "body")
_MISS_GROUP = np.array(
    [
        0 if name in FACE_KEYPOINTS else 1 if name.endswith("wrist") else 2
        if name.endswith("elbow") else 3
        for name in COCO18_KEYPOINTS
    ]
)  # fmt: skip
ARM_KEYPOINTS = {
    side: [_index(f"{side}_{joint}") for joint in ("shoulder", "elbow", "wrist")] for side in "rl"
}
WRISTS = (_index("r_wrist"), _index("l_wrist"))

_RATE_RANGE, _TIME_RANGE = (0.0, 0.9), (0.0, 10.0)


@dataclasses.dataclass(frozen=True)
class DetectorModel:
    """How the simulated pose detector errs (see the module's docstring for the figures).

    joint_error_m: per-axis sd (m) of the image-plane error at the joints' mean, [0, 0.2].
    pixel_sigma: independent per-frame jitter (px per axis) on top, [0, 100].
    bias_share: share of `joint_error_m`'s variance that persists, [0, 1].
    bias_time_s: the bias's time constant (s), (0, 100]; bias_motion_m: and the keypoint
    motion (m) that renews it by the same factor, (0, 10].
    miss_rate: share of frames each keypoint is missing, by group (face, wrist, elbow, body),
    each in [0, 0.9]; miss_run_s: mean run of a miss (s), [0, 10] (0: independent frames).
    swap_rate, swap_run_s: the arms' labels exchanged, share of frames and mean run.
    spurious_rate, spurious_run_s: a wrist reported on an object within `spurious_reach_m`
    (m, [0, 2]), share of such frames and mean run.
    confidence_spread: how far below the border-scaled confidence a keypoint's may fall, [0, 0.5].
    occlusion_margin (m): a keypoint is hidden when the depth image shows a surface nearer
    than it by more than this, unless that surface is the person's own body around it:
    within `own_body_radius` (m) of a bone meeting at it (limbs are 3.5-7 cm thick, the
    trunk's front 11 cm from its midline, and an arm raised toward the camera covers its own
    shoulder and elbow without hiding them). Each in [0, 1].
    """

    joint_error_m: float = 0.0175
    pixel_sigma: float = 0.0
    bias_share: float = 0.75
    bias_time_s: float = 2.0
    bias_motion_m: float = 0.25
    miss_rate: tuple[float, float, float, float] = (0.10, 0.08, 0.04, 0.02)
    miss_run_s: float = 0.2
    swap_rate: float = 0.02
    swap_run_s: float = 0.1
    spurious_rate: float = 0.05
    spurious_run_s: float = 0.1
    spurious_reach_m: float = 0.25
    confidence_spread: float = 0.3
    occlusion_margin: float = 0.05
    own_body_radius: float = 0.12

    def __post_init__(self) -> None:
        object.__setattr__(self, "miss_rate", tuple(float(r) for r in self.miss_rate))
        if len(self.miss_rate) != len(MISS_GROUPS):
            raise ValueError(f"miss_rate: expected {len(MISS_GROUPS)} rates {MISS_GROUPS}")
        ranges = {
            "joint_error_m": (0.0, 0.2), "pixel_sigma": (0.0, 100.0), "bias_share": (0.0, 1.0),
            "miss_run_s": _TIME_RANGE, "swap_rate": _RATE_RANGE, "swap_run_s": _TIME_RANGE,
            "spurious_rate": _RATE_RANGE, "spurious_run_s": _TIME_RANGE,
            "spurious_reach_m": (0.0, 2.0), "confidence_spread": (0.0, 0.5),
            "occlusion_margin": (0.0, 1.0), "own_body_radius": (0.0, 1.0),
        }  # fmt: skip
        for name, (low, high) in ranges.items():
            value = getattr(self, name)
            if not low <= value <= high:
                raise ValueError(f"{name}: expected in [{low:g}, {high:g}], got {value}")
        for rate in self.miss_rate:
            if not _RATE_RANGE[0] <= rate <= _RATE_RANGE[1]:
                raise ValueError(f"miss_rate: expected each in [0, 0.9], got {self.miss_rate}")
        if not (0 < self.bias_time_s <= 100 and 0 < self.bias_motion_m <= 10):
            raise ValueError(
                "bias_time_s, bias_motion_m: expected in (0, 100] s and (0, 10] m, got "
                f"{self.bias_time_s}, {self.bias_motion_m}"
            )

    @classmethod
    def ideal(cls) -> DetectorModel:
        """A kind detector: 2 px of independent jitter per axis (at 640 x 480) and each face
        point dropped in a tenth of frames, independently; no bias, swaps or spurious points."""
        return cls(
            joint_error_m=0.0, pixel_sigma=2.0, miss_rate=(0.1, 0.0, 0.0, 0.0), miss_run_s=0.0,
            swap_rate=0.0, spurious_rate=0.0, confidence_spread=0.0,
        )  # fmt: skip

    def scaled(self, factor: float) -> DetectorModel:
        """Every error size and rate times `factor` (rates capped at 0.9)."""
        if not factor >= 0:
            raise ValueError(f"factor: expected >= 0, got {factor}")

        def rate(value: float) -> float:
            return min(value * factor, _RATE_RANGE[1])

        return dataclasses.replace(
            self,
            joint_error_m=min(self.joint_error_m * factor, 0.2),
            pixel_sigma=min(self.pixel_sigma * factor, 100.0),
            miss_rate=tuple(rate(r) for r in self.miss_rate),
            swap_rate=rate(self.swap_rate),
            spurious_rate=rate(self.spurious_rate),
        )

    def keypoint_miss_rate(self) -> np.ndarray:
        """(18,) each keypoint's share of frames missing."""
        return np.asarray(self.miss_rate)[_MISS_GROUP]


PRESETS = {"realistic": DetectorModel, "ideal": DetectorModel.ideal}


@dataclasses.dataclass(frozen=True)
class DetectorState:
    """What persists of the detector's errors between frames: each keypoint's bias (18, 2) (m,
    camera x and y), which keypoints are in a missed run (18,), whether the arms are swapped,
    where each wrist (right, left) is reported instead when spurious ((2, 3) world points,
    NaN when not), and the keypoints (18, 3) and time (s) of the frame it was drawn for."""

    bias: np.ndarray
    missing: np.ndarray
    swapped: bool
    spurious: np.ndarray
    keypoints: np.ndarray
    time: float

    @classmethod
    def start(cls) -> DetectorState:
        """Before the first frame: the first frame draws from the stationary distributions."""
        nan = np.full((NUM_KEYPOINTS, 3), np.nan)
        return cls(np.zeros((NUM_KEYPOINTS, 2)), np.zeros(NUM_KEYPOINTS, bool), False,
                   np.full((2, 3), np.nan), nan, math.nan)  # fmt: skip


def _runs(active, rate, run_s: float, dt: float, draws):
    """The next frame of two-state runs with stationary share `rate` and mean length `run_s`
    at frames `dt` apart: a run goes on with probability 1 - dt / run_s (never below `rate`,
    which makes frames independent; `run_s` 0 does), and starts with the probability that
    keeps the share at `rate`. A first frame (`dt` NaN) draws from the share itself."""
    rate = np.asarray(rate, dtype=float)
    if math.isnan(dt):
        return draws < rate
    stay = rate if run_s <= 0 or dt <= 0 else np.maximum(1.0 - dt / run_s, rate)
    start = rate * (1.0 - stay) / (1.0 - rate)  # rate <= 0.9
    return np.where(active, draws < stay, draws < start)


def advance(
    state: DetectorState,
    keypoints_W: np.ndarray,
    objects_W: np.ndarray,
    time: float,
    model: DetectorModel,
    rng: np.random.Generator,
) -> DetectorState:
    """The detector's persistent errors at the frame captured at `time` (s) of a person whose
    true keypoints are `keypoints_W` (18, 3), among objects centred at `objects_W` (N, 3).

    The draws have fixed sizes, so the same generator gives the same errors whichever
    keypoints or objects there are."""
    dt = time - state.time
    bias_sd = model.joint_error_m * math.sqrt(model.bias_share) * KEYPOINT_SHARE[:, None]
    bias_draw = rng.standard_normal((NUM_KEYPOINTS, 2))
    miss_draw, swap_draw, spurious_draw = rng.random(NUM_KEYPOINTS), rng.random(), rng.random(2)
    if math.isnan(dt):
        bias = bias_sd * bias_draw
    else:
        moved = np.linalg.norm(keypoints_W - state.keypoints, axis=1)
        moved = np.where(np.isfinite(moved), moved, np.inf)
        keep = np.exp(-(dt / model.bias_time_s + moved / model.bias_motion_m))[:, None]
        bias = keep * state.bias + np.sqrt(1 - keep**2) * bias_sd * bias_draw
    missing = _runs(state.missing, model.keypoint_miss_rate(), model.miss_run_s, dt, miss_draw)
    swapped = bool(_runs(np.array(state.swapped), model.swap_rate, model.swap_run_s, dt, swap_draw))
    spurious = np.full((2, 3), np.nan)
    objects_W = np.asarray(objects_W, dtype=float).reshape(-1, 3)
    for k, wrist in enumerate(WRISTS):
        if not len(objects_W):
            continue
        distances = np.linalg.norm(objects_W - keypoints_W[wrist], axis=1)
        nearest = int(np.argmin(distances))
        if not distances[nearest] <= model.spurious_reach_m:
            continue
        active = np.isfinite(state.spurious[k]).all()
        on = _runs(np.array(active), model.spurious_rate, model.spurious_run_s, dt,
                   spurious_draw[k])  # fmt: skip
        if on:
            spurious[k] = objects_W[nearest]
    return DetectorState(bias, missing, swapped, spurious, np.array(keypoints_W, float), time)
