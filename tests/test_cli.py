"""`hsr-handover run` and `attention` end to end, as a user runs them: a replay that holds the
recording; a progress bar that ends at the duration; n/a, not nan, where the JSON has null."""

from __future__ import annotations

import io
import json
import math
import subprocess
import sys

import pytest

from hsr_handover.cli import SimulatedTimeBar, print_cycle
from hsr_handover.experiments.reporting import format_value
from hsr_handover.robot.handover.cycle_types import CycleRecord, Failure, Phase
from tests.meshcat_html import meshcat_commands
from tests.paths import SCENARIOS

FULL_BAR = "[" + "#" * 30 + "]"


def test_run_writes_a_replay_holding_the_recording(tmp_path):
    replay = tmp_path / "left.html"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "hsr_handover.cli",
            "run",
            str(SCENARIOS / "point_left.yaml"),
            "--html",
            str(replay),
            "--duration",
            "0.3",
            "--seed",
            "3",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    for label in ("sim time:", "wall time:", "real-time factor:", f"replay:      {replay}"):
        assert label in result.stdout
    assert "0.30 / 0.30 s simulated" in result.stderr  # the progress bar reached the end
    commands = meshcat_commands(replay.read_bytes())
    (animation,) = [c for c in commands if c.get("type") == "set_animation"]
    animated = {entry["path"] for entry in animation["animations"]}
    for model in ("red_cup", "person", "hsrb", "table"):
        assert any(path.startswith(f"/drake/visualizer/{model}/") for path in animated), model
    clip = animation["animations"][0]["clip"]
    assert clip["fps"] == 20 and max(key["time"] for key in clip["tracks"][0]["keys"]) >= 5
    assert not list(tmp_path.glob(".*.partial*"))  # no temporary left behind


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("terminal", [False, True])
def test_progress_bar_ends_full_when_the_runner_stops_short(monkeypatch, terminal: bool) -> None:
    stderr = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stderr)
    bar = SimulatedTimeBar()
    now, duration = 0.0, 9.0
    while now < duration - 1e-12:  # the runner's loop: it stops at 8.99999999999999 s
        now = min(now + 0.09, duration)
        bar(now, duration)
    assert now < duration
    last = stderr.getvalue().replace("\r", "\n").rstrip("\n").splitlines()[-1]
    assert last == f"{FULL_BAR}   9.00 / 9.00 s simulated"
    assert stderr.getvalue().endswith("\n")


@pytest.mark.parametrize(
    ("value", "spec", "unit", "text"),
    [
        (1.234, "5.2f", "", " 1.23"),
        (0.5, ".2f", " s", "0.50 s"),
        (math.nan, "5.2f", "", "  n/a"),
        (math.nan, ".2f", " s", "n/a"),
        (math.inf, "4.2f", "", " n/a"),
    ],
)
def test_undefined_values_read_n_a(value: float, spec: str, unit: str, text: str) -> None:
    assert format_value(value, spec, unit) == text


