"""The `hsr-handover` command.

Errors in what the user gave (a broken scenario, a bad argument, an unwritable output path)
print one line `error: ...` and exit 2 without writing anything; a simulation whose physics
cannot go on reports what it did and exits 3 (`EXIT_SIMULATION_FAILED`); anything else is an
internal error, exit 1. No tracebacks: `--debug` shows them.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from hsr_handover.error_text import first_line
from hsr_handover.experiments.reporting import FIGURE_SUFFIXES
from hsr_handover.output_files import write_together
from hsr_handover.progress import ProgressBar

EXIT_USAGE = 2
EXIT_FAILED = 1
EXIT_SIMULATION_FAILED = 3  # the run's physics could not go on: reported, with what it did
RECORD_FORMATS = ("folder", "ros2", "ros1")
"""`simulation.RECORD_FORMATS`, the first the default, named here so that parsing the command
line does not import Drake."""


class UsageError(Exception):
    """Bad user input found before anything runs."""


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line (`error: ...`, exit 2), like every other error."""

    def error(self, message: str):
        print(f"error: {self.prog}: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _add_experiment_parsers(commands) -> None:
    experiment = commands.add_parser("experiment", help="run one of the paper's experiments")
    kinds = experiment.add_subparsers(dest="experiment", required=True)
    intent = kinds.add_parser(
        "intent", help="which object the person points at and looks at (paper 4.2)"
    )
    _add_trial_arguments(intent)
    intent.add_argument("--distractors", type=int, default=0, help="trials with no request")
    handover = kinds.add_parser(
        "handover", help="fetch the object asked for and hand it over (paper 4.3)"
    )
    _add_trial_arguments(handover)
    handover.add_argument(
        "--refusals", type=int, default=0, help="more trials in which the person never takes it"
    )


def _add_trial_arguments(parser) -> None:
    """What every trial experiment takes: the scenario, how many trials, the seed, where they
    run and what to write."""
    parser.add_argument("scenario", type=Path, help="scenario YAML with two or more objects")
    parser.add_argument("--trials", type=int, default=60, help="requests (default 60)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the whole experiment")
    parser.add_argument("--workers", type=int, help="local worker processes (default: cores)")
    parser.add_argument("--ray-address", help="run the trials on this existing Ray cluster")
    parser.add_argument("--csv", type=Path, help="one row per trial (.csv)")
    parser.add_argument("--json", type=Path, help="summary (.json)")
    parser.add_argument(
        "--plot", type=Path, help="figure beside the paper's figures (.png, .svg or .pdf)"
    )
    parser.add_argument(
        "--report", type=Path,
        help="a folder for the report page (index.html: the rates beside the paper's, the "
        "figure, the trials, each linked to its replay with --html-dir)",
    )  # fmt: skip
    parser.add_argument(
        "--html-dir", type=Path, help="a replay per trial, named by trial and outcome"
    )
    parser.add_argument(
        "--layouts", choices=("scenario", "generated"), default="scenario",
        help="scenario (default: the file's layout, its person varied) or generated (a new "
        "layout per trial, drawn from the file's `layouts` ranges)",
    )  # fmt: skip
    parser.add_argument(
        "--scenario-dir", type=Path, help="each trial's scenario as it ran (trial_NNN.yaml)"
    )


def _add_openpose_parsers(commands) -> None:
    openpose = commands.add_parser("openpose", help="OpenPose's JSON output")
    kinds = openpose.add_subparsers(dest="openpose", required=True)
    check = kinds.add_parser(
        "check", help="summarise OpenPose JSON files or folders of per-frame files"
    )
    check.add_argument(
        "paths", type=Path, nargs="+", metavar="PATH", help="a JSON file or a folder of frames"
    )
    check.add_argument("--json", type=Path, help="summary to write (.json)")
    check.add_argument(
        "--model", default="auto", help="auto (default: told by the files), COCO or BODY_25"
    )
    check.add_argument(
        "--keypoint-scale",
        default="pixels",
        help="pixels (default), unit ([0, 1]) or signed_unit ([-1, 1]); these need --image-size",
    )
    check.add_argument(
        "--image-size", type=int, nargs=2, metavar=("W", "H"), help="the images' size (px)"
    )
    check.add_argument(
        "--near",
        type=float,
        nargs=2,
        metavar=("U", "V"),
        help="follow the person nearest this pixel",
    )


def _add_bag_arguments(parser) -> None:
    """Where a ROS bag holds what the robot perceives (the HSR's names by default)."""
    from hsr_handover.recording import ros_topics

    for option, default, what in (
        ("--color-topic", ros_topics.COLOR_TOPIC, "colour images (Image, or CompressedImage)"),
        ("--depth-topic", ros_topics.DEPTH_TOPIC, "registered depth (16UC1 mm or 32FC1 m)"),
        ("--camera-info-topic", ros_topics.CAMERA_INFO_TOPIC, "the colour camera's CameraInfo"),
        ("--joint-states-topic", ros_topics.JOINT_STATES_TOPIC, "JointState"),
        ("--skeleton-topic", ros_topics.SKELETON_TOPIC, "keypoints (PolygonStamped)"),
        ("--camera-frame", ros_topics.CAMERA_FRAME, "the images' optical frame in TF"),
    ):
        parser.add_argument(option, default=default, help=f"{what} (default {default})")
    parser.add_argument(
        "--base-frame", help="the fixed frame of the camera's pose (default odom, else "
        "base_footprint when TF has no odom)",
    )  # fmt: skip
    parser.add_argument(
        "--tolerance", type=float, metavar="S",
        help="pairing and TF tolerance (s; default half the colour's median period)",
    )  # fmt: skip
    parser.add_argument(
        "--openpose", type=Path, metavar="DIR",
        help="OpenPose JSON frames, frame k for the bag's k-th colour image (instead of the "
        "skeleton topic)",
    )  # fmt: skip


def _add_bag_parsers(commands) -> None:
    bag = commands.add_parser("bag", help="ROS bags of an HSR session")
    kinds = bag.add_subparsers(dest="bag", required=True)
    check = kinds.add_parser("check", help="what a bag holds for the robot's perception")
    check.add_argument("path", type=Path, metavar="BAG", help="a ROS 1 .bag or ROS 2 bag folder")
    check.add_argument("--json", type=Path, help="summary to write (.json)")
    _add_bag_arguments(check)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="hsr-handover",
        description="Toyota HSR handover by topological mapping, simulated in Drake.",
    )
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser("run", help="simulate a scenario and write an HTML replay")
    run.add_argument("scenario", type=Path, help="scenario YAML file")
    run.add_argument("--html", type=Path, help="replay file to write (default: SCENARIO.html)")
    run.add_argument("--duration", type=float, help="simulated seconds (overrides the file)")
    run.add_argument("--seed", type=int, help="random seed (overrides the file)")
    run.add_argument(
        "--record", type=Path, metavar="PATH",
        help="write the robot's sensors frame by frame to PATH (folder, ros2: a new or empty "
        "directory; ros1: a new .bag file)",
    )  # fmt: skip
    run.add_argument(
        "--record-format", choices=RECORD_FORMATS,
        help="with --record: folder (default: PNG frames, YAML, OpenPose JSON), ros2 (an MCAP "
        "bag folder) or ros1 (a .bag file), with the HSR's topics",
    )  # fmt: skip
    run.add_argument(
        "--trajectories", type=Path, metavar="FILE",
        help="write the robot's planned motions as the HSR's trajectory controllers take them "
        "(.json; a scenario with handover)",
    )  # fmt: skip
    validate = commands.add_parser("validate", help="check a scenario without simulating it")
    validate.add_argument("scenario", type=Path, help="scenario YAML file")
    attention = commands.add_parser(
        "attention", help="run the attention experiment (paper figs. 9-12) on a scenario"
    )
    attention.add_argument("scenario", type=Path, help="scenario YAML with perception.attention")
    attention.add_argument("--plot", type=Path, help="figure to write (.png, .svg or .pdf)")
    attention.add_argument("--csv", type=Path, help="time series to write (.csv)")
    attention.add_argument("--json", type=Path, help="summary to write (.json)")
    attention.add_argument("--html", type=Path, help="replay to write (.html)")
    attention.add_argument("--duration", type=float, help="simulated seconds (overrides the file)")
    attention.add_argument("--seed", type=int, help="random seed (overrides the file)")
    effectivity = commands.add_parser(
        "effectivity", help="the arm's and the person's ranges and the handover point (figs. 8, 14)"
    )
    effectivity.add_argument("scenario", type=Path, help="scenario YAML with a person")
    effectivity.add_argument("--plot", type=Path, help="figure to write (.png, .svg or .pdf)")
    effectivity.add_argument("--json", type=Path, help="summary to write (.json)")
    effectivity.add_argument("--html", type=Path, help="replay with the figures to write (.html)")
    intent = commands.add_parser(
        "intent", help="the robot's perception and intent offline, on a recorded session"
    )
    intent.add_argument(
        "session", type=Path, help="a folder written by run --record, a ROS 1 .bag file or a "
        "ROS 2 bag folder",
    )  # fmt: skip
    intent.add_argument("--json", type=Path, help="what it recognised (.json)")
    _add_bag_arguments(intent)
    _add_bag_parsers(commands)
    _add_experiment_parsers(commands)
    _add_openpose_parsers(commands)
    return parser


