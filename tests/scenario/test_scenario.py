"""Scenario files: the bundled ones validate; each class of broken file gets its own one-line
error naming the file, the key path and what was expected, with exit status 2."""

from __future__ import annotations

import math

import pytest

from hsr_handover.cli import main
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.scenario import CameraConfig, load_scenario
from hsr_handover.scenario.schema import MAX_KEY_PATH
from hsr_handover.scenario.strict_yaml import MAX_DEPTH
from tests.paths import SCENARIOS, bundled_scenarios

MAX_ERROR_LINE = 300


@pytest.mark.parametrize("path", bundled_scenarios(), ids=lambda p: p.name)
def test_bundled_scenario_validates(path, capsys):
    assert main(["validate", str(path)]) == 0
    assert capsys.readouterr().out.startswith(f"ok: {path}")


def test_bundled_left_center_right_differ_as_the_person_sees_them():
    targets = {}
    for name in ("point_left", "point_center", "point_right"):
        scenario = load_scenario(f"scenarios/{name}.yaml")
        target = scenario.person.behavior[-1].target
        targets[name] = next(o for o in scenario.objects if o.name == target).position[1]
        gaps = sorted(o.position[1] for o in scenario.objects)
        assert all(0.20 <= b - a <= 0.25 for a, b in zip(gaps, gaps[1:], strict=False))
    # The person faces -x, so their left is world -y.
    assert targets["point_left"] < targets["point_center"] < targets["point_right"]


def _set(path: str, value):
    """A mutation that sets data[a][b]... = value for a dotted path with [i] indices."""

    def mutate(data):
        keys = path.replace("[", ".").replace("]", "").split(".")
        node = data
        for key in keys[:-1]:
            node = node[int(key)] if key.isdigit() else node.setdefault(key, {})
        last = keys[-1]
        node[int(last) if last.isdigit() else last] = value

    return mutate


