"""The experiments' trial runner: outcomes in spec order, failures and dead workers accounted
for, the progress callback, and the same trials on a local Ray instance."""

from __future__ import annotations

import collections
import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from hsr_handover.experiments import trials
from hsr_handover.experiments.trials import (
    CRASHED,
    RAY_MISSING,
    ClusterUnavailable,
    TrialOutcome,
    TrialProgress,
    run_trials,
)
from tests import trial_functions

REPO = Path(__file__).resolve().parents[2]


class Recorder:
    """A progress callback that keeps its calls."""

    def __init__(self) -> None:
        self.calls: list[tuple[int, int, int]] = []

    def __call__(self, done: int, total: int, failed: int) -> None:
        self.calls.append((done, total, failed))


def results(outcomes: list[TrialOutcome]) -> list:
    return [outcome.result for outcome in outcomes]


def test_same_specs_same_outcomes_with_one_or_two_workers():
    specs = [{"seed": seed} for seed in (3, 1, 4, 1, 5, 9)]
    serial = run_trials(trial_functions.draw, specs, workers=1)
    pooled = run_trials(trial_functions.draw, specs, workers=2)
    assert all(outcome.ok for outcome in serial + pooled)
    assert results(pooled) == results(serial)
    assert results(serial)[1] == results(serial)[3]  # seed 1 twice: the seed is all that counts
    assert results(serial)[0] != results(serial)[1]


def test_outcomes_in_spec_order_when_later_specs_finish_first():
    # The first runs long enough that the other worker, however late it starts on a loaded
    # machine (spawning takes a second or more there), finishes later specs before it.
    specs = [{"value": index, "sleep": 2.5 if index == 0 else 0.05} for index in range(6)]
    outcomes = run_trials(trial_functions.sleep_then_finish, specs, workers=2)
    assert [outcome.index for outcome in outcomes] == list(range(6))
    assert [result["value"] for result in results(outcomes)] == list(range(6))
    finished = [result["finished"] for result in results(outcomes)]
    assert finished != sorted(finished), "the later specs were meant to finish first"
    slept = [spec["sleep"] for spec in specs]
    assert all(outcome.wall_s >= sleep for outcome, sleep in zip(outcomes, slept, strict=True))


@pytest.mark.parametrize("workers", [1, 2])
def test_an_exception_is_a_failed_outcome_with_its_reason(workers):
    specs = [{"value": index, "fail": index == 1} for index in range(4)]
    recorder = Recorder()
    outcomes = run_trials(trial_functions.fail_if_asked, specs, workers=workers, progress=recorder)
    failed = outcomes[1]
    assert (failed.ok, failed.result, failed.error) == (False, None, "ValueError: no depth image")
    assert [(o.ok, o.result, o.error) for i, o in enumerate(outcomes) if i != 1] == [
        (True, 0, ""),
        (True, 2, ""),
        (True, 3, ""),
    ]
    assert recorder.calls[-1] == (4, 4, 1)


def test_a_dead_worker_fails_its_trial_and_the_rest_complete(tmp_path):
    """Trial 2 calls os._exit(1) once the other five are in (the progress callback releases
    it), so no other trial is running when its worker dies."""
    release = tmp_path / "release"
    specs = [{"value": index, "exit": index == 2, "release": str(release)} for index in range(6)]
    recorder = Recorder()

    def progress(done: int, total: int, failed: int) -> None:
        recorder(done, total, failed)
        if done == 5:
            release.touch()

    outcomes = run_trials(trial_functions.exit_if_asked, specs, workers=2, progress=progress)
    crashed = outcomes[2]
    assert not crashed.ok and crashed.result is None
    assert crashed.error == CRASHED
    assert "worker process died" in crashed.error and "\n" not in crashed.error
    assert [(o.ok, o.result) for i, o in enumerate(outcomes) if i != 2] == [
        (True, value) for value in (0, 1, 3, 4, 5)
    ]
    assert recorder.calls[-1] == (6, 6, 1)


def test_trials_pending_when_a_worker_dies_run_in_a_fresh_pool():
    """Trial 0 kills its worker at once: the pool breaks with most trials not yet started; they
    run in a fresh pool. Only a trial the other worker was running then may fail with it."""
    specs = [{"value": index, "exit": index == 0, "sleep": 0.3} for index in range(6)]
    outcomes = run_trials(trial_functions.exit_if_asked, specs, workers=2)
    assert (outcomes[0].ok, outcomes[0].error) == (False, CRASHED)
    others = outcomes[1:]
    collateral = [outcome for outcome in others if not outcome.ok]
    assert len(collateral) <= 1, [outcome.error for outcome in collateral]
    assert all(outcome.error == CRASHED for outcome in collateral)
    assert all(o.result == o.index for o in others if o.ok)


def test_no_worker_process_runs_more_than_a_pools_trials(monkeypatch):
    """Each trial's Drake diagrams stay alive in its worker: fresh workers take over once a pool
    has run TRIALS_PER_WORKER trials a worker, and every trial still runs, once."""
    monkeypatch.setattr(trials, "TRIALS_PER_WORKER", 2)
    specs = [{"sleep": 0.05}] * 9
    recorder = Recorder()
    outcomes = run_trials(trial_functions.worker_pid, specs, workers=2, progress=recorder)
    assert all(outcome.ok for outcome in outcomes) and recorder.calls[-1] == (9, 9, 0)
    pids = collections.Counter(results(outcomes))
    assert max(pids.values()) <= 4  # a pool's four, at most
    assert len(pids) >= 3  # nine trials, four a pool
    assert os.getpid() not in pids