def _output_path(path: Path | None, option: str, suffixes: str | tuple[str, ...]) -> Path | None:
    """Check an output path before anything runs, so a bad one costs no simulation."""
    if path is None:
        return None
    suffixes = (suffixes,) if isinstance(suffixes, str) else suffixes
    if path.suffix.lower() not in suffixes:
        expected = " or ".join(suffixes)
        raise UsageError(f"{option}: expected a path ending in {expected}, got {str(path)!r}")
    if path.is_dir():
        raise UsageError(f"{option}: expected a file to write, {str(path)!r} is a directory")
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise UsageError(f"{option}: expected an existing directory, {str(directory)!r} is not one")
    if not os.access(directory, os.W_OK):
        raise UsageError(f"{option}: expected a writable directory, {str(directory)!r} is not")
    return path


def _output_dir(path: Path | None, option: str) -> Path | None:
    """Check an output directory option before anything runs: an existing writable directory,
    or one to make in an existing writable directory (made only once every check has
    passed)."""
    if path is None:
        return None
    if path.exists() and not path.is_dir():
        raise UsageError(f"{option}: expected a directory, {str(path)!r} is a file")
    existing = path if path.is_dir() else (path.parent if str(path.parent) else Path("."))
    if not existing.is_dir():
        raise UsageError(f"{option}: expected an existing parent directory for {str(path)!r}")
    if not os.access(existing, os.W_OK):
        raise UsageError(f"{option}: expected a writable directory, {str(existing)!r} is not")
    return path