BROKEN = {
    "unknown key": (_set("table.colour", "red"), "table.colour", "unknown key"),
    "wrong type (list)": (_set("objects[1].size", "big"), "objects[1].size", "expected a list"),
    "wrong type (scalar)": (
        _set("simulation.duration", "long"),
        "simulation.duration",
        "expected float",
    ),
    "missing model file": (
        _set("robot.model", "models/none.sdf"),
        "robot.model",
        "existing model file",
    ),
    "object of a femtogram": (
        _set("objects[0].mass", 1e-15),
        "objects[0].mass",
        "expected a number in [0.001, 1.2] (kg), got 1e-15",
    ),
    "object beyond the payload": (
        _set("objects[0].mass", 1.5),
        "objects[0].mass",
        "expected a number in [0.001, 1.2] (kg), got 1.5",
    ),
    "object floating": (
        _set("objects[0].position", [0.8, -0.22, 0.9]),
        "objects[0].position",
        "rest on the table top",
    ),
    "object off the table": (
        _set("objects[0].position", [2.5, 0.0]),
        "objects[0].position",
        "inside the table top",
    ),
    "overlapping objects": (
        _set("objects[1].position", [0.81, -0.19]),
        "objects[1].position",
        "no overlap with objects[0]",
    ),
    "unknown object in action": (
        _set("person.behavior[1].target", "teapot"),
        "person.behavior[1].target",
        "expected one of the objects",
    ),
    "zero action duration": (
        _set("person.behavior[1].duration", 0),
        "person.behavior[1].duration",
        "expected a number in (0, 3600] (s), got 0",
    ),
    "actions out of order": (
        _set("person.behavior[1].start", 0.1),
        "person.behavior[1].start",
        "in time order",
    ),
    "negative sim duration": (
        _set("simulation.duration", -1.0),
        "simulation.duration",
        "expected a number in (0, 3600] (s), got -1.0",
    ),
    "person in the table": (
        _set("person.position", [1.15, 0.0]),
        "person.position",
        "the person clear of the table",
    ),
    "robot in the table": (
        _set("robot.base_pose", [0.6, 0.0, 0.0]),
        "robot.base_pose",
        "the robot clear of the table",
    ),
    "unknown robot joint": (
        _set("robot.joints", {"elbow_joint": 0.1}),
        "robot.joints.elbow_joint",
        "joint name",
    ),
    "coupled robot joint": (
        _set("robot.joints", {"torso_lift_joint": 0.1}),
        "robot.joints.torso_lift_joint",
        "follows its partner by mimic",
    ),
    "robot joint beyond limit": (
        _set("robot.joints", {"arm_lift_joint": 0.9}),
        "robot.joints.arm_lift_joint",
        "value in [0, 0.69]",
    ),
    # Once a Drake or Python failure with exit status 1:
    "object named like the table": (
        _set("objects[2].name", "table"),
        "objects[2].name",
        "expected a name other than [",
    ),
    "object named like the robot model": (
        _set("objects[2].name", "hsrb"),
        "objects[2].name",
        "'hsrb', 'table', 'person', 'world'] and __*, got 'hsrb'",
    ),
    "object named like a name SDFormat reserves": (
        _set("objects[2].name", "__model__"),
        "objects[2].name",
        "and __*, got '__model__'",
    ),
    "robot model file that is not a model": (
        _set("robot.model", "scenario.yaml"),
        "robot.model",
        "expected one SDF or URDF model that Drake parses",
    ),
    "robot model without the HSR's joints": (
        _set("robot.model", "box.sdf"),
        "robot.model",
        "expected the HSR's joints and camera frame; base_x_joint is missing",
    ),
    "NaN in the robot's base pose": (
        _set("robot.base_pose", [math.nan, 0.0, 0.0]),
        "robot.base_pose[0]",
        "expected a number in [-20, 20] (m), got nan",
    ),
    "infinite person position": (
        _set("person.position", [math.inf, 0.0]),
        "person.position[0]",
        "expected a number in [-20, 20] (m), got inf",
    ),
    "NaN table centre": (
        _set("table.center", [0.85, math.nan]),
        "table.center[1]",
        "expected a number in [-20, 20] (m), got nan",
    ),
    "NaN cup height": (
        _set("objects[0].size", [0.07, math.nan]),
        "objects[0].size[1]",
        "expected a number in [0.01, 0.5] (m), got nan",
    ),
    "joint name that is not a string": (
        _set("robot.joints", {1: 0.3}),
        "robot.joints.1",
        "expected a str key, got int 1",
    ),
    # Once accepted although broken:
    "negative seed": (
        _set("simulation.seed", -1),
        "simulation.seed",
        "expected an integer in [0, 4294967295], got -1",
    ),
    "seed beyond 32 bits": (
        _set("simulation.seed", 2**32),
        "simulation.seed",
        "got 4294967296",
    ),
    "a camera too slow to perceive with": (
        _set("camera.rate_hz", 1e-300),
        "camera.rate_hz",
        "expected a number in [1, 120] (Hz), got 1e-300",
    ),
    "an object of micrometres": (
        _set("objects[0].size", [1e-6, 0.1]),
        "objects[0].size[0]",
        "expected a number in [0.01, 0.5] (m), got 1e-06",
    ),
    "a table too small for an object and a hand": (
        _set("table.size", [0.6, 0.05]),
        "table.size[1]",
        "expected a number in [0.2, 5] (m), got 0.05",
    ),
    "camera rate without end": (
        _set("camera.rate_hz", 1e308),
        "camera.rate_hz",
        "expected a number in [1, 120] (Hz), got 1e+308",
    ),
    "a seat no one sits on": (
        _set("person.seat_height", 1.5),
        "person.seat_height",
        "expected a number in [0.3, 0.9] (m), got 1.5",
    ),
    "camera intrinsics short of four": (
        _set("camera.intrinsics", [500.0, 500.0, 320.0]),
        "camera.intrinsics",
        "expected [fx, fy, cx, cy]",
    ),
    "principal point outside the image": (
        _set("camera.intrinsics", [500.0, 500.0, 700.0, 240.0]),
        "camera.intrinsics",
        "expected the principal point (cx, cy) inside the image, got [700.0, 240.0]",
    ),
    "NaN object height": (
        _set("objects[0].position", [0.8, -0.22, math.nan]),
        "objects[0].position[2]",
        "got nan",
    ),
    "huge simulation duration": (
        _set("simulation.duration", 1e308),
        "simulation.duration",
        "got 1e+308",
    ),
    "huge action duration": (
        _set("person.behavior[1].duration", 1e308),
        "person.behavior[1].duration",
        "(0, 3600] (s), got 1e+308",
    ),
    "huge yaw": (
        _set("table.yaw", 1e308),
        "table.yaw",
        "expected a number in [-6.28319, 6.28319] (rad), got 1e+308",
    ),
    "huge object yaw": (_set("objects[1].yaw", -1e308), "objects[1].yaw", "(rad), got -1e+308"),
    "GNG learning rate of 0": (
        _set("perception.gng.mu1", 0.0),
        "perception.gng.mu1",
        "expected a number in (0, 1], got 0.0",
    ),
    "GNG with too few nodes": (
        _set("perception.gng.max_nodes", 2),
        "perception.gng.max_nodes",
        "expected an integer in [3, 5000], got 2",
    ),
    "unknown detector preset": (
        _set("perception.detector.preset", "openpose"),
        "perception.detector.preset",
        "expected one of ['realistic', 'ideal'], got 'openpose'",
    ),
    "detector bias share above 1": (
        _set("perception.detector.bias_share", 1.5),
        "perception.detector.bias_share",
        "expected in [0, 1], got 1.5",
    ),
    "detector miss rates not four": (
        _set("perception.detector.miss_rate", [0.1, 0.1]),
        "perception.detector.miss_rate",
        "expected 4 rates",
    ),
    "detector scale of 20": (
        _set("perception.detector.scale", 20.0),
        "perception.detector.scale",
        "in [0, 10]",
    ),
    "the old pixel_sigma key": (
        _set("perception.pixel_sigma", 1.0),
        "perception.pixel_sigma",
        "unknown key",
    ),
    "base pose beyond the room": (
        _set("robot.base_pose", [150.0, 0.0, 0.0]),
        "robot.base_pose[0]",
        "got 150.0",
    ),
    "list of 1,000 items echoed": (
        _set("table.center", [0.5] * 1000),
        "table.center",
        "expected [x, y], got a list of 1000 items",
    ),
    "long string echoed": (
        _set("objects[0].color", "r" * 100_000),
        "objects[0].color",
        "(100000 characters)",
    ),
    "repeat after no time": (
        _set("person.receiving", {"repeats": True, "repeat_after_s": 0.0}),
        "person.receiving.repeat_after_s",
        "expected a number in [0.5, 30] (s), got 0.0",
    ),
    "source set in the file": (_set("source", "x.yaml"), "source", "unknown key"),
    "long unknown key": (
        _set("table." + "k" * 10_000, 1),
        "table." + "k" * (MAX_KEY_PATH - 7) + "…",
        "unknown key",
    ),
}


