"""The scenario schema: typed dataclasses that Drake's `yaml_load_typed` fills (the `Scenario` +
`load_scenario` pattern of the manipulation course). No `from __future__ import annotations`
here: Drake's YAML loader reads the field types at run time and needs them as real types.

World frame: z up, the floor at z = 0. Poses are [x, y, yaw] on the floor unless said otherwise.
Left and right in scenario names are as the *person* sees them.

Every number has a range, stated in its class's docstring and checked on loading (`checks`):
all are finite; positions (x, y or z) lie in the room, [-20, 20] m; yaws in [-2pi, 2pi] rad;
times in [0, 3600] s. Intervals are written as in maths: (0, 1] excludes 0 and includes 1.
"""

import dataclasses
from dataclasses import field

from hsr_handover.interface.openpose_format import DEFAULT_KEYPOINT_SCALE, DEFAULT_MODEL
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.intent import IntentParams
from hsr_handover.robot.perception.attention import DEFAULT_ATTENTION_WEIGHT
from hsr_handover.robot.perception.cloud_map import SCENE_GNG_PARAMS, SIGNALS_PER_FRAME
from hsr_handover.scenario.typed_yaml import YAML_KEY, shorten
from hsr_handover.world.person.body import SEAT_HEIGHT, BodyDimensions
from hsr_handover.world.person.imprecision import Imprecision
from hsr_handover.world.person.receiving import ReceivingParams
from hsr_handover.world.sensors.detector_model import PRESETS, DetectorModel

MAX_KEY_PATH = 60
MAX_EXPECTED = 140
"""Longest key path and expectation an error repeats, so every error is one short line."""


class ScenarioError(ValueError):
    """A scenario file is broken: names the file, the key path and what was expected."""

    def __init__(self, filename: str, key_path: str, expected: str):
        key_path, expected = shorten(key_path, MAX_KEY_PATH), shorten(expected, MAX_EXPECTED)
        super().__init__(f"{filename}: {key_path}: {expected}")
        self.filename = filename
        self.key_path = key_path
        self.expected = expected


@dataclasses.dataclass
class RobotConfig:
    """The HSR: model URL (package:// or a path relative to the scenario file), base pose on the
    floor [x, y, yaw] and the start posture by joint name. The file's joints are merged over the
    HSR's default posture (the arm upright, the hand tucked forward, the head level); joints
    named nowhere start at 0. With `perception.active_gaze` the robot turns its head itself to
    find the person, so no scenario needs to set the head.

    Ranges: model names an SDF or URDF file with the HSR's joints and head camera frame;
    base_pose x, y in [-20, 20] m, yaw in [-2pi, 2pi] rad; each joint value in [-2pi, 2pi]
    (rad, or m for arm_lift_joint), and within the joint's limits in the model."""

    model: str = "package://hsr_handover/hsrb/hsrb.sdf"
    base_pose: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    joints: dict[str, float] = field(
        default_factory=lambda: {
            "arm_flex_joint": 0.0,
            "wrist_flex_joint": -1.57,
        }
    )


@dataclasses.dataclass
class TableConfig:
    """A four-legged table: top centre [x, y] and yaw, top size [depth along its x, width along
    its y], the height of the top surface and the top's thickness (m).

    Ranges: center each in [-20, 20] m; yaw in [-2pi, 2pi] rad; size each in [0.2, 5] m (room
    for an object and the hand); height in [0.3, 1.2] m; thickness in (0, height) m."""

    center: list[float] = field(default_factory=lambda: [0.85, 0.0])
    yaw: float = 0.0
    size: list[float] = field(default_factory=lambda: [0.6, 1.0])
    height: float = 0.72
    thickness: float = 0.04


@dataclasses.dataclass
class ObjectConfig:
    """A graspable object resting on the table.

    shape: "cup" (size [diameter, height]) or "box" (size [x, y, z]).
    position: [x, y] of its centre on the table top, or [x, y, z] of its centre (then checked to
    rest on the top). color: a name from `OBJECT_COLORS`; colours must be distinct, since the
    robot tells objects apart by colour.

    Ranges: name of at most 64 ASCII letters, digits and _, unique, and not a name the world
    already uses ("table", "person", the robot model's name, Drake's "WorldModelInstance" and
    "DefaultModelInstance", SDFormat's "world" and "__...__"); size each in [0.01, 0.5] m, the
    smaller horizontal side at most the gripper's 0.12 m; position x, y (and z) in [-20, 20] m,
    the footprint inside the table top; yaw in [-2pi, 2pi] rad; mass in [0.001, 1.2] kg (a gram
    to the payload).
    """

    name: str = ""
    shape: str = "cup"
    size: list[float] = field(default_factory=lambda: [0.07, 0.10])
    color: str = "red"
    position: list[float] = field(default_factory=lambda: [0.8, 0.0])
    yaw: float = 0.0
    mass: float = 0.2


