"""The intent experiment: trials made reproducibly, scored as the paper scores them, and run
from the command line."""

from __future__ import annotations

import copy
import dataclasses
import json
import sys

import numpy as np
import pytest

from hsr_handover.cli import main
from hsr_handover.experiments.arm_aim import arm_aim, most_likely_asked
from hsr_handover.experiments.experiment import replay_name
from hsr_handover.experiments.intent.percepts import replay_intent
from hsr_handover.experiments.intent.report import plot, summary_lines, write_csv
from hsr_handover.experiments.intent.trial import IntentExperiment, run_intent_trial, summarise
from hsr_handover.experiments.intent.trials import DISTRACTORS, make_trials, object_positions
from hsr_handover.experiments.trials import RAY_MISSING, TrialOutcome
from hsr_handover.scenario import ImprecisionConfig, load_scenario
from tests.paths import SCENARIOS


@pytest.fixture(scope="module")
def base():
    return load_scenario(SCENARIOS / "intent_reference.yaml")


def test_objects_are_classed_from_the_persons_point_of_view(base):
    # The person faces the robot (-x): the person's left is world -y.
    assert object_positions(base) == {"red_cup": "left", "green_cup": "centre",
                                      "blue_cup": "right"}  # fmt: skip


def test_trials_cycle_targets_and_are_the_same_for_the_same_seed(base):
    trials = make_trials(base, 7, 5, seed=3)
    assert [t.target for t in trials[:7]] == ["red_cup", "green_cup", "blue_cup"] * 2 + ["red_cup"]
    assert [t.kind for t in trials[7:]] == [*DISTRACTORS, DISTRACTORS[0]]
    again = make_trials(base, 7, 5, seed=3)
    assert [t.scenario for t in again] == [t.scenario for t in trials]
    other = make_trials(base, 7, 5, seed=4)
    assert other[0].scenario.person.height != trials[0].scenario.person.height
    seeds = {t.scenario.simulation.seed for t in trials}
    assert len(seeds) == len(trials)  # every trial its own person and noise


def test_a_request_trial_looks_then_points_and_ends_after_it(base):
    (trial,) = make_trials(base, 1, 0, seed=0)
    look, point = trial.scenario.person.behavior
    assert (look.action, point.action, point.target) == ("look_at", "point_at", "red_cup")
    assert point.start == pytest.approx(trial.pointing_onset) and point.start > look.start
    assert trial.scenario.simulation.duration > point.start + point.duration
    assert trial.scenario.perception.enabled and not trial.scenario.camera.render_label
    distractors = make_trials(base, 0, 4, seed=0)
    actions = [[a.action for a in t.scenario.person.behavior] for t in distractors]
    assert actions == [["gesture"], ["touch"], ["touch"], ["look_at"]]
    assert all("point_at" not in kinds for kinds in actions)


def _outcome(index, recognised, latency=1.0, ok=True):
    result = {"index": index, "recognised": recognised, "latency_s": latency} if ok else None
    return TrialOutcome(index, ok, result, "" if ok else "ValueError: boom", 1.0)


def _outcomes(trials, recognised: list[str | None]) -> list[TrialOutcome]:
    """One outcome per trial: the name recognised ("" for none), or None for a failed trial."""
    outcomes = []
    for trial, name in zip(trials, recognised, strict=True):
        outcome = _outcome(trial.index, name, ok=name is not None)
        if outcome.ok:
            outcome.result.update(kind=trial.kind, target=trial.target, arm=trial.arm)
        outcomes.append(outcome)
    return outcomes


def test_the_summary_scores_success_by_position_false_triggers_and_failures(base, tmp_path):
    trials = make_trials(base, 6, 2, seed=1)
    recognised = ["red_cup", "green_cup", "red_cup", "red_cup", "", None, "", "blue_cup"]
    outcomes = _outcomes(trials, recognised)
    summary = summarise(IntentExperiment(trials, outcomes, base, 1, 12.0))
    assert summary["trials"] == 6 and summary["distractor_trials"] == 2
    assert summary["by_position"] == {"left": 1.0, "centre": 0.5, "right": 0.0}
    assert summary["by_object"]["red_cup"] == 1.0 and summary["success_rate"] == 3 / 6
    assert summary["confusion"]["blue_cup"] == {"red_cup": 1, "green_cup": 0, "blue_cup": 0,
                                                "none": 1}  # fmt: skip
    assert summary["false_trigger_rate"] == 0.5
    assert summary["failed_trials"] == 1 and summary["failures"][0]["error"] == "ValueError: boom"
    assert summary["latency_s"]["median"] == 1.0
    assert summary["person_model"]["imprecision"]["pointing_error_deg"] == pytest.approx(7.3)
    lines = "\n".join(summary_lines(summary))
    assert "78.3 %" in lines and "ValueError: boom" in lines
    write_csv(IntentExperiment(trials, outcomes, base, 1, 12.0).rows(), tmp_path / "t.csv")
    assert len((tmp_path / "t.csv").read_text().splitlines()) == 9
    plot(summary, tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    "arguments, expected",
    [
        (["--trials", "0"], "--trials: expected an integer in [1, 100000], got 0"),
        (["--workers", "0"], "--workers: expected an integer in [1, 1024], got 0"),
        (["--seed", "-3"], "--seed: expected an integer in [0, 4294967295], got -3"),
        (["--json", "out.txt"], "--json: expected a path ending in .json, got 'out.txt'"),
        (
            ["--plot", "out.jpg"],
            "--plot: expected a path ending in .png or .svg or .pdf, got 'out.jpg'",
        ),
        (["--plot", "."], "--plot: expected a path ending in .png or .svg or .pdf, got '.'"),
    ],
)
def test_bad_arguments_are_one_line_errors(capsys, arguments, expected):
    code = main(["experiment", "intent", str(SCENARIOS / "intent_reference.yaml"), *arguments])
    assert code == 2 and capsys.readouterr().err.strip() == f"error: {expected}"