def _record_path(path: Path | None, record_format: str) -> Path | None:
    """Check --record before anything runs: for a folder or a ROS 2 bag, a new directory in an
    existing writable one, or an empty existing directory; for a ROS 1 bag, a new .bag file in
    an existing writable directory (a recording is never written over another)."""
    if path is None or record_format != "ros1":
        return _record_dir(path)
    if path.suffix != ".bag":
        raise UsageError(f"--record: expected a path ending in .bag for ros1, got {str(path)!r}")
    if path.exists():
        raise UsageError(f"--record: expected a new .bag file, {str(path)!r} exists")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise UsageError(f"--record: expected a writable parent directory for {str(path)!r}")
    return path


def _record_dir(path: Path | None) -> Path | None:
    """A new directory in an existing writable one, or an empty existing directory."""
    if path is None:
        return None
    if path.exists() and not (path.is_dir() and not any(path.iterdir())):
        raise UsageError(f"--record: expected a new or empty directory, {str(path)!r} is not")
    parent = path if path.is_dir() else (path.parent if str(path.parent) else Path("."))
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise UsageError(f"--record: expected a writable parent directory for {str(path)!r}")
    return path


def _replay_path(args: argparse.Namespace) -> Path:
    default = Path(args.scenario.stem + ".html")
    return _output_path(args.html if args.html is not None else default, "--html", ".html")