@dataclasses.dataclass
class ActionConfig:
    """One timed action of the person's script.

    action: "look_at" (target), "point_at" (target), "reach_to" (point [x, y, z]), "touch" (point:
    the hand goes there without the eyes following, to scratch the head or lay an arm down),
    "gesture" (talking with the `arm`'s hand, elbow bent) or "rest".
    start: when it begins (s). duration: how long it lasts (s); by default until the next action
    starts. The person rests between an action's end and the next one's start.
    arm: "right" or "left", the arm that points or reaches.

    Ranges: start in [0, 3600] s, not before the previous action's; duration in (0, 3600] s;
    point each in [-20, 20] m.
    """

    action: str = "rest"
    start: float = 0.0
    duration: float | None = None
    target: str = ""
    point: list[float] = field(default_factory=list)
    arm: str = "right"


@dataclasses.dataclass
class ImprecisionConfig:
    """How imprecisely the simulated person points and looks, drawn from the run's seed
    (`world.person.imprecision`): each pointing gesture misses the shoulder-to-target ray
    by `pointing_error_deg` on average (Breuer et al. 2010: 7.3 deg); the head makes
    `head_turn_fraction` of a gaze shift on average (Stiefelhagen and Zhu 2002: 0.689), varying
    between people by `head_turn_fraction_sd`. Zero error and a fraction of 1 give an exact person.

    Ranges: pointing_error_deg in [0, 45] deg; head_turn_fraction in [0.3, 1];
    head_turn_fraction_sd in [0, 0.5]."""

    pointing_error_deg: float = Imprecision.pointing_error_deg
    head_turn_fraction: float = Imprecision.head_turn_fraction
    head_turn_fraction_sd: float = Imprecision.head_turn_fraction_sd

    def model(self) -> Imprecision:
        return Imprecision(**dataclasses.asdict(self))


@dataclasses.dataclass
class VariationConfig:
    """How much the person varies from trial to trial in an experiment (a single run uses the
    file's person as it is): height (m), position on the floor (m, each axis) and yaw (deg) as
    standard deviations; when the request starts (`onset_s` [earliest, latest]); how long the
    look leads the pointing (`look_lead_s`); how long the arm points (`point_duration_s`); and
    the chance that the left arm points rather than the right (`left_arm_probability`). In the
    handover experiment also: how soon the person reaches for an object held out to them
    (`reaction_s` [earliest, latest]); the chance they hold out their receiving hand before the
    robot comes (`hold_out_probability`), how long after the pointing ends (`hold_out_delay_s`)
    and how far from the usual place, in front of the receiving shoulder (`hold_out_sd`, m each
    axis).

    Ranges: height_sd in [0, 0.2] m; position_sd in [0, 0.3] m; yaw_sd_deg in [0, 30] deg;
    onset_s, look_lead_s, point_duration_s, reaction_s, hold_out_delay_s each [low, high] with
    0 <= low <= high <= 60 s; left_arm_probability and hold_out_probability in [0, 1];
    hold_out_sd in [0, 0.2] m."""

    height_sd: float = 0.07
    position_sd: float = 0.05
    yaw_sd_deg: float = 8.0
    onset_s: list[float] = field(default_factory=lambda: [0.3, 1.0])
    look_lead_s: list[float] = field(default_factory=lambda: [0.2, 0.8])
    point_duration_s: list[float] = field(default_factory=lambda: [2.0, 3.0])
    left_arm_probability: float = 0.3
    reaction_s: list[float] = field(default_factory=lambda: [0.3, 1.0])
    hold_out_probability: float = 0.5
    hold_out_delay_s: list[float] = field(default_factory=lambda: [0.5, 3.0])
    hold_out_sd: float = 0.05