def test_a_replay_folder_that_is_a_file_or_has_no_parent_is_a_one_line_error(capsys, tmp_path):
    scenario = str(SCENARIOS / "intent_reference.yaml")
    afile = tmp_path / "replays"
    afile.write_text("")
    for folder, expected in ((afile, "is a file"), (tmp_path / "no" / "such", "parent")):
        code = main(["experiment", "intent", scenario, "--html-dir", str(folder)])
        error = capsys.readouterr().err.strip()
        assert code == 2 and error.startswith("error: --html-dir:") and expected in error
        assert "\n" not in error
    assert not (tmp_path / "no").exists()


def test_bad_layout_options_are_one_line_errors_before_any_trial(capsys, tmp_path):
    scenario = str(SCENARIOS / "intent_reference.yaml")
    with pytest.raises(SystemExit) as raised:
        main(["experiment", "intent", scenario, "--layouts", "random"])
    error = capsys.readouterr().err.strip()
    assert raised.value.code == 2 and "--layouts" in error and "'generated'" in error
    afile = tmp_path / "layouts"
    afile.write_text("")
    code = main(["experiment", "intent", scenario, "--layouts", "generated",
                 "--scenario-dir", str(afile)])  # fmt: skip
    error = capsys.readouterr().err.strip()
    assert code == 2 and error.startswith("error: --scenario-dir:") and "is a file" in error


def test_replay_names_say_the_trial_and_its_outcome():
    assert replay_name(7, "person contact") == "trial_007_person-contact.html"
    assert replay_name(12, "Wrong object!") == "trial_012_wrong-object.html"
    assert replay_name(0, "") == "trial_000_unknown.html"


def test_a_scenario_with_one_object_has_nothing_to_choose(capsys, write_scenario):
    def one_cup(data):
        data["objects"] = data["objects"][:1]
        data["person"]["behavior"] = []

    code = main(["experiment", "intent", str(write_scenario(one_cup))])
    assert code == 2 and "objects: expected two or more" in capsys.readouterr().err


@pytest.mark.slow
def test_the_command_runs_trials_in_parallel_and_writes_its_results(tmp_path):
    outputs = {kind: tmp_path / f"intent.{kind}" for kind in ("json", "csv", "png")}
    code = main(["experiment", "intent", str(SCENARIOS / "intent_reference.yaml"),
                 "--trials", "3", "--distractors", "1", "--workers", "2",
                 "--json", str(outputs["json"]), "--csv", str(outputs["csv"]),
                 "--plot", str(outputs["png"])])  # fmt: skip
    assert code == 0
    summary = json.loads(outputs["json"].read_text())
    for key in ("trials", "success_rate", "by_position", "by_object", "false_trigger_rate",
                "latency_s", "person_model", "wall_s"):  # fmt: skip
        assert key in summary, key
    assert summary["trials"] == 3 and summary["failed_trials"] == 0
    assert 0.0 <= summary["success_rate"] <= 1.0 and summary["wall_s"] > 0


def test_one_trial_end_to_end_the_robot_names_the_cup_it_was_asked_for(base, tmp_path):
    """Station, robot and recogniser together, on one request by an exact person; the recorded
    percepts replayed offline reach the same recognition at the same time; the trial's replay
    is kept under its outcome's name."""
    exact = copy.deepcopy(base)
    exact.person.imprecision = ImprecisionConfig(0.0, 1.0, 0.0)
    (trial,) = make_trials(exact, 1, 0, seed=11)
    spec = dataclasses.replace(trial, record_percepts=True, replay_dir=str(tmp_path))
    result = run_intent_trial(spec)
    assert result["recognised"] == trial.target
    assert 0.5 <= result["latency_s"] <= 3.0
    offline = replay_intent(result["percepts"], exact.intent.params())
    assert offline.recognised_time == result["recognised_time_s"]
    assert [path.name for path in tmp_path.iterdir()] == [replay_name(0, "recognised")]