def _apply_overrides(scenario, args: argparse.Namespace) -> None:
    """--duration and --seed over the file's, within the ranges the file's own are held to."""
    from hsr_handover.scenario.checks import DURATION, SEED

    if args.duration is not None:
        if args.duration not in DURATION:
            raise UsageError(f"--duration: expected a number in {DURATION}, got {args.duration}")
        scenario.simulation.duration = args.duration
    if args.seed is not None:
        if args.seed not in SEED:
            raise UsageError(f"--seed: expected an integer in {SEED}, got {args.seed}")
        scenario.simulation.seed = args.seed


class SimulatedTimeBar(ProgressBar):
    """A bar over simulated time, `progress(now, total)`."""

    def __call__(self, now: float, total: float) -> None:
        # A runner that adds up float steps may stop a rounding error short of the total (0.09 s
        # a hundred times is 8.99999999999999 s): that last call is the end all the same.
        done = now >= total - 1e-9 * max(total, 1.0)
        now = total if done else now
        self.show(now / total, f"{now:6.2f} / {total:.2f} s simulated", done)


def _run(args: argparse.Namespace) -> int:
    from hsr_handover.scenario import load_scenario
    from hsr_handover.simulation import SimulationFailed, run_scenario

    scenario = load_scenario(args.scenario)
    _apply_overrides(scenario, args)
    if args.record_format is not None and args.record is None:
        raise UsageError("--record-format: expected --record PATH with it (nothing is recorded)")
    args.record_format = args.record_format or RECORD_FORMATS[0]
    replay, record = _replay_path(args), _record_path(args.record, args.record_format)
    trajectories = _output_path(args.trajectories, "--trajectories", ".json")
    if trajectories is not None and not scenario.handover.enabled:
        raise UsageError(
            f"--trajectories: expected a scenario with handover enabled, {args.scenario} plans "
            "no motions"
        )
    try:
        report = run_scenario(scenario, replay=replay, progress=SimulatedTimeBar(),
                              record=record, record_format=args.record_format)  # fmt: skip
    except SimulationFailed as failed:
        _write_trajectories(args, failed.report, trajectories)
        _print_run(args, failed.report, record, trajectories)
        print(f"simulation:  failed {failed}", file=sys.stderr)
        return EXIT_SIMULATION_FAILED
    _write_trajectories(args, report, trajectories)
    _print_run(args, report, record, trajectories)
    return 0


def _write_trajectories(args: argparse.Namespace, report, trajectories: Path | None) -> None:
    """The robot's planned motions to `trajectories` (written whole), before anything is
    printed: a write that fails leaves no report half printed."""
    if trajectories is not None:
        from hsr_handover.recording.trajectory_json import write_trajectories

        write_together({trajectories: lambda path: write_trajectories(
            path, report.commanded, str(args.scenario))})  # fmt: skip


def _print_run(args: argparse.Namespace, report, record: Path | None, trajectories: Path | None):
    """What a run did (as far as it went), with the files it wrote."""
    print(f"sim time:    {report.sim_time:.2f} s")
    print(f"wall time:   {report.wall_time:.2f} s")
    print(f"real-time factor: {report.real_time_factor:.2f}")
    print(f"replay:      {report.replay}")
    if record is not None:
        kind = "" if args.record_format == "folder" else f" ({args.record_format} bag)"
        print(f"recorded:    {record}{kind}")
    if trajectories is not None:
        print(f"trajectories: {trajectories} ({len(report.commanded)} motions)")
    if report.intent is not None:
        print(f"intent:      {_recognised(report.intent.target, report.intent.recognised_time)}")
    if report.cycle is not None:
        print_cycle(report.cycle, report.person_holds)


def _recognised(target: str | None, time: float) -> str:
    return f"{target} (recognised at {time:.2f} s)" if target else "nothing recognised"


def _bag_topics(args: argparse.Namespace):
    from hsr_handover.recording.ros_topics import BagTopics

    if args.tolerance is not None and not args.tolerance > 0:
        raise UsageError(
            f"--tolerance: expected a positive number of seconds, got {args.tolerance}"
        )
    if args.openpose is not None and not args.openpose.is_dir():
        raise UsageError(
            f"--openpose: expected a folder of OpenPose JSON frames, {str(args.openpose)!r} "
            "is not one"
        )
    return BagTopics(args.color_topic, args.depth_topic, args.camera_info_topic,
                     args.joint_states_topic, args.skeleton_topic, args.base_frame,
                     args.camera_frame)  # fmt: skip