@dataclasses.dataclass
class ReceivingConfig:
    """How the person takes an object the robot holds out (the world side of a handover):
    `takes` (false: never reaches, so the robot must give up), `reaction_s` from the offer
    (the object still and within reach) to the reach, the `arm` preferred (the hand held out),
    `either_hand` (false: takes with `arm` only; true: with the hand whose shoulder is nearer
    the object held out), `corrects` (false: a person who sees the robot lift another object
    than the one asked for does not ask again) and `repeats` (false: a person whose request
    draws no response, the robot's hand still for `repeat_after_s` after the pointing ends,
    does not ask again). A person who asked for an object takes only that one.

    Ranges: reaction_s in [0, 10] s; arm "right" or "left"; repeat_after_s in [0.5, 30] s."""

    takes: bool = ReceivingParams.takes
    reaction_s: float = ReceivingParams.reaction_s
    arm: str = ReceivingParams.arm
    either_hand: bool = ReceivingParams.either_hand
    corrects: bool = ReceivingParams.corrects
    repeats: bool = ReceivingParams.repeats
    repeat_after_s: float = ReceivingParams.repeat_after_s

    def params(self) -> ReceivingParams:
        return ReceivingParams(**dataclasses.asdict(self))


@dataclasses.dataclass
class PersonConfig:
    """An adult at the table: feet position [x, y] and yaw (facing its +x), height, posture
    ("seated" or "standing"), the seat's height (its top, seated only: a dining chair's by
    default, a bar stool's at a bar table), the behaviour script, how imprecisely they point
    and look, and how much they vary between an experiment's trials.

    Ranges: position each in [-20, 20] m; yaw in [-2pi, 2pi] rad; height in [1.2, 2.1] m;
    seat_height in [0.3, 0.9] m."""

    position: list[float] = field(default_factory=lambda: [1.55, 0.0])
    yaw: float = 3.141592653589793
    height: float = 1.70
    posture: str = "seated"
    seat_height: float = SEAT_HEIGHT
    behavior: list[ActionConfig] = field(default_factory=list)
    imprecision: ImprecisionConfig = field(default_factory=ImprecisionConfig)
    variation: VariationConfig = field(default_factory=VariationConfig)
    receiving: ReceivingConfig = field(default_factory=ReceivingConfig)

    def body(self) -> BodyDimensions:
        """The person's body dimensions, standing or on their seat."""
        return BodyDimensions.from_height(self.height, self.posture == "seated", self.seat_height)


@dataclasses.dataclass
class CameraConfig:
    """The HSR's head RGB-D camera (an Xtion): image size, frame rate, horizontal field of view,
    the depth range it reports (m), and whether to render the ground-truth label image (for
    scoring only; the robot never reads it; off saves about a quarter of the camera's time).
    `intrinsics` [fx, fy, cx, cy] (px) give a calibrated camera's, as a recorded session's
    camera_info holds them; empty, the pixels are square and the principal point centred, from
    `fov_x`.

    Ranges: width and height integers in [16, 4096] px; rate_hz in [1, 120] Hz; fov_x in
    (0, pi) rad; depth_range [near, far] with 0 < near < far <= 20 m; intrinsics empty or
    fx, fy in (0, 1e5] px and cx, cy inside the image."""

    width: int = 640
    height: int = 480
    rate_hz: float = 30.0
    fov_x: float = 1.05
    depth_range: list[float] = field(default_factory=lambda: [0.35, 4.0])
    render_label: bool = True
    intrinsics: list[float] = field(default_factory=list)

    def pinhole(self) -> PinholeCamera:
        """The intrinsics as the numpy pinhole model perception uses."""
        if self.intrinsics:
            return PinholeCamera(self.width, self.height, *map(float, self.intrinsics))
        return PinholeCamera.from_fov_x(self.width, self.height, self.fov_x)


@dataclasses.dataclass
class GngConfig:
    """The scene map's adaptive Growing Neural Gas (paper §3.1 names; docs/design.md §3.1). The
    defaults are the adaptive settings that reach the paper's ~4x node density under attention.

    Ranges: max_nodes an integer in [3, 5000]; lam and a_max integers in [1, 1e6]; mu1 and mu2
    in (0, 1]; mu3 in [0, 1e6] 1/m; alpha and beta in [0, 1); e_min in [0, 1e6] m^2."""

    max_nodes: int = SCENE_GNG_PARAMS["max_nodes"]
    lam: int = SCENE_GNG_PARAMS["lam"]
    mu1: float = SCENE_GNG_PARAMS["mu1"]
    mu2: float = SCENE_GNG_PARAMS["mu2"]
    mu3: float = SCENE_GNG_PARAMS["mu3"]
    a_max: int = SCENE_GNG_PARAMS["a_max"]
    alpha: float = SCENE_GNG_PARAMS["alpha"]
    beta: float = SCENE_GNG_PARAMS["beta"]
    e_min: float = SCENE_GNG_PARAMS["e_min"]


