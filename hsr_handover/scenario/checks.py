"""Checks of a loaded Scenario: every number within its stated range (the ranges the dataclass
docstrings in `schema` give), names and references that resolve, objects that rest on the table
without overlapping, and a robot model file that Drake parses into an HSR.

Each raises ScenarioError naming the key path and what was expected. Footprints on the table
top are exact for the shapes we have: cups are discs, boxes are rotated rectangles.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import logging
import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import NoReturn

import numpy as np
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.error_text import first_line
from hsr_handover.hsr import (
    ARM_JOINTS,
    BASE_JOINTS,
    CAMERA_FRAME,
    GRIPPER_JOINT,
    GRIPPER_MAX_OPENING,
    GRIPPER_MIMIC_JOINT,
    HEAD_JOINTS,
    MODELS_DIR,
    TORSO_JOINT,
    actuated_joint_names,
    add_hsr,
)
from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.interface.openpose_format import KEYPOINT_SCALES, MODEL_CHOICES
from hsr_handover.robot.perception.attention import FOCUS_KINDS
from hsr_handover.scenario.schema import LayoutsConfig, ObjectConfig, Scenario, ScenarioError
from hsr_handover.scenario.typed_yaml import describe
from hsr_handover.world.person.behavior import ACTIONS, REACHES
from hsr_handover.world.scene.object_models import OBJECT_SHAPES, object_height

GRIPPER_MAX_WIDTH = round(
    GRIPPER_MAX_OPENING - 0.017, 3
)  # m: what the gripper closes around, with margin
PAYLOAD = 1.2  # kg
LIGHTEST_OBJECT = 0.001  # kg: a gram; far lighter, the contact solver's factorisation fails
SMALLEST_OBJECT = 0.01
"""m: an object's least side; smaller, it is no object to hand over (under 2 px at the camera's
1 m and 320 px), and contact between bodies of micrometres is past the solver's resolution."""
SMALLEST_TABLE = 0.2  # m: a table's least depth or width, room for one object and the hand
SLOWEST_CAMERA = 1.0
"""Hz: the least camera rate; perception and intent smooth over frames a fraction of a second
apart (IntentParams' windows), which a slower camera never fills."""
REST_TOLERANCE = 0.005  # m: how far an object's given z may be from resting on the top
MAX_NAME_LENGTH = 64

HSR_ACTUATED_JOINTS = (*BASE_JOINTS, *ARM_JOINTS, *HEAD_JOINTS, GRIPPER_JOINT)
HSR_MIMIC_JOINTS = (TORSO_JOINT, GRIPPER_MIMIC_JOINT)
WORLD_MODELS = ("table", "person")
"""The models the station adds besides the robot and the objects (scene/table_model.py and
scene/person_model.py name them); model names in one plant must be unique."""

Fail = Callable[[str, str], NoReturn]


@dataclasses.dataclass(frozen=True)
class Interval:
    """A range of numbers with its unit, written as in maths: [a, b] closed, (a, b] open at a."""

    low: float
    high: float
    unit: str = ""
    open_low: bool = False
    open_high: bool = False
    integer: bool = False

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.open_low else value >= self.low
        below = value < self.high if self.open_high else value <= self.high
        return bool(above and below)  # False for NaN, which compares False with everything

    def __str__(self) -> str:
        low, high = (_format(bound) for bound in (self.low, self.high))
        text = f"{'(['[not self.open_low]}{low}, {high}{')]'[not self.open_high]}"
        return f"{text} ({self.unit})" if self.unit else text

    @property
    def noun(self) -> str:
        return "an integer" if self.integer else "a number"


def _format(number: float) -> str:
    """An int in full (2**32 - 1 is 4294967295, not 4.29497e+09), a float briefly."""
    return f"{number:g}" if isinstance(number, float) else str(number)


TAU = 2 * math.pi
ROOM = Interval(-20.0, 20.0, "m")  # every position: the room the robot works in
YAW = Interval(-TAU, TAU, "rad")
TIME = Interval(0.0, 3600.0, "s")  # start times in a script
DURATION = Interval(0.0, 3600.0, "s", open_low=True)
RATE = Interval(0.0, 120.0, "Hz", open_low=True)
UNIT_RATE = Interval(0.0, 1.0, open_low=True)  # GNG learning rates
FRACTION = Interval(0.0, 1.0, open_high=True)  # GNG error reductions
COUNT = Interval(1, 1_000_000, integer=True)
SEED = Interval(0, 2**32 - 1, integer=True)  # what numpy and Drake seed with
JOINT = Interval(-TAU, TAU, "rad or m")