def _read_recording(args: argparse.Namespace):
    """The folder or bag `intent` was given, read (a bag's usage errors: one line)."""
    from hsr_handover.recording.rgbd_session import read_session
    from hsr_handover.recording.ros_bag import is_bag
    from hsr_handover.recording.ros_bag_session import read_bag_session

    topics = _bag_topics(args)
    if is_bag(args.session) or args.session.suffix == ".bag":
        return read_bag_session(args.session, topics, args.tolerance, args.openpose)
    if not args.session.is_dir():
        raise UsageError(
            f"{args.session}: expected a session folder written by run --record, a ROS 1 .bag "
            "file or a ROS 2 bag folder"
        )
    for option in ("tolerance", "openpose", "base_frame"):
        if getattr(args, option) is not None:
            raise UsageError(
                f"--{option.replace('_', '-')}: expected a bag, {args.session} is a folder"
            )
    return read_session(args.session)


def _intent(args: argparse.Namespace) -> int:
    """Run perception and intent on a recorded session folder or bag; one that is not, or whose
    settings are broken, is a usage error."""
    from hsr_handover.experiments.reporting import write_json
    from hsr_handover.recording.offline_intent import perceive
    from hsr_handover.recording.rgbd_session import SessionError

    output = _output_path(args.json, "--json", ".json")
    try:
        session = _read_recording(args)
        try:
            result = perceive(session)
        finally:
            getattr(session, "close", lambda: None)()
    except SessionError as error:
        raise UsageError(str(error)) from None
    print(f"frames:      {result.frames} at {result.rate_hz:g} Hz")
    for reason in session.skipped:
        print(f"skipped:     {reason}")
    print(f"intent:      {_recognised(result.target, result.recognised_time)}")
    if result.target:
        print(f"frame:       {result.frame}, confidence {result.confidence:.2f}")
    if output is not None:
        write_json(result.to_dict() | {"skipped": list(session.skipped)}, output)
        print(f"wrote {output}")
    return 0


def _bag(args: argparse.Namespace) -> int:
    """`bag check`: a bag's summary; one that is not a bag is a usage error, nothing printed."""
    from hsr_handover.experiments.reporting import write_json
    from hsr_handover.recording.rgbd_session import SessionError
    from hsr_handover.recording.ros_bag_check import check_bag, summary_lines

    output = _output_path(args.json, "--json", ".json")
    try:
        survey = check_bag(args.path, _bag_topics(args), args.tolerance, args.openpose)
    except SessionError as error:
        raise UsageError(str(error)) from None
    print("\n".join(summary_lines(survey)))
    if output is not None:
        write_json(survey.to_dict(), output)
        print(f"wrote {output}")
    return 0


def print_cycle(cycle, person_holds: str) -> None:
    """What the robot did: the outcome, the target and when each phase began."""
    print(f"handover:    {cycle.outcome}")
    target = cycle.target or "none recognised"
    if cycle.target:
        target += f" (recognised at {cycle.recognised_time:.1f} s)"
    print(f"target:      {target}")
    if cycle.watch_lift > 0:
        print(f"watched from: the torso raised, arm lift {cycle.watch_lift:.2f} m")
    phases = ", ".join(f"{name} {at:.1f} s" for name, at in cycle.phase_times.items())
    print(f"phases:      {phases or 'watching only'}")
    print(f"planning:    {cycle.planning_s:.2f} s of wall time")
    print(f"person holds: {person_holds or 'nothing'}")


def _validate(args: argparse.Namespace) -> int:
    from hsr_handover.scenario import load_scenario
    from hsr_handover.simulation import prepare_simulation

    scenario = load_scenario(args.scenario)
    prepare_simulation(scenario, with_meshcat=False)
    print(
        f"ok: {args.scenario} ({len(scenario.objects)} objects, "
        f"{len(scenario.person.behavior)} actions, {scenario.simulation.duration:g} s)"
    )
    return 0