@pytest.fixture
def box_model(tmp_path):
    """A model file beside the written scenario that parses but is no HSR."""
    sdf = '<?xml version="1.0"?><sdf version="1.9"><model name="box"><link name="b"/></model></sdf>'
    (tmp_path / "box.sdf").write_text(sdf)


def assert_one_error_line(capsys, path, key_path: str, phrase: str) -> None:
    """Exactly one short line on stderr, `error: FILE: KEY: ...` holding `phrase`."""
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err[:1000]
    assert lines[0].startswith(f"error: {path}: {key_path}: "), lines[0][:1000]
    assert phrase in lines[0]
    assert len(lines[0]) < MAX_ERROR_LINE, lines[0]


@pytest.mark.usefixtures("box_model")
@pytest.mark.parametrize("case", list(BROKEN), ids=list(BROKEN))
def test_broken_scenario_gets_one_line_naming_file_key_and_expectation(
    case, write_scenario, capsys
):
    mutate, key_path, phrase = BROKEN[case]
    path = write_scenario(mutate)
    assert main(["validate", str(path)]) == 2
    assert_one_error_line(capsys, path, key_path, phrase)


POINT_LEFT = (SCENARIOS / "point_left.yaml").read_text()
DURATION_LINE = "  duration: 5.0\n"
assert DURATION_LINE in POINT_LEFT