def check_scenario(scenario: Scenario) -> None:
    """Raise ScenarioError at the first problem a scenario's numbers show."""
    fail = _failer(scenario.source)
    robot_models = _check_robot(scenario, fail)
    _check_simulation(scenario, fail)
    _check_camera(scenario, fail)
    _check_table(scenario, fail)
    _check_objects(scenario, robot_models, fail)
    _check_person(scenario, fail)
    _check_imprecision(scenario, fail)
    _check_variation(scenario, fail)
    _check_perception(scenario, fail)
    _check_intent(scenario, fail)
    _check_layouts(scenario, fail)
    if scenario.handover.enabled and not scenario.perception.enabled:
        fail("handover.enabled", "perception.enabled: true as well (the robot acts on percepts)")


def _failer(source: str) -> Fail:
    def fail(key_path: str, expected: str) -> NoReturn:
        raise ScenarioError(source, key_path, expected)

    return fail


def _number(fail: Fail, key: str, value: float, interval: Interval) -> None:
    """One number within its interval (type checks already ran: ints where ints belong)."""
    if value not in interval:
        fail(key, f"expected {interval.noun} in {interval}, got {describe(value)}")


def _numbers(
    fail: Fail, key: str, values: Sequence[float], interval: Interval, layout: str = ""
) -> None:
    """A list of numbers, each within `interval`; with a `layout` such as "[x, y]", also as many
    as it names."""
    if layout and len(values) != layout.count(",") + 1:
        fail(key, f"expected {layout}, got {describe(values)}")
    for index, value in enumerate(values):
        _number(fail, f"{key}[{index}]", value, interval)


def _choice(fail: Fail, key: str, value: str, choices: Sequence[str], what: str = "") -> None:
    """A name that must be one of `choices` (`what` says what they are, e.g. "the objects ")."""
    if value not in choices:
        fail(key, f"expected one of {what}{list(choices)}, got {describe(value)}")


def resolve_model_path(url: str, scenario_source: str) -> Path | None:
    """The file a model URL names (package://hsr_handover/... or a path relative to the
    scenario file), or None when there is no such file."""
    prefix = "package://hsr_handover/"
    if url.startswith(prefix):
        path = MODELS_DIR / url.removeprefix(prefix)
    elif url.startswith("package://"):
        return None
    else:
        path = Path(scenario_source).parent / url
    return path if path.is_file() else None


def resolve_recording_path(path: str, scenario_source: str) -> Path | None:
    """The file or folder a recording's path names (absolute, or relative to the scenario
    file), or None when there is none."""
    resolved = Path(scenario_source).parent / path  # an absolute path stays as it is
    return resolved if path and resolved.exists() else None


def _check_robot(scenario: Scenario, fail: Fail) -> tuple[str, ...]:
    """Check the robot section; returns the model names the robot's file adds to a plant."""
    robot = scenario.robot
    path = resolve_model_path(robot.model, scenario.source)
    if path is None:
        fail("robot.model", f"expected an existing model file, got {describe(robot.model)}")
    stat = path.stat()
    try:
        models = robot_model_names(path.resolve(), stat.st_mtime_ns, stat.st_size)
    except ValueError as error:
        fail("robot.model", str(error))
    if len(robot.base_pose) != 3:
        fail("robot.base_pose", f"expected [x, y, yaw], got {describe(robot.base_pose)}")
    _numbers(fail, "robot.base_pose", robot.base_pose[:2], ROOM)
    _number(fail, "robot.base_pose[2]", robot.base_pose[2], YAW)
    for name, value in robot.joints.items():
        # Each joint's own limits are checked against the model when the station is built.
        _number(fail, f"robot.joints.{name}", value, JOINT)
    return models


@contextmanager
def _quiet_drake() -> Iterator[None]:
    """Silence Drake's parser warnings: a broken file gets one error line, not a log."""
    logger = logging.getLogger("drake")
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(level)


