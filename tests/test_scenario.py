"""Scenario files: the bundled ones validate; each class of broken file gets its own one-line
error naming the file, the key path and what was expected, with exit status 2."""

from __future__ import annotations

import pytest

from hsr_handover.cli import main
from hsr_handover.scenario import load_scenario
from tests.conftest import bundled_scenarios


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
        "positive",
    ),
    "actions out of order": (
        _set("person.behavior[1].start", 0.1),
        "person.behavior[1].start",
        "in time order",
    ),
    "negative sim duration": (_set("simulation.duration", -1.0), "simulation.duration", "positive"),
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
}


@pytest.mark.parametrize("case", list(BROKEN), ids=list(BROKEN))
def test_broken_scenario_gets_one_line_naming_file_key_and_expectation(
    case, write_scenario, capsys
):
    mutate, key_path, phrase = BROKEN[case]
    path = write_scenario(mutate)
    assert main(["validate", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"error: {path}: {key_path}: "), lines[0]
    assert phrase in lines[0]


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
    assert "--duration: expected a positive" in capsys.readouterr().err
    assert main(["run", str(path), "--html", str(tmp_path / "missing" / "a.html")]) == 2
    assert "--html: expected an existing directory" in capsys.readouterr().err
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
    assert "--plot: expected a path ending in .png" in capsys.readouterr().err
    assert not list(tmp_path.glob("a.*"))