def test_a_failed_distractor_trial_does_not_lower_the_false_trigger_rate(base):
    trials = make_trials(base, 3, 2, seed=1)
    recognised = ["red_cup", "green_cup", "blue_cup", "red_cup", None]
    outcomes = _outcomes(trials, recognised)
    summary = summarise(IntentExperiment(trials, outcomes, base, 1, 12.0))
    assert summary["false_trigger_rate"] == 1.0  # one distractor ran, and it triggered
    assert summary["failed_trials"] == 1


def test_ray_address_without_ray_is_a_one_line_usage_error(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` now raises ImportError
    scenario = str(SCENARIOS / "intent_reference.yaml")
    code = main(["experiment", "intent", scenario, "--ray-address", "127.0.0.1:6379"])
    error = capsys.readouterr().err.strip()
    assert code == 2 and error == f"error: {RAY_MISSING}"


def test_an_exact_persons_arm_points_at_the_target_and_a_distractors_at_nothing(base):
    exact = copy.deepcopy(base)
    exact.person.imprecision = ImprecisionConfig(0.0, 1.0, 0.0)
    *requests, distractor = make_trials(exact, 3, 1, seed=2)
    for trial in requests:
        aim = arm_aim(trial.scenario)
        assert aim.nearest == trial.target and aim.error_deg < 1e-3
        assert aim.most_likely == trial.target
    assert arm_aim(distractor.scenario) is None


def test_the_arms_error_is_the_drawn_one_and_misaimed_requests_are_counted(base):
    """At 20 degrees' mean error most arms point nearer a neighbour (the cups are 12-14
    degrees apart from the shoulder); the summary counts them and those read right anyway."""
    sloppy = copy.deepcopy(base)
    sloppy.person.imprecision = ImprecisionConfig(20.0, 0.689, 0.08)
    trials = make_trials(sloppy, 30, 0, seed=5)
    aims = [arm_aim(trial.scenario) for trial in trials]
    assert 14.0 < sum(aim.error_deg for aim in aims) / len(aims) < 26.0
    misaimed = [aim.nearest != trial.target for aim, trial in zip(aims, trials, strict=True)]
    assert sum(misaimed) >= 10
    recognised = [trial.target if index % 2 else "" for index, trial in enumerate(trials)]
    summary = summarise(IntentExperiment(trials, _outcomes(trials, recognised), sloppy, 1, 1.0))
    arm = summary["arm_alone"]
    assert arm["misaimed"] == sum(misaimed)
    assert arm["nearest_target_rate"] == pytest.approx(1 - sum(misaimed) / 30)
    read_right = sum(m and index % 2 == 1 for index, m in enumerate(misaimed))
    assert arm["misaimed_recognised"] == read_right
    assert arm["breuer"]["targets_found"] == pytest.approx(0.866)
    assert "Breuer et al.: 86.6 %" in "\n".join(summary_lines(summary))


def test_the_face_chooses_between_objects_the_arm_points_between():
    person = ImprecisionConfig(7.3, 0.689, 0.08)
    yaws = np.radians([10.0, 30.0])
    between = np.array([6.0, 6.0])  # the arm as far from each
    for asked in (0, 1):
        assert most_likely_asked(between, 0.689 * yaws[asked], yaws, person) == asked
    # Two objects 6 degrees apart as the face turns, the face turned the usual share toward
    # the second: 2.5 sd from the first's share. An arm 16 degrees off the second (2.7 sd) and
    # on the first outweighs it; one 10 degrees off does not.
    near = np.radians([20.0, 26.0])
    face = 0.689 * near[1]
    assert most_likely_asked(np.array([0.0, 16.0]), face, near, person) == 0
    assert most_likely_asked(np.array([0.0, 10.0]), face, near, person) == 1


def test_the_cue_limit_counts_requests_whose_arm_and_face_asked_for_another(base):
    """At 20 degrees' mean error and a head share spread of 0.3, some gestures together ask
    for a neighbour; the summary counts them and those read right anyway."""
    sloppy = copy.deepcopy(base)
    sloppy.person.imprecision = ImprecisionConfig(20.0, 0.689, 0.3)
    trials = make_trials(sloppy, 30, 0, seed=5)
    likely = [arm_aim(trial.scenario).most_likely for trial in trials]
    astray = [name != trial.target for name, trial in zip(likely, trials, strict=True)]
    assert 0 < sum(astray) < 30
    recognised = [trial.target if index % 2 else "" for index, trial in enumerate(trials)]
    summary = summarise(IntentExperiment(trials, _outcomes(trials, recognised), sloppy, 1, 1.0))
    limit = summary["cue_limit"]
    assert limit["success_rate"] == pytest.approx(1 - sum(astray) / 30)
    assert limit["astray"] == sum(astray)
    assert limit["astray_recognised"] == sum(a and i % 2 == 1 for i, a in enumerate(astray))
    seated = limit["by_class"]["posture"]["seated"]
    assert seated["trials"] == 30 and seated["rate"] == pytest.approx(limit["success_rate"])
    assert f"of the {sum(astray)} that asked for another object" in "\n".join(
        summary_lines(summary)
    )