@dataclasses.dataclass
class FocusConfig:
    """From `start` (s), attend to `focus`: "face", "hand", "object" (then `target` names the
    object) or "none".

    Ranges: start in [0, 3600] s, not before the previous entry's."""

    start: float = 0.0
    focus: str = "none"
    target: str = ""


@dataclasses.dataclass
class SkeletonRecordingConfig:
    """Recorded OpenPose output played back as the skeleton sensor's detections, in place of
    the simulated detector's: `path`, an OpenPose JSON file or a folder of per-frame files
    (relative to the scenario file; frames in OpenPose's order, natural order by name), frame k
    shown from k / `frame_rate_hz` s; `model` "auto" (told by the files), "COCO" or "BODY_25";
    `keypoint_scale` "pixels", "unit" ([0, 1]) or "signed_unit" ([-1, 1]), converted with the
    camera's image size; `near_px` [u, v] follows the person nearest that pixel (empty: the one
    facing the camera with the widest shoulders). Frames that cannot be read are skipped with a
    warning. The recording must come from a camera with the scenario camera's intrinsics.

    Ranges: path an existing file or folder; frame_rate_hz in (0, 120] Hz; near_px empty or
    [u, v] each in [-1e5, 1e5] px."""

    path: str = ""
    frame_rate_hz: float = 30.0
    model: str = DEFAULT_MODEL
    keypoint_scale: str = DEFAULT_KEYPOINT_SCALE
    near_px: list[float] = field(default_factory=list)


@dataclasses.dataclass
class DetectorConfig:
    """The simulated pose detector (`hsr_handover.world.sensors.detector_model`, where the figures
    come from): `preset` "realistic" (OpenPose's measured errors: a persistent bias and frame
    jitter, misses in runs, swapped arms, a wrist on an object) or "ideal" (2 px of independent
    jitter at 640 x 480 and face points dropped in a tenth of frames, nothing else); any of
    DetectorModel's fields set here replaces the preset's; then every error size and rate is
    multiplied by `scale`.

    Ranges: preset one of ["realistic", "ideal"]; scale in [0, 10]; each field as
    `DetectorModel` states (joint_error_m [0, 0.2] m, pixel_sigma [0, 100] px, bias_share
    [0, 1], bias_time_s (0, 100] s, bias_motion_m (0, 10] m, miss_rate four rates (face,
    wrist, elbow, body) each [0, 0.9], the rates [0, 0.9], the runs [0, 10] s,
    spurious_reach_m [0, 2] m, confidence_spread [0, 0.5], occlusion_margin and
    own_body_radius [0, 1] m)."""

    preset: str = "realistic"
    scale: float = 1.0
    joint_error_m: float | None = None
    pixel_sigma: float | None = None
    bias_share: float | None = None
    bias_time_s: float | None = None
    bias_motion_m: float | None = None
    miss_rate: list[float] | None = None
    miss_run_s: float | None = None
    swap_rate: float | None = None
    swap_run_s: float | None = None
    spurious_rate: float | None = None
    spurious_run_s: float | None = None
    spurious_reach_m: float | None = None
    confidence_spread: float | None = None
    occlusion_margin: float | None = None
    own_body_radius: float | None = None

    def model(self) -> DetectorModel:
        """The detector model (raises ValueError naming a field out of range)."""
        fields = dataclasses.asdict(self)
        preset, scale = fields.pop("preset"), fields.pop("scale")
        if preset not in PRESETS:
            raise ValueError(f"preset: expected one of {list(PRESETS)}, got {preset!r}")
        overrides = {name: value for name, value in fields.items() if value is not None}
        return dataclasses.replace(PRESETS[preset](), **overrides).scaled(scale)