def _replace(old: str, new: str) -> bytes:
    return POINT_LEFT.replace(old, new, 1).encode()


RAW_BROKEN = {
    "bytes that are not UTF-8": (
        POINT_LEFT.encode().replace(b"paper", b"pap\xff", 1),
        "(file)",
        "expected UTF-8 text; line 1 is not",
    ),
    "control character": (
        _replace(DURATION_LINE, "  duration: 5\x00\n"),
        "line 6, column 14",
        "expected valid YAML (control characters are not allowed)",
    ),
    "a tab after a key's colon": (
        _replace(DURATION_LINE, "  duration:\t5.0\n"),
        "line 6, column 12",
        "expected valid YAML (found character '\\t' that cannot start any token)",
    ),
    "a tab indenting a key": (
        _replace(DURATION_LINE, "\tduration: 5.0\n"),
        "line 6, column 1",
        "expected valid YAML (found character that cannot start any token)",
    ),
    "a stray character": (
        _replace(DURATION_LINE, "  duration: `5.0\n"),
        "line 6, column 13",
        "expected valid YAML (found character that cannot start any token)",
    ),
    "an unclosed quote": (
        _replace(DURATION_LINE, '  duration: "5.0\n'),
        f"line {POINT_LEFT.count(chr(10)) + 1}, column 1",
        "(found unexpected end of stream, while scanning a quoted scalar begun at line 6, "
        "column 13)",
    ),
    "an unclosed flow sequence": (
        _replace("center: [0.85, 0.0]", "center: [0.85, 0.0"),
        "line 11, column 7",
        "while parsing a flow sequence begun at line 10, column 11",
    ),
    "empty file": (b"", "(file)", "expected a mapping of scenario sections"),
    "comment-only file": (b"# to do\n", "(file)", "expected a mapping of scenario sections"),
    "lists nested a thousand deep": (
        _replace(DURATION_LINE, f"  duration: {'[' * 1000}{']' * 1000}\n"),
        "simulation.duration" + "[0]" * (MAX_DEPTH - 2),
        f"expected at most {MAX_DEPTH} nested levels",
    ),
    "integer of 5,000 digits": (
        _replace(DURATION_LINE, f"  duration: {'9' * 5000}\n"),
        "simulation.duration",
        "expected a number of at most 100 digits, got 5000",
    ),
    "duplicate key": (
        _replace(DURATION_LINE, DURATION_LINE + "  duration: 50.0\n"),
        "simulation.duration",
        "expected each key once; this one repeats",
    ),
    "duplicate key in a flow mapping": (
        _replace("color: red,", "color: red, color: blue,"),
        "objects[0].color",
        "expected each key once",
    ),
    "duplicate section": (
        (POINT_LEFT + "simulation: {duration: 2.0}\n").encode(),
        "simulation",
        "expected each key once",
    ),
    "list of 100,000 items": (
        _replace("center: [0.85, 0.0]", f"center: [{'0.5, ' * 100_000}0.5]"),
        "table.center",
        "expected at most 1000 entries",
    ),
    "tagged value that does not construct": (
        _replace(DURATION_LINE, DURATION_LINE + "  seed: !!int abc\n"),
        "simulation.seed",
        "expected a valid int",
    ),
}