def _attention(args: argparse.Namespace) -> int:
    from hsr_handover.experiments.attention.experiment import run_attention
    from hsr_handover.experiments.attention.report import (
        plot,
        summary_lines,
        write_csv,
        write_json,
    )
    from hsr_handover.scenario import load_scenario

    scenario = load_scenario(args.scenario)
    _apply_overrides(scenario, args)
    if not scenario.perception.attention:
        raise UsageError(f"{args.scenario}: perception.attention: expected a focus schedule")
    outputs = {
        "plot": _output_path(args.plot, "--plot", FIGURE_SUFFIXES),
        "csv": _output_path(args.csv, "--csv", ".csv"),
        "json": _output_path(args.json, "--json", ".json"),
    }
    replay = _output_path(args.html, "--html", ".html")
    result, report = run_attention(scenario, replay=replay, progress=SimulatedTimeBar())
    writers = {"plot": plot, "csv": write_csv, "json": write_json}
    write_together({path: functools.partial(writers[name], result)
                    for name, path in outputs.items() if path is not None})  # fmt: skip
    print("\n".join(summary_lines(result)))  # n/a where the JSON has null
    print(f"wall time {report.wall_time:.1f} s, real-time factor {report.real_time_factor:.2f}")
    for path in (*outputs.values(), replay):
        if path is not None:
            print(f"wrote {path}")
    return 0


def _effectivity(args: argparse.Namespace) -> int:
    from hsr_handover.experiments.effectivity.figures import run_effectivity
    from hsr_handover.experiments.effectivity.report import plot, summary_lines, write_json
    from hsr_handover.scenario import load_scenario

    scenario = load_scenario(args.scenario)
    outputs = {"plot": _output_path(args.plot, "--plot", FIGURE_SUFFIXES),
               "json": _output_path(args.json, "--json", ".json"),
               "html": _output_path(args.html, "--html", ".html")}  # fmt: skip
    result = run_effectivity(scenario, replay=outputs["html"])
    writers = {"plot": plot, "json": write_json}
    write_together({outputs[name]: functools.partial(write, result)
                    for name, write in writers.items() if outputs[name] is not None})  # fmt: skip
    print("\n".join(summary_lines(result)))
    print(f"wall time {result.wall_s:.1f} s")
    for path in outputs.values():
        if path is not None:
            print(f"wrote {path}")
    return 0


def _count(value: int | None, option: str, low: int, high: int) -> None:
    if value is not None and not low <= value <= high:
        raise UsageError(f"{option}: expected an integer in [{low}, {high}], got {value}")


def _experiment(args: argparse.Namespace) -> int:
    """Check everything the user gave, run the trials with a progress bar, write what was
    asked for and print the table."""
    from hsr_handover.experiments.reporting import write_json
    from hsr_handover.experiments.trials import TrialProgress
    from hsr_handover.scenario import load_scenario
    from hsr_handover.scenario.checks import SEED

    scenario = load_scenario(args.scenario)
    if len(scenario.objects) < 2:
        raise UsageError(f"{args.scenario}: objects: expected two or more to choose between")
    _count(args.trials, "--trials", 1, 100_000)
    extra = "distractors" if args.experiment == "intent" else "refusals"
    _count(getattr(args, extra), f"--{extra}", 0, 100_000)
    _count(args.workers, "--workers", 1, 1024)
    if args.seed not in SEED:
        raise UsageError(f"--seed: expected an integer in {SEED}, got {args.seed}")
    outputs = {
        "csv": _output_path(args.csv, "--csv", ".csv"),
        "json": _output_path(args.json, "--json", ".json"),
        "plot": _output_path(args.plot, "--plot", FIGURE_SUFFIXES),
    }
    html_dir = _output_dir(args.html_dir, "--html-dir")
    scenario_dir = _output_dir(args.scenario_dir, "--scenario-dir")
    report_dir = _output_dir(args.report, "--report")
    run, summarise, report = _experiment_kind(args.experiment)
    for directory in (html_dir, scenario_dir, report_dir):
        if directory is not None:
            directory.mkdir(exist_ok=True)
    experiment = run(
        scenario, args.trials, getattr(args, extra), args.seed, args.workers, args.ray_address,
        TrialProgress(), html_dir, args.layouts, scenario_dir,
    )  # fmt: skip
    summary = summarise(experiment)
    writers = {
        "csv": lambda path: report.write_csv(experiment.rows(), path),
        "json": lambda path: write_json(summary, path),
        "plot": lambda path: report.plot(summary, path),
    }
    write_together({path: writers[name] for name, path in outputs.items() if path is not None})
    for path in outputs.values():
        if path is not None:
            print(f"wrote {path}")
    if report_dir is not None:
        print(f"wrote {_write_report(report_dir, report, summary, experiment.rows(), html_dir)}")
    print("\n".join(report.summary_lines(summary)))
    return 0