@dataclasses.dataclass
class PerceptionConfig:
    """The robot's perception, off unless `enabled`: the head camera's depth is downsampled to
    `cloud_size` [width, height] (the paper's 200 x 200), lifted to a world point cloud, cropped
    to `workspace` [x, y, z lower, x, y, z upper] (m) and learnt by the scene GNG with
    `signals_per_frame` signals per camera frame; attended regions are sampled `attention_weight`
    times more often. The skeleton sensor errs as `detector` says (DetectorConfig: OpenPose's
    measured errors unless told otherwise); with `skeleton_recording`, it plays a recording
    of OpenPose's output instead (SkeletonRecordingConfig). With `active_gaze` the robot turns
    its head to find the person and keep their face, hands and the objects in view
    (`hsr_handover.robot.perception.active_gaze`); off, the head holds the start posture (the
    baseline the active gaze is measured against).

    Ranges: cloud_size integers each in [8, 1024] px; workspace each in [-20, 20] m, each lower
    bound below its upper; signals_per_frame an integer in [1, 1e6]; attention_weight in
    [1, 1e4]."""

    enabled: bool = False
    cloud_size: list[int] = field(default_factory=lambda: [200, 200])
    workspace: list[float] = field(default_factory=lambda: [0.3, -1.0, 0.05, 2.4, 1.0, 2.0])
    signals_per_frame: int = SIGNALS_PER_FRAME
    attention_weight: float = DEFAULT_ATTENTION_WEIGHT
    attention: list[FocusConfig] = field(default_factory=list)
    gng: GngConfig = field(default_factory=GngConfig)
    detector: DetectorConfig = field(default_factory=DetectorConfig)
    skeleton_recording: SkeletonRecordingConfig | None = None
    active_gaze: bool = True


@dataclasses.dataclass
class IntentConfig:
    """The robot's pointing-intent recogniser (paper 3.2, eqs. 16-17), which runs whenever
    perception does: an arm straighter than `straight_arm_deg` (eq. 16's elbow angle) whose
    `pointing_ray` ("shoulder_wrist", "elbow_wrist" or "eye_wrist") passes within `d_min` of an
    object, and the eyes' direction (eq. 17's face normal, its turn from the torso's forward
    direction and its pitch from level, scaled by `head_gain`; with `face_from_head_shape`
    the face's direction is read from the head's shape in depth where it is found, else from
    eq. 17's normal tilted down by `face_tilt_deg`)
    within `gaze_tolerance_deg` horizontally of the same object (or `gaze_tolerance_share` of
    the eyes' turn from the torso's front to it, if more) and no more than
    `gaze_pitch_tolerance_deg` above it (or `gaze_pitch_tolerance_share` of the eyes' look down
    to it, if more), both for `t_max`, over rays averaged across
    `smoothing_s` (the face's pitch across `pitch_smoothing_s`), while the pointing arm turns
    slower than `steady_deg_s`; an arm that reads bent for no longer than `bent_gap_s` goes on
    pointing; `gaze_weight` weighs the eyes against the arm between objects both allow; with
    `track_keypoints`, each keypoint is followed over time first (smoothed, outliers and
    swapped arms rejected, short misses bridged: `hsr_handover.robot.perception.keypoint_filter`).
    The meaning and the measured defaults: `hsr_handover.robot.intent.IntentParams`.

    Ranges: straight_arm_deg in (90, 180] deg; d_min in (0, 2] m; gaze_tolerance_deg and
    gaze_pitch_tolerance_deg in (0, 90] deg; gaze_tolerance_share and
    gaze_pitch_tolerance_share in [0, 1];
    gaze_weight in (0, 10]; t_max in [0, 10] s;
    head_gain in [1, 3]; face_tilt_deg in [0, 90] deg; smoothing_s in [0, 10] s; steady_deg_s
    in (0, 1000] deg/s; bent_gap_s and pitch_smoothing_s in [0, 10] s."""

    straight_arm_deg: float = IntentParams.straight_arm_deg
    d_min: float = IntentParams.d_min
    gaze_tolerance_deg: float = IntentParams.gaze_tolerance_deg
    gaze_tolerance_share: float = IntentParams.gaze_tolerance_share
    gaze_pitch_tolerance_deg: float = IntentParams.gaze_pitch_tolerance_deg
    gaze_pitch_tolerance_share: float = IntentParams.gaze_pitch_tolerance_share
    gaze_weight: float = IntentParams.gaze_weight
    t_max: float = IntentParams.t_max
    pointing_ray: str = IntentParams.pointing_ray
    head_gain: float = IntentParams.head_gain
    face_from_head_shape: bool = IntentParams.face_from_head_shape
    face_tilt_deg: float = IntentParams.face_tilt_deg
    smoothing_s: float = IntentParams.smoothing_s
    steady_deg_s: float = IntentParams.steady_deg_s
    bent_gap_s: float = IntentParams.bent_gap_s
    pitch_smoothing_s: float = IntentParams.pitch_smoothing_s
    track_keypoints: bool = IntentParams.track_keypoints

    def params(self) -> IntentParams:
        """The recogniser's parameters (raises ValueError naming a field out of range)."""
        return IntentParams(**dataclasses.asdict(self))