def test_attention_summary_says_n_a_where_the_json_has_null(tmp_path) -> None:
    summary = tmp_path / "a.json"
    # 0.2 s: the runner's float steps stop just short of it, as they do of the full 9 s.
    result = subprocess.run(
        [sys.executable, "-m", "hsr_handover.cli", "attention",
         str(SCENARIOS / "attention_shift.yaml"), "--duration", "0.2", "--json", str(summary)],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert f"{FULL_BAR}   0.20 / 0.20 s simulated" in result.stderr
    assert "nan" not in result.stdout.lower()
    unattended = json.loads(summary.read_text())["phases"][0]
    assert unattended["focus"] == "none" and unattended["attended_ratio"] is None
    (line,) = [line for line in result.stdout.splitlines() if line.startswith("  none")]
    assert "attended ratio   n/a (gain  n/a)" in line


@pytest.mark.parametrize(
    "option, value, expected",
    [
        ("--duration", "1e308", "--duration: expected a number in (0, 3600] (s), got 1e+308"),
        ("--duration", "0", "--duration: expected a number in (0, 3600] (s), got 0.0"),
        ("--seed", "4294967296", "--seed: expected an integer in [0, 4294967295], got 4294967296"),
        ("--seed", "-1", "--seed: expected an integer in [0, 4294967295], got -1"),
    ],
)
def test_overrides_are_held_to_the_files_ranges(tmp_path, capsys, option, value, expected):
    from hsr_handover.cli import main

    replay = tmp_path / "never.html"
    code = main(["run", str(SCENARIOS / "point_left.yaml"), "--html", str(replay), option, value])
    assert code == 2 and capsys.readouterr().err.strip() == f"error: {expected}"
    assert not replay.exists()


def test_a_record_format_without_a_recording_is_refused(tmp_path, capsys):
    from hsr_handover import cli, simulation

    assert cli.RECORD_FORMATS == simulation.RECORD_FORMATS
    replay = tmp_path / "never.html"
    code = cli.main(["run", str(SCENARIOS / "point_left.yaml"), "--html", str(replay),
                     "--record-format", "ros2"])  # fmt: skip
    expected = "--record-format: expected --record PATH with it (nothing is recorded)"
    assert code == 2 and capsys.readouterr().err.strip() == f"error: {expected}"
    assert not replay.exists()


@pytest.mark.parametrize(("lift", "said"), [(0.0, False), (0.42, True)])
def test_the_run_says_when_the_robot_watched_from_a_raised_torso(capsys, lift: float, said: bool):
    cycle = CycleRecord(Phase.DONE, target="yellow", recognised_time=4.0, watch_lift=lift)
    print_cycle(cycle, "yellow_box")
    out = capsys.readouterr().out
    assert ("watched from: the torso raised, arm lift 0.42 m" in out) is said
    assert "target:      yellow (recognised at 4.0 s)" in out


@pytest.mark.parametrize(
    ("cycle", "outcome"),
    [
        (CycleRecord(Phase.DONE, target="yellow"), "done"),
        (CycleRecord(Phase.WATCH), "not recognised"),
        (CycleRecord(Phase.FAILED, Failure.UNREACHABLE, "no base pose", target="red"),
         "failed, unreachable: no base pose"),
        (CycleRecord(Phase.RETREAT, Failure.DROPPED, "it slipped", target="red"),
         "failed, dropped: it slipped"),
        (CycleRecord(Phase.CARRY, target="red"), "timeout: carry when the run ended"),
        (CycleRecord(Phase.WATCH, target="red"), "timeout: watch when the run ended"),
    ],
)  # fmt: skip
def test_a_run_ends_in_one_of_the_documented_outcomes(cycle: CycleRecord, outcome: str):
    """Never a bare phase name: a run in which nothing was recognised says so, and one cut
    short by its duration says where the cycle was."""
    assert cycle.outcome == outcome


@pytest.mark.parametrize(
    ("scenario", "trajectories", "expected"),
    [
        ("point_left.yaml", "motions.json",
         "--trajectories: expected a scenario with handover enabled, {scenario} plans no motions"),
        ("demo.yaml", "motions.csv",
         "--trajectories: expected a path ending in .json, got {path!r}"),
        ("demo.yaml", "folder.json",
         "--trajectories: expected a file to write, {path!r} is a directory"),
    ],
)  # fmt: skip
def test_trajectories_out_are_refused_before_anything_runs(
    tmp_path, capsys, scenario: str, trajectories: str, expected: str
):
    from hsr_handover.cli import main

    (tmp_path / "folder.json").mkdir()
    path, replay = tmp_path / trajectories, tmp_path / "never.html"
    code = main(["run", str(SCENARIOS / scenario), "--html", str(replay),
                 "--trajectories", str(path)])  # fmt: skip
    message = expected.format(scenario=SCENARIOS / scenario, path=str(path))
    assert code == 2 and capsys.readouterr().err.strip() == f"error: {message}"
    assert not replay.exists() and (path.is_dir() or not path.exists())


def test_a_simulation_that_fails_numerically_ends_the_run_with_what_it_did(
    tmp_path, capsys, monkeypatch
):
    """The plant's solver giving up part way (as a near-weightless object made it) is not a
    crash: the run stops there, writes its replay and says what it did, when and why, with its
    own exit status."""
    from pydrake.systems.analysis import Simulator

    from hsr_handover import simulation
    from hsr_handover.cli import EXIT_SIMULATION_FAILED, main

    class FailingSimulator(Simulator):
        def AdvanceTo(self, time: float):
            if time > 0.15:
                raise RuntimeError("Call to Solve() failed: factorization not ready\nmore")
            return super().AdvanceTo(time)

    monkeypatch.setattr(simulation, "Simulator", FailingSimulator)
    replay = tmp_path / "cut.html"
    code = main(["run", str(SCENARIOS / "point_left.yaml"), "--duration", "0.4",
                 "--html", str(replay)])  # fmt: skip
    captured = capsys.readouterr()
    assert code == EXIT_SIMULATION_FAILED == 3
    assert captured.err.strip().splitlines()[-1] == (
        "simulation:  failed at 0.10 s: Call to Solve() failed: factorization not ready"
    )
    assert "sim time:    0.10 s" in captured.out and replay.is_file()