def test_progress_is_called_once_per_trial_and_ends_at_total():
    specs = [{"value": index, "fail": index % 3 == 0} for index in range(7)]
    recorder = Recorder()
    run_trials(trial_functions.fail_if_asked, specs, workers=2, progress=recorder)
    assert [call[0] for call in recorder.calls] == list(range(1, 8))
    assert {call[1] for call in recorder.calls} == {7}
    failed = [call[2] for call in recorder.calls]
    assert failed == sorted(failed) and failed[-1] == 3


def test_progress_bar_off_a_terminal_prints_a_line_per_tenth_and_ends_at_total(capsys):
    bar = TrialProgress()
    for done in range(1, 26):
        bar(done, 25, min(done, 2))
    lines = capsys.readouterr().err.splitlines()
    assert 10 <= len(lines) <= 11
    assert lines[-1].endswith("25 / 25 trials, 2 failed")
    assert lines[-1].startswith("[" + "#" * 30 + "]")


@pytest.mark.parametrize("workers", [1, 2])
def test_keyboard_interrupt_propagates(workers):
    specs = [{}] + [{"value": index, "sleep": 0.5} for index in range(1, 5)]
    with pytest.raises(KeyboardInterrupt):
        run_trials(trial_functions.interrupt, specs, workers=workers)


def test_no_specs_no_outcomes_and_workers_must_be_positive():
    assert run_trials(trial_functions.draw, []) == []
    with pytest.raises(ValueError, match="workers: expected at least 1, got 0"):
        run_trials(trial_functions.draw, [{"seed": 0}], workers=0)


def test_ray_address_without_ray_is_a_clear_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` now raises ImportError
    with pytest.raises(RuntimeError) as error:
        run_trials(trial_functions.draw, [{"seed": 0}], ray_address="127.0.0.1:6379")
    assert str(error.value) == RAY_MISSING
    assert str(error.value) == "--ray-address needs Ray: pip install 'hsr_handover[cluster]'"


def test_an_address_where_nothing_listens_is_refused_at_once():
    """Ray itself retries such an address for minutes; the runner asks the port first."""
    pytest.importorskip("ray")
    with socket.socket() as probe:  # a port nothing listens on: bound, never listening
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
        with pytest.raises(ClusterUnavailable, match=f"no Ray cluster at 127.0.0.1:{port}: "
                           f"nothing answers at 127.0.0.1:{port}"):  # fmt: skip
            run_trials(trial_functions.draw, [{"seed": 0}], ray_address=f"127.0.0.1:{port}")


# A one-CPU Ray instance in a process of its own, as a cluster's head would be: it prints its
# address, then lives until its stdin closes. address="local" so it never joins another Ray on
# this machine, its files in a folder of its own rather than the shared /tmp/ray; the repository
# is on its workers' path, as the project is on a real cluster's.
_RAY_HEAD = """
import sys, ray
ray.init(address="local", num_cpus=1, include_dashboard=False, _node_ip_address="127.0.0.1",
         _temp_dir=sys.argv[1])
print(ray.get_runtime_context().gcs_address, flush=True)
sys.stdin.read()
ray.shutdown()
"""


@pytest.fixture
def ray_head():
    pytest.importorskip("ray", reason="Ray is not installed (pip install -e '.[cluster]')")
    env = dict(
        os.environ,
        PYTHONPATH=str(REPO),
        # A driver given an explicit address does not send Ray's token; this short-lived
        # instance does without one.
        RAY_AUTH_MODE="disabled",
        RAY_USAGE_STATS_ENABLED="0",
    )
    # Short: Ray's Unix sockets live under it, and their paths may not exceed 107 characters.
    temp_dir = tempfile.mkdtemp(prefix="ray-test-")
    head = subprocess.Popen(
        [sys.executable, "-c", _RAY_HEAD, temp_dir],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        env=env,
        text=True,
        start_new_session=True,  # its own process group: Ray's daemons can be ended with it
    )
    try:
        ready, _, _ = select.select([head.stdout], [], [], 120)
        address = head.stdout.readline().strip() if ready else ""
        assert address, "the Ray head did not start"
        yield address
    finally:
        head.stdin.close()
        try:
            head.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(head.pid, signal.SIGKILL)
            head.wait()
        shutil.rmtree(temp_dir, ignore_errors=True)


def test_the_same_trials_on_a_local_ray_instance(ray_head):
    draws = [{"seed": seed} for seed in (7, 8)]
    specs = [*draws, {"fail": True}, {"exit": True}]
    recorder = Recorder()
    outcomes = run_trials(
        trial_functions.fail_or_exit_or_draw, specs, ray_address=ray_head, progress=recorder
    )
    assert results(outcomes[:2]) == results(run_trials(trial_functions.draw, draws, workers=1))
    assert outcomes[2].error == "ValueError: no depth image"
    assert not outcomes[3].ok and outcomes[3].error.startswith("WorkerCrashedError: ")
    assert [outcome.index for outcome in outcomes] == [0, 1, 2, 3]
    assert recorder.calls[-1] == (4, 4, 2) and len(recorder.calls) == 4