@functools.lru_cache(maxsize=8)
def robot_model_names(path: Path, mtime_ns: int, size: int) -> tuple[str, ...]:
    """The model instance names a plant holds after adding the robot model at `path` the way
    the station does (Drake's own instances included). Raises ValueError saying what was
    expected when the file does not parse or lacks the HSR's joints or camera frame.

    Cached by path, modification time and size: validate and run load the same file twice.
    """
    del mtime_ns, size  # the cache key only
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=0.0)
    try:
        with _quiet_drake():
            robot = add_hsr(plant, Parser(plant), path)
            plant.Finalize()  # actuators are indexed per model instance only then
    except (RuntimeError, ValueError) as error:
        reason = first_line(error).removeprefix("error: ")
        raise ValueError(f"expected one SDF or URDF model that Drake parses ({reason})") from None
    actuated = set(actuated_joint_names(plant, robot))
    missing = [name for name in HSR_ACTUATED_JOINTS if name not in actuated]
    missing += [name for name in HSR_MIMIC_JOINTS if not plant.HasJointNamed(name, robot)]
    missing += [] if plant.HasFrameNamed(CAMERA_FRAME, robot) else [CAMERA_FRAME]
    if missing:
        raise ValueError(f"expected the HSR's joints and camera frame; {missing[0]} is missing")
    instances = map(ModelInstanceIndex, range(plant.num_model_instances()))
    return tuple(plant.GetModelInstanceName(instance) for instance in instances)


def _check_simulation(scenario: Scenario, fail: Fail) -> None:
    sim = scenario.simulation
    _number(fail, "simulation.duration", sim.duration, DURATION)
    # Below 0.1 ms an hour-long run would take days; above 10 ms contact is not stable.
    _number(fail, "simulation.time_step", sim.time_step, Interval(1e-4, 0.01, "s"))
    _number(fail, "simulation.seed", sim.seed, SEED)
    _number(fail, "simulation.replay_fps", sim.replay_fps, RATE)


def _check_camera(scenario: Scenario, fail: Fail) -> None:
    camera = scenario.camera
    pixels = Interval(16, 4096, "px", integer=True)
    _number(fail, "camera.width", camera.width, pixels)
    _number(fail, "camera.height", camera.height, pixels)
    _number(fail, "camera.rate_hz", camera.rate_hz, Interval(SLOWEST_CAMERA, RATE.high, "Hz"))
    _number(fail, "camera.fov_x", camera.fov_x, Interval(0, math.pi, "rad", True, True))
    near_far = camera.depth_range
    _numbers(fail, "camera.depth_range", near_far, Interval(0, 20, "m", True), "[near, far]")
    if not near_far[0] < near_far[1]:
        fail("camera.depth_range", f"expected [near, far] with near < far, got {near_far}")
    if camera.intrinsics:
        key = "camera.intrinsics"
        _numbers(fail, key, camera.intrinsics, Interval(0, 1e5, "px", True), "[fx, fy, cx, cy]")
        _, _, cx, cy = camera.intrinsics
        if not (0 <= cx < camera.width and 0 <= cy < camera.height):
            fail(key, f"expected the principal point (cx, cy) inside the image, got {[cx, cy]}")


def _check_table(scenario: Scenario, fail: Fail) -> None:
    table = scenario.table
    _numbers(fail, "table.center", table.center, ROOM, "[x, y]")
    _number(fail, "table.yaw", table.yaw, YAW)
    _numbers(fail, "table.size", table.size, Interval(SMALLEST_TABLE, 5, "m"), "[depth, width]")
    _number(fail, "table.height", table.height, Interval(0.3, 1.2, "m"))
    if not 0 < table.thickness < table.height:
        fail("table.thickness", f"expected 0 < thickness < height, got {table.thickness}")


def _check_objects(scenario: Scenario, robot_models: tuple[str, ...], fail: Fail) -> None:
    taken = [*robot_models, *WORLD_MODELS, "world"]  # model names must be unique in a plant
    names, colors = set(), set()
    for index, obj in enumerate(scenario.objects):
        key = f"objects[{index}]"
        _check_object(obj, key, fail)
        if obj.name in taken or obj.name.startswith("__"):  # SDFormat reserves __*__ names
            expected = f"a name other than {taken} and __*"
            fail(f"{key}.name", f"expected {expected}, got {obj.name!r}")
        if obj.name in names:
            fail(f"{key}.name", f"expected a unique name, {obj.name!r} is used twice")
        if obj.color in colors:
            fail(f"{key}.color", f"expected a colour no other object has, {obj.color!r} is taken")
        names.add(obj.name)
        colors.add(obj.color)
        _check_resting(scenario, obj, key, fail)
    for (i, a), (j, b) in itertools.combinations(enumerate(scenario.objects), 2):
        if footprints_overlap(a, b):
            fail(f"objects[{j}].position", f"expected no overlap with objects[{i}] ({a.name})")