@dataclasses.dataclass
class HandoverConfig:
    """The perceiving-acting cycle: with `enabled`, the robot watches (its head
    looks round the table first), and once it recognises the object asked for it grasps it,
    lifts it, carries it to the handover point and waits for the person's hand, releasing
    when the hand holds it. It needs `perception.enabled`."""

    enabled: bool = False


@dataclasses.dataclass
class SimulationConfig:
    """Simulated duration (s), the plant's discrete time step (s), the random seed, and the frame
    rate of the replay recording.

    Ranges: duration in (0, 3600] s; time_step in [1e-4, 0.01] s (below, a run of minutes
    takes days; above, contact is not stable); seed an integer in [0, 2**32 - 1]; replay_fps
    in (0, 120] Hz. The 3 ms step: the handover reference (64 trials) and the three layouts
    give the same outcomes as at 2 ms, 1.14 times faster; at 4 ms a held object slips."""

    duration: float = 5.0
    time_step: float = 0.003
    seed: int = 0
    replay_fps: float = 20.0


@dataclasses.dataclass
class LayoutsConfig:
    """The ranges `--layouts generated` draws each experiment trial's layout from (uniformly,
    each [low, high]; `hsr_handover.experiments.layouts`). The table stands with its near edge
    `layouts.NEAR_EDGE` (0.65 m) before the robot's nominal base; the person across it,
    `person_back` m beyond its far edge (the point below the hips), `person_along` m to the side
    of the table's axis, turned `facing_deg` off facing it, seated or (with
    `standing_probability`) standing; 3-6 cups and boxes in distinct detector colours, in a row
    across the table or staggered (`staggered_probability`), `object_spacing` m apart; the
    robot's base moved by `base_offset` m along each axis and turned by `base_yaw` rad.

    Ranges: a scenario may only narrow them: each [low, high] with low <= high inside the
    defaults (person_height [1.5, 1.95] m, person_back [0.3, 0.6] m, person_along
    [-0.35, 0.35] m, facing_deg [-25, 25] deg, table_height [0.6, 0.85] m, table_depth
    [0.5, 0.8] m, table_width [0.8, 1.4] m, object_count [3, 6] integers, object_spacing
    [0.15, 0.3] m, base_offset [-0.2, 0.2] m, base_yaw [-0.4, 0.4] rad); the probabilities in
    [0, 1]."""

    standing_probability: float = 0.5
    person_height: list[float] = field(default_factory=lambda: [1.50, 1.95])
    person_back: list[float] = field(default_factory=lambda: [0.30, 0.60])
    person_along: list[float] = field(default_factory=lambda: [-0.35, 0.35])
    facing_deg: list[float] = field(default_factory=lambda: [-25.0, 25.0])
    table_height: list[float] = field(default_factory=lambda: [0.60, 0.85])
    table_depth: list[float] = field(default_factory=lambda: [0.50, 0.80])
    table_width: list[float] = field(default_factory=lambda: [0.80, 1.40])
    object_count: list[int] = field(default_factory=lambda: [3, 6])
    object_spacing: list[float] = field(default_factory=lambda: [0.15, 0.30])
    staggered_probability: float = 0.5
    base_offset: list[float] = field(default_factory=lambda: [-0.2, 0.2])
    base_yaw: list[float] = field(default_factory=lambda: [-0.4, 0.4])


@dataclasses.dataclass
class Scenario:
    """A whole scenario file: one mapping of these sections, each optional (defaults above)."""

    robot: RobotConfig = field(default_factory=RobotConfig)
    table: TableConfig = field(default_factory=TableConfig)
    objects: list[ObjectConfig] = field(default_factory=list)
    person: PersonConfig = field(default_factory=PersonConfig)
    camera: CameraConfig = field(default_factory=CameraConfig)
    perception: PerceptionConfig = field(default_factory=PerceptionConfig)
    intent: IntentConfig = field(default_factory=IntentConfig)
    handover: HandoverConfig = field(default_factory=HandoverConfig)
    simulation: SimulationConfig = field(default_factory=SimulationConfig)
    layouts: LayoutsConfig = field(default_factory=LayoutsConfig)
    # Where the scenario came from, for error messages and relative model paths; set by the
    # loader, never read from YAML (the schema walk treats it as an unknown key).
    source: str = field(default="<scenario>", metadata={YAML_KEY: False})
