"""Checks of a loaded Scenario that need only its numbers (no built plant).

Each raises ScenarioError naming the key path and what was expected. Footprints on the table
top are exact for the shapes we have: cups are discs, boxes are rotated rectangles.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np

from hsr_handover.hsr import GRIPPER_MAX_OPENING, MODELS_DIR
from hsr_handover.human.behavior import ACTIONS
from hsr_handover.perception.attention import FOCUS_KINDS
from hsr_handover.perception.object_colors import OBJECT_COLORS
from hsr_handover.scenario.schema import ObjectConfig, Scenario, ScenarioError
from hsr_handover.scene.object_models import OBJECT_SHAPES, object_height

GRIPPER_MAX_WIDTH = round(
    GRIPPER_MAX_OPENING - 0.017, 3
)  # m: what the gripper closes around, with margin
PAYLOAD = 1.2  # kg
REST_TOLERANCE = 0.005  # m: how far an object's given z may be from resting on the top


def check_scenario(scenario: Scenario) -> None:
    """Raise ScenarioError at the first problem a scenario's numbers show."""
    fail = _failer(scenario.source)
    _check_simulation(scenario, fail)
    _check_camera(scenario, fail)
    _check_table(scenario, fail)
    _check_objects(scenario, fail)
    _check_person(scenario, fail)
    _check_perception(scenario, fail)
    if resolve_model_path(scenario.robot.model, scenario.source) is None:
        fail("robot.model", f"expected an existing model file, got {scenario.robot.model!r}")
    if len(scenario.robot.base_pose) != 3:
        fail("robot.base_pose", "expected [x, y, yaw]")


def _failer(source: str):
    def fail(key_path: str, expected: str):
        raise ScenarioError(source, key_path, expected)

    return fail


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


def _positive(fail, key: str, value: float) -> None:
    if not (value > 0 and math.isfinite(value)):
        fail(key, f"expected a positive number, got {value}")


def _check_simulation(scenario: Scenario, fail) -> None:
    sim = scenario.simulation
    _positive(fail, "simulation.duration", sim.duration)
    _positive(fail, "simulation.time_step", sim.time_step)
    if sim.time_step > 0.01:
        fail(
            "simulation.time_step",
            f"expected at most 0.01 s for stable contact, got {sim.time_step}",
        )
    _positive(fail, "simulation.replay_fps", sim.replay_fps)


def _check_camera(scenario: Scenario, fail) -> None:
    camera = scenario.camera
    _positive(fail, "camera.width", camera.width)
    _positive(fail, "camera.height", camera.height)
    _positive(fail, "camera.rate_hz", camera.rate_hz)
    if not 0 < camera.fov_x < math.pi:
        fail("camera.fov_x", f"expected a field of view in (0, pi) rad, got {camera.fov_x}")
    near_far = camera.depth_range
    if len(near_far) != 2 or not 0 < near_far[0] < near_far[1]:
        fail("camera.depth_range", f"expected [near, far] with 0 < near < far, got {near_far}")


def _check_table(scenario: Scenario, fail) -> None:
    table = scenario.table
    if len(table.center) != 2:
        fail("table.center", f"expected [x, y], got {table.center}")
    if len(table.size) != 2 or min(table.size) <= 0:
        fail("table.size", f"expected [depth, width] both positive, got {table.size}")
    if not 0.3 <= table.height <= 1.2:
        fail("table.height", f"expected a top height between 0.3 and 1.2 m, got {table.height}")
    if not 0 < table.thickness < table.height:
        fail("table.thickness", f"expected 0 < thickness < height, got {table.thickness}")


def _check_objects(scenario: Scenario, fail) -> None:
    names, colors = set(), set()
    for index, obj in enumerate(scenario.objects):
        key = f"objects[{index}]"
        _check_object(obj, key, fail)
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