def _check_object(obj: ObjectConfig, key: str, fail: Fail) -> None:
    if not _is_model_name(obj.name):
        expected = f"a name of at most {MAX_NAME_LENGTH} letters, digits and _"
        fail(f"{key}.name", f"expected {expected}, got {describe(obj.name)}")
    _choice(fail, f"{key}.shape", obj.shape, sorted(OBJECT_SHAPES))
    layout = "[diameter, height]" if obj.shape == "cup" else "[x, y, z]"
    _numbers(fail, f"{key}.size", obj.size, Interval(SMALLEST_OBJECT, 0.5, "m"), layout)
    if min(obj.size[:2]) > GRIPPER_MAX_WIDTH:
        fail(f"{key}.size", f"expected a side at most {GRIPPER_MAX_WIDTH} m for the gripper")
    _choice(fail, f"{key}.color", obj.color, sorted(OBJECT_COLORS))
    _number(fail, f"{key}.mass", obj.mass, Interval(LIGHTEST_OBJECT, PAYLOAD, "kg"))
    if len(obj.position) not in (2, 3):
        fail(f"{key}.position", f"expected [x, y] or [x, y, z], got {describe(obj.position)}")
    _numbers(fail, f"{key}.position", obj.position, ROOM)
    _number(fail, f"{key}.yaw", obj.yaw, YAW)


def _is_model_name(name: str) -> bool:
    """ASCII letters, digits and _: a name that fits SDFormat, Meshcat paths and messages."""
    return name.isascii() and name.isidentifier() and len(name) <= MAX_NAME_LENGTH


def object_center(scenario: Scenario, obj: ObjectConfig) -> np.ndarray:
    """Where the object's centre is when it rests on the table top at its [x, y]."""
    z = scenario.table.height + object_height(obj.shape, obj.size) / 2
    return np.array([obj.position[0], obj.position[1], z])


def _check_resting(scenario: Scenario, obj: ObjectConfig, key: str, fail: Fail) -> None:
    resting_z = object_center(scenario, obj)[2]
    if len(obj.position) == 3 and abs(obj.position[2] - resting_z) > REST_TOLERANCE:
        fail(f"{key}.position", f"expected z = {resting_z:.3f} m to rest on the table top")
    table = scenario.table
    corners = _footprint_corners(obj) - np.asarray(table.center)
    local = corners @ _rotation(table.yaw)  # rows rotated into the table frame
    half = np.asarray(table.size) / 2
    if np.any(np.abs(local) > half + 1e-9):
        fail(f"{key}.position", "expected the object's footprint inside the table top")


def _rotation(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def _footprint_corners(obj: ObjectConfig, samples: int = 32) -> np.ndarray:
    """Footprint outline on the floor plane: a box's four corners, or points on a cup's rim."""
    center = np.asarray(obj.position[:2], dtype=float)
    if obj.shape == "cup":
        angles = np.linspace(0, 2 * np.pi, samples, endpoint=False)
        return center + obj.size[0] / 2 * np.stack([np.cos(angles), np.sin(angles)], 1)
    half = np.array(obj.size[:2]) / 2
    signs = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]])
    return center + (signs * half) @ _rotation(obj.yaw).T


def footprints_overlap(a: ObjectConfig, b: ObjectConfig) -> bool:
    """Separating-axis test on the two footprints (a cup's rim sampled finely enough that the
    error is under a millimetre for cup-sized discs)."""
    pa, pb = _footprint_corners(a, 64), _footprint_corners(b, 64)
    for poly in (pa, pb):
        edges = np.roll(poly, -1, axis=0) - poly
        normals = np.stack([-edges[:, 1], edges[:, 0]], 1)
        for normal in normals:
            proj_a, proj_b = pa @ normal, pb @ normal
            if proj_a.max() <= proj_b.min() or proj_b.max() <= proj_a.min():
                return False
    return True