def _write_report(directory: Path, report, summary: dict, rows: list[dict], replays) -> Path:
    """The experiment's report page in `directory` (`experiments.html_report`)."""
    from hsr_handover.experiments.html_report import write_report

    return write_report(
        directory, report.TITLE, report.rate_rows(summary), report.summary_lines(summary),
        lambda path: report.plot(summary, path), rows, report.trial_columns(rows), replays,
    )  # fmt: skip


def _experiment_kind(kind: str):
    """The experiment's (run, summarise, report module)."""
    if kind == "intent":
        from hsr_handover.experiments.intent import report, trial

        return trial.run_intent_experiment, trial.summarise, report
    from hsr_handover.experiments.handover import report, trial

    return trial.run_handover_experiment, trial.summarise, report


_OPENPOSE_OPTIONS = {
    "model": "--model", "keypoint_scale": "--keypoint-scale", "image_size": "--image-size",
}  # fmt: skip


def _openpose(args: argparse.Namespace) -> int:
    """Read every path before printing or writing anything: one that is not OpenPose output
    is a usage error, with no partial output."""
    from hsr_handover.experiments.reporting import write_json
    from hsr_handover.recording.openpose_check import check_openpose, summary_lines

    output = _output_path(args.json, "--json", ".json")
    if args.near is not None and not all(math.isfinite(value) for value in args.near):
        raise UsageError(f"--near: expected a finite pixel U V, got {args.near[0]} {args.near[1]}")
    options = {
        "model": args.model,
        "keypoint_scale": args.keypoint_scale,
        "image_size": None if args.image_size is None else tuple(args.image_size),
        "near_px": None if args.near is None else tuple(args.near),
    }
    try:
        summaries = [check_openpose(path, **options) for path in args.paths]
    except ValueError as error:
        message = str(error)
        for name, option in _OPENPOSE_OPTIONS.items():  # the reader names its arguments
            if message.startswith(f"{name}: "):
                message = option + message.removeprefix(name)
        raise UsageError(message) from None
    for summary in summaries:
        print("\n".join(summary_lines(summary)))
    if output is not None:
        write_json({"paths": [summary.to_dict() for summary in summaries]}, output)
        print(f"wrote {output}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    from hsr_handover.experiments.trials import ClusterUnavailable
    from hsr_handover.scenario import ScenarioError

    handlers = {
        "run": _run, "validate": _validate, "attention": _attention, "experiment": _experiment,
        "effectivity": _effectivity, "openpose": _openpose, "intent": _intent, "bag": _bag,
    }  # fmt: skip
    try:
        return handlers[args.command](args)
    except (ScenarioError, UsageError, ClusterUnavailable) as error:
        if args.debug:
            raise
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except (RuntimeError, ValueError) as error:
        if args.debug:
            raise
        print(f"error: the simulation failed: {first_line(error)}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("error: interrupted; no replay written", file=sys.stderr)
        return EXIT_FAILED
    except Exception as error:  # a bug, not bad input: still one line, with a way to see more
        if args.debug:
            raise
        print(
            f"error: internal error ({type(error).__name__}: {error}); run with --debug "
            "for the traceback",
            file=sys.stderr,
        )
        return EXIT_FAILED


if __name__ == "__main__":
    sys.exit(main())