def _check_object(obj: ObjectConfig, key: str, fail) -> None:
    if not obj.name.isidentifier():
        fail(f"{key}.name", f"expected a name of letters, digits and _, got {obj.name!r}")
    if obj.shape not in OBJECT_SHAPES:
        fail(f"{key}.shape", f"expected one of {sorted(OBJECT_SHAPES)}, got {obj.shape!r}")
    count = OBJECT_SHAPES[obj.shape]
    if len(obj.size) != count or min(obj.size) <= 0:
        fail(f"{key}.size", f"expected {count} positive sizes for a {obj.shape}, got {obj.size}")
    if min(obj.size[:2]) > GRIPPER_MAX_WIDTH:
        fail(f"{key}.size", f"expected a side at most {GRIPPER_MAX_WIDTH} m for the gripper")
    if obj.color not in OBJECT_COLORS:
        fail(f"{key}.color", f"expected one of {sorted(OBJECT_COLORS)}, got {obj.color!r}")
    if not 0 < obj.mass <= PAYLOAD:
        fail(f"{key}.mass", f"expected a mass in (0, {PAYLOAD}] kg (the payload), got {obj.mass}")
    if len(obj.position) not in (2, 3):
        fail(f"{key}.position", f"expected [x, y] or [x, y, z], got {obj.position}")


def object_center(scenario: Scenario, obj: ObjectConfig) -> np.ndarray:
    """Where the object's centre is when it rests on the table top at its [x, y]."""
    z = scenario.table.height + object_height(obj.shape, obj.size) / 2
    return np.array([obj.position[0], obj.position[1], z])


def _check_resting(scenario: Scenario, obj: ObjectConfig, key: str, fail) -> None:
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


def _check_time_order(fail, key: str, starts: list[float]) -> None:
    """A script's entries start at finite, non-negative, non-decreasing times."""
    previous = 0.0
    for index, start in enumerate(starts):
        if not (start >= previous and math.isfinite(start)):
            fail(
                f"{key}[{index}].start", f"expected a time >= {previous} s (entries in time order)"
            )
        previous = start


def _check_person(scenario: Scenario, fail) -> None:
    person = scenario.person
    if len(person.position) != 2:
        fail("person.position", f"expected [x, y], got {person.position}")
    if not 1.2 <= person.height <= 2.1:
        fail("person.height", f"expected an adult height in [1.2, 2.1] m, got {person.height}")
    if person.posture not in ("seated", "standing"):
        fail("person.posture", f"expected 'seated' or 'standing', got {person.posture!r}")
    names = {obj.name for obj in scenario.objects}
    _check_time_order(fail, "person.behavior", [action.start for action in person.behavior])
    for index, action in enumerate(person.behavior):
        key = f"person.behavior[{index}]"
        if action.action not in ACTIONS:
            fail(f"{key}.action", f"expected one of {list(ACTIONS)}, got {action.action!r}")
        if action.duration is not None:
            _positive(fail, f"{key}.duration", action.duration)
        if action.arm not in ("right", "left"):
            fail(f"{key}.arm", f"expected 'right' or 'left', got {action.arm!r}")
        if action.action in ("look_at", "point_at") and action.target not in names:
            fail(
                f"{key}.target",
                f"expected one of the objects {sorted(names)}, got {action.target!r}",
            )
        if action.action == "reach_to" and len(action.point) != 3:
            fail(f"{key}.point", f"expected [x, y, z] for reach_to, got {action.point}")


def _check_perception(scenario: Scenario, fail) -> None:
    perception = scenario.perception
    size = perception.cloud_size
    if len(size) != 2 or min(size) <= 0:
        fail("perception.cloud_size", f"expected [width, height], both positive, got {size}")
    box = perception.workspace
    if len(box) != 6 or not all(lo < hi for lo, hi in zip(box[:3], box[3:], strict=True)):
        fail("perception.workspace", f"expected [x, y, z lower, x, y, z upper], got {box}")
    _positive(fail, "perception.signals_per_frame", perception.signals_per_frame)
    if not perception.attention_weight >= 1:
        weight = perception.attention_weight
        fail("perception.attention_weight", f"expected a sampling weight >= 1, got {weight}")
    if not 0 <= perception.face_drop_probability <= 1:
        fail("perception.face_drop_probability", "expected a probability in [0, 1]")
    if not perception.pixel_sigma >= 0:
        fail("perception.pixel_sigma", f"expected sigma >= 0, got {perception.pixel_sigma}")
    names = {obj.name for obj in scenario.objects}
    _check_time_order(
        fail, "perception.attention", [change.start for change in perception.attention]
    )
    for index, change in enumerate(perception.attention):
        key = f"perception.attention[{index}]"
        if change.focus not in FOCUS_KINDS:
            fail(f"{key}.focus", f"expected one of {list(FOCUS_KINDS)}, got {change.focus!r}")
        if change.focus == "object" and change.target not in names:
            fail(
                f"{key}.target",
                f"expected one of the objects {sorted(names)}, got {change.target!r}",
            )