@pytest.mark.parametrize("case", list(RAW_BROKEN), ids=list(RAW_BROKEN))
def test_broken_file_text_gets_one_line_naming_the_key(case, tmp_path, capsys):
    text, key_path, phrase = RAW_BROKEN[case]
    path = tmp_path / "scenario.yaml"
    path.write_bytes(text)
    assert main(["validate", str(path)]) == 2
    assert_one_error_line(capsys, path, key_path, phrase)


def test_merge_keys_may_override_and_yaml_12_floats_are_numbers(tmp_path):
    text = _replace(DURATION_LINE, "  <<: {duration: 5.0}\n  duration: 4.0\n  time_step: 2e-3\n")
    path = tmp_path / "scenario.yaml"
    path.write_bytes(text)
    simulation = load_scenario(path).simulation
    assert (simulation.duration, simulation.time_step) == (4.0, 0.002)


@pytest.mark.usefixtures("box_model")
def test_each_broken_class_has_its_own_message(write_scenario, capsys):
    messages = set()
    for mutate, _, _ in BROKEN.values():
        main(["validate", str(write_scenario(mutate))])
        messages.add(capsys.readouterr().err.split(": ", 2)[-1])
    assert len(messages) == len(BROKEN)


def test_missing_and_unparsable_files(tmp_path, capsys):
    assert main(["validate", str(tmp_path / "absent.yaml")]) == 2
    assert "expected an existing scenario YAML file" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text("table: {center: [1, 2\n")
    assert main(["validate", str(bad)]) == 2
    assert "expected valid YAML" in capsys.readouterr().err


def test_run_on_broken_scenario_writes_no_replay(write_scenario, tmp_path, capsys):
    path = write_scenario(_set("objects[0].color", "chartreuse"))
    out = tmp_path / "replay.html"
    assert main(["run", str(path), "--html", str(out)]) == 2
    assert "objects[0].color" in capsys.readouterr().err
    assert not out.exists()


def test_bad_cli_arguments_are_one_line_errors(write_scenario, tmp_path, capsys):
    path = write_scenario()
    assert main(["run", str(path), "--duration", "0", "--html", str(tmp_path / "a.html")]) == 2
    assert "--duration: expected a number in (0, 3600]" in capsys.readouterr().err
    assert main(["run", str(path), "--html", str(tmp_path / "missing" / "a.html")]) == 2
    assert "--html: expected an existing directory" in capsys.readouterr().err
    (tmp_path / "taken.html").mkdir()  # checked before the run, not after it
    assert main(["run", str(path), "--html", str(tmp_path / "taken.html")]) == 2
    assert "--html: expected a file to write" in capsys.readouterr().err
    assert not (tmp_path / "a.html").exists()


def test_attention_needs_a_schedule_and_checks_outputs_before_running(
    write_scenario, tmp_path, capsys
):
    path = write_scenario()
    assert main(["attention", str(path), "--json", str(tmp_path / "a.json")]) == 2
    assert "perception.attention: expected a focus schedule" in capsys.readouterr().err

    def schedule(data):
        data["perception"] = {"attention": [{"start": 0.0, "focus": "face"}]}

    path = write_scenario(schedule)
    assert main(["attention", str(path), "--plot", str(tmp_path / "a.jpg")]) == 2
    assert "--plot: expected a path ending in .png or .svg or .pdf" in capsys.readouterr().err
    (tmp_path / "figure.svg").mkdir()
    assert main(["attention", str(path), "--plot", str(tmp_path / "figure.svg")]) == 2
    assert "--plot: expected a file to write" in capsys.readouterr().err
    assert not list(tmp_path.glob("a.*"))


def test_a_calibrated_cameras_intrinsics_replace_the_field_of_views():
    square = CameraConfig(width=320, height=240).pinhole()
    assert square.fx == square.fy and square.cx == 159.5
    calibrated = CameraConfig(width=320, height=240, intrinsics=[270.0, 268.0, 161.2, 118.9])
    assert calibrated.pinhole() == PinholeCamera(320, 240, 270.0, 268.0, 161.2, 118.9)