def _check_time_order(fail: Fail, key: str, starts: list[float]) -> None:
    """A script's entries start within TIME, in non-decreasing order."""
    previous = 0.0
    for index, start in enumerate(starts):
        _number(fail, f"{key}[{index}].start", start, TIME)
        if start < previous:
            fail(
                f"{key}[{index}].start", f"expected a time >= {previous} s (entries in time order)"
            )
        previous = start


def _check_person(scenario: Scenario, fail: Fail) -> None:
    person = scenario.person
    _numbers(fail, "person.position", person.position, ROOM, "[x, y]")
    _number(fail, "person.yaw", person.yaw, YAW)
    _number(fail, "person.height", person.height, Interval(1.2, 2.1, "m, an adult"))
    _choice(fail, "person.posture", person.posture, ("seated", "standing"))
    _number(fail, "person.seat_height", person.seat_height, Interval(0.3, 0.9, "m"))
    _number(fail, "person.receiving.reaction_s", person.receiving.reaction_s, Interval(0, 10, "s"))
    _choice(fail, "person.receiving.arm", person.receiving.arm, ("right", "left"))
    _number(fail, "person.receiving.repeat_after_s", person.receiving.repeat_after_s,
            Interval(0.5, 30, "s"))  # fmt: skip
    names = sorted(obj.name for obj in scenario.objects)
    _check_time_order(fail, "person.behavior", [action.start for action in person.behavior])
    for index, action in enumerate(person.behavior):
        key = f"person.behavior[{index}]"
        _choice(fail, f"{key}.action", action.action, ACTIONS)
        if action.duration is not None:
            _number(fail, f"{key}.duration", action.duration, DURATION)
        _choice(fail, f"{key}.arm", action.arm, ("right", "left"))
        if action.action in ("look_at", "point_at"):
            _choice(fail, f"{key}.target", action.target, names, "the objects ")
        layout = f"[x, y, z] for {action.action}" if action.action in REACHES else ""
        _numbers(fail, f"{key}.point", action.point, ROOM, layout)


def _check_detector(scenario: Scenario, fail: Fail) -> None:
    """The detector's scale and fields in their ranges; DetectorModel names the field."""
    detector = scenario.perception.detector
    _number(fail, "perception.detector.scale", detector.scale, Interval(0, 10, "factor"))
    try:
        detector.model()
    except ValueError as error:
        field_name, _, expected = str(error).partition(": ")
        fail(f"perception.detector.{field_name}", expected)


def _check_intent(scenario: Scenario, fail: Fail) -> None:
    """Each field in its range (NaN included); IntentParams names the field its message is
    about."""
    try:
        scenario.intent.params()
    except ValueError as error:
        field_name, _, expected = str(error).partition(": ")
        fail(f"intent.{field_name}", expected)


def _check_imprecision(scenario: Scenario, fail: Fail) -> None:
    imprecision, key = scenario.person.imprecision, "person.imprecision"
    _number(
        fail, f"{key}.pointing_error_deg", imprecision.pointing_error_deg, Interval(0, 45, "deg")
    )
    _number(fail, f"{key}.head_turn_fraction", imprecision.head_turn_fraction, Interval(0.3, 1))
    _number(
        fail, f"{key}.head_turn_fraction_sd", imprecision.head_turn_fraction_sd, Interval(0, 0.5)
    )


def _check_variation(scenario: Scenario, fail: Fail) -> None:
    variation, key = scenario.person.variation, "person.variation"
    _number(fail, f"{key}.height_sd", variation.height_sd, Interval(0, 0.2, "m"))
    _number(fail, f"{key}.position_sd", variation.position_sd, Interval(0, 0.3, "m"))
    _number(fail, f"{key}.yaw_sd_deg", variation.yaw_sd_deg, Interval(0, 30, "deg"))
    spans = ("onset_s", "look_lead_s", "point_duration_s", "reaction_s", "hold_out_delay_s")
    for name in spans:
        span = getattr(variation, name)
        _numbers(fail, f"{key}.{name}", span, Interval(0, 60, "s"), "[low, high]")
        if span[0] > span[1]:
            fail(f"{key}.{name}", f"expected low <= high, got {span}")
    for name in ("left_arm_probability", "hold_out_probability"):
        _number(fail, f"{key}.{name}", getattr(variation, name), Interval(0, 1))
    _number(fail, f"{key}.hold_out_sd", variation.hold_out_sd, Interval(0, 0.2, "m"))


def _check_layouts(scenario: Scenario, fail: Fail) -> None:
    """Each range [low, high] inside the default's (a scenario may only narrow them)."""
    layouts, defaults = scenario.layouts, LayoutsConfig()
    for name in ("standing_probability", "staggered_probability"):
        _number(fail, f"layouts.{name}", getattr(layouts, name), Interval(0, 1))
    for spec in dataclasses.fields(LayoutsConfig):
        span, default = getattr(layouts, spec.name), getattr(defaults, spec.name)
        if not isinstance(default, list):
            continue
        outer = Interval(*default, integer=isinstance(default[0], int))
        _numbers(fail, f"layouts.{spec.name}", span, outer, "[low, high]")
        if span[0] > span[1]:
            fail(f"layouts.{spec.name}", f"expected low <= high, got {span}")


def _check_perception(scenario: Scenario, fail: Fail) -> None:
    perception = scenario.perception
    size = Interval(8, 1024, "px", integer=True)
    _numbers(fail, "perception.cloud_size", perception.cloud_size, size, "[width, height]")
    box = perception.workspace
    _numbers(fail, "perception.workspace", box, ROOM, "[x, y, z lower, x, y, z upper]")
    if not all(lo < hi for lo, hi in zip(box[:3], box[3:], strict=True)):
        fail("perception.workspace", f"expected each lower bound below its upper, got {box}")
    _number(fail, "perception.signals_per_frame", perception.signals_per_frame, COUNT)
    weight = Interval(1, 1e4, "sampling weight")
    _number(fail, "perception.attention_weight", perception.attention_weight, weight)
    _check_detector(scenario, fail)
    _check_gng(scenario, fail)
    _check_skeleton_recording(scenario, fail)
    names = sorted(obj.name for obj in scenario.objects)
    _check_time_order(
        fail, "perception.attention", [change.start for change in perception.attention]
    )
    for index, change in enumerate(perception.attention):
        key = f"perception.attention[{index}]"
        _choice(fail, f"{key}.focus", change.focus, FOCUS_KINDS)
        if change.focus == "object":
            _choice(fail, f"{key}.target", change.target, names, "the objects ")


def _check_gng(scenario: Scenario, fail: Fail) -> None:
    """The scene GNG's parameters, here rather than when the GNG is built, so a bad one costs
    no world building and the error names its key."""
    gng = scenario.perception.gng
    key = "perception.gng"
    _number(fail, f"{key}.max_nodes", gng.max_nodes, Interval(3, 5000, integer=True))
    _number(fail, f"{key}.lam", gng.lam, COUNT)
    _number(fail, f"{key}.mu1", gng.mu1, UNIT_RATE)
    _number(fail, f"{key}.mu2", gng.mu2, UNIT_RATE)
    _number(fail, f"{key}.mu3", gng.mu3, Interval(0, 1e6, "1/m"))
    _number(fail, f"{key}.a_max", gng.a_max, COUNT)
    _number(fail, f"{key}.alpha", gng.alpha, FRACTION)
    _number(fail, f"{key}.beta", gng.beta, FRACTION)
    _number(fail, f"{key}.e_min", gng.e_min, Interval(0, 1e6, "m^2"))


def _check_skeleton_recording(scenario: Scenario, fail: Fail) -> None:
    """The recording's settings; its files are read, and checked, when the station is built."""
    recording, key = scenario.perception.skeleton_recording, "perception.skeleton_recording"
    if recording is None:
        return
    if resolve_recording_path(recording.path, scenario.source) is None:
        expected = "an existing OpenPose JSON file or folder (relative to the scenario file)"
        fail(f"{key}.path", f"expected {expected}, got {describe(recording.path)}")
    _number(fail, f"{key}.frame_rate_hz", recording.frame_rate_hz, RATE)
    _choice(fail, f"{key}.model", recording.model, MODEL_CHOICES)
    _choice(fail, f"{key}.keypoint_scale", recording.keypoint_scale, KEYPOINT_SCALES)
    if recording.near_px:
        _numbers(fail, f"{key}.near_px", recording.near_px, Interval(-1e5, 1e5, "px"), "[u, v]")
