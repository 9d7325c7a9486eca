"""The trial runner the experiments share: `function(spec)` for every spec, in local worker
processes or on a Ray cluster, with every trial accounted for.

It knows nothing about robots. A trial is a top-level (so picklable) function applied to a
picklable spec that holds everything the trial needs, its seed included: never global state,
so the same specs give the same results whatever the number of workers or where they run.

A failed trial is counted and explained, never dropped: an exception inside the function, a
worker process that dies (a segfault, `os._exit`, the OOM killer) or a Ray task that is lost
each become a `TrialOutcome` with `ok=False` and a one-line reason.
"""

from __future__ import annotations

import multiprocessing
import os
import socket
import time
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from typing import Any

from hsr_handover.error_text import first_line
from hsr_handover.progress import ProgressBar

Progress = Callable[[int, int, int], None]
"""Called as `progress(done, total, failed)` once per finished trial."""

RAY_MISSING = "--ray-address needs Ray: pip install 'hsr_handover[cluster]'"


class ClusterUnavailable(RuntimeError):
    """The Ray cluster asked for cannot be used: Ray is not installed, or no cluster answers."""


TRIALS_PER_WORKER = 32
"""Trials a pool of local workers runs per worker before fresh processes take over (one worker
may run more of them than another, none more than the pool's): in pydrake 1.51.1 a diagram
that holds a Python LeafSystem is never freed (drake#23161; even one with no ports), so each
trial leaves its diagrams in the process that ran it, about 35 MB, and 330 trials a worker
filled a 24 GiB machine."""

CRASHED = "BrokenProcessPool: a worker process died (crash, os._exit, kill) while this trial ran"
NOT_RUN = "BrokenProcessPool: not run, worker processes died in two pools in a row"
_MAX_REASON = 200


@dataclass(frozen=True)
class TrialOutcome:
    """One trial's fate: `result` is what the function returned (None on failure), `error` a
    one-line reason such as "ValueError: no depth image" ("" when ok), `wall_s` the wall time
    the function ran (0.0 when that is unknown: a trial never run, or lost on Ray)."""

    index: int
    ok: bool
    result: Any
    error: str
    wall_s: float


def run_trials(
    function: Callable[[Any], Any],
    specs: Iterable[Any],
    workers: int | None = None,
    ray_address: str | None = None,
    progress: Progress | None = None,
) -> list[TrialOutcome]:
    """Apply `function(spec)` to every spec; one outcome per spec, in spec order.

    Locally, `workers` processes (default `os.cpu_count()`, never more than there are specs)
    started with `spawn`; a single worker runs the trials here, serially, with no pool (for
    debugging and tests). With `ray_address`, the trials run as tasks on that existing Ray
    cluster instead (a connection this process already has is reused). `progress(done, total,
    failed)` is called as each trial finishes. KeyboardInterrupt cancels the pending trials and
    propagates.
    """
    specs = list(specs)
    tally = _Tally(len(specs), progress)
    if ray_address is not None:
        _run_on_ray(function, specs, ray_address, tally)
    else:
        count = _worker_count(workers, len(specs))
        if count <= 1:
            _run_here(function, specs, tally)
        else:
            _run_in_pools(function, specs, count, tally)
    return tally.outcomes()


class TrialProgress(ProgressBar):
    """A bar over trials, `progress(done, total, failed)`; it ends at total / total."""

    def __call__(self, done: int, total: int, failed: int) -> None:
        label = f"{done:{len(str(total))}d} / {total} trials, {failed} failed"
        self.show(done / total if total else 1.0, label, done >= total)


class _Tally:
    """The outcomes so far, in spec order, and the progress callback fed as they arrive."""

    def __init__(self, total: int, progress: Progress | None):
        self._outcomes: list[TrialOutcome | None] = [None] * total
        self._progress = progress
        self._done = 0
        self._failed = 0

    def record(self, outcome: TrialOutcome) -> None:
        self._outcomes[outcome.index] = outcome
        self._done += 1
        self._failed += not outcome.ok
        if self._progress is not None:
            self._progress(self._done, len(self._outcomes), self._failed)

    def outcomes(self) -> list[TrialOutcome]:
        missing = [index for index, outcome in enumerate(self._outcomes) if outcome is None]
        assert not missing, f"trials without an outcome: {missing}"
        return list(self._outcomes)  # type: ignore[arg-type]


def _call(function: Callable[[Any], Any], index: int, spec: Any) -> TrialOutcome:
    """Run one trial wherever it is: here, in a pool worker or in a Ray task."""
    start = time.perf_counter()
    try:
        result = function(spec)
    # SystemExit too: a trial calling sys.exit() fails itself, not the serial run around it.
    except (Exception, SystemExit) as exc:
        return TrialOutcome(index, False, None, _reason(exc), time.perf_counter() - start)
    return TrialOutcome(index, True, result, "", time.perf_counter() - start)


def _reason(exc: BaseException) -> str:
    """ "Type: first line of the message", short enough for a table cell."""
    lines = str(exc).strip().splitlines()
    text = f"{type(exc).__name__}: {lines[0].strip()}" if lines else type(exc).__name__
    return text if len(text) <= _MAX_REASON else text[: _MAX_REASON - 3] + "..."


def _worker_count(workers: int | None, trials: int) -> int:
    if workers is None:
        workers = os.cpu_count() or 1
    if workers < 1:
        raise ValueError(f"workers: expected at least 1, got {workers}")
    return min(workers, trials)


def _run_here(function: Callable[[Any], Any], specs: list[Any], tally: _Tally) -> None:
    for index, spec in enumerate(specs):
        tally.record(_call(function, index, spec))


# --- local worker processes ----------------------------------------------------------------

# In a pool worker: when each trial started (time.time(), 0.0 = not yet), shared with the
# parent, which is how it tells a trial that was running when a worker died from one still
# pending (a BrokenProcessPool fails both alike).
_started: Any = None


def _init_worker(started: Any) -> None:
    global _started
    _started = started


def _pool_call(function: Callable[[Any], Any], index: int, spec: Any) -> TrialOutcome:
    _started[index] = time.time()
    return _call(function, index, spec)


def _run_in_pools(
    function: Callable[[Any], Any], specs: list[Any], workers: int, tally: _Tally
) -> None:
    """Pools of at most TRIALS_PER_WORKER trials a worker, one after another. When a worker
    died, the trials that had not started run in the next pool, so one crash does not fail the
    batch; a death in two pools in a row fails what is left."""
    pending, died, size = list(range(len(specs))), False, workers * TRIALS_PER_WORKER
    while pending:
        batch, rest = pending[:size], pending[size:]
        lost = _pool_round(function, specs, batch, workers, tally)
        if lost and died:
            _settle_lost({**lost, **dict.fromkeys(rest, 0.0)}, tally, retry=False)
            return
        pending = _settle_lost(lost, tally, retry=True) + rest
        died = bool(lost)


def _pool_round(
    function: Callable[[Any], Any],
    specs: list[Any],
    indices: list[int],
    workers: int,
    tally: _Tally,
) -> dict[int, float]:
    """Run `indices` in a fresh pool; the trials lost to a dead worker, with their start times
    (0.0 for those that had not started)."""
    # spawn, not fork: Drake and numba do not survive a fork of a process that has used them.
    context = multiprocessing.get_context("spawn")
    started = context.Array("d", len(specs), lock=False)
    executor = ProcessPoolExecutor(
        min(workers, len(indices)),
        mp_context=context,
        initializer=_init_worker,
        initargs=(started,),
    )
    try:
        lost = _stream_pool(executor, function, specs, indices, tally)
    except BaseException:
        # Ctrl-C (or a failing progress callback): drop the pending trials, let running ones end.
        executor.shutdown(wait=False, cancel_futures=True)
        raise
    executor.shutdown(wait=True)
    return {index: started[index] for index in lost}


def _stream_pool(
    executor: ProcessPoolExecutor,
    function: Callable[[Any], Any],
    specs: list[Any],
    indices: list[int],
    tally: _Tally,
) -> list[int]:
    """Submit, then record outcomes as trials finish; the indices lost to a broken pool."""
    futures = {}
    lost: list[int] = []
    for position, index in enumerate(indices):
        try:
            futures[executor.submit(_pool_call, function, index, specs[index])] = index
        except BrokenProcessPool:  # a worker died while the batch was still being submitted
            lost.extend(indices[position:])
            break
    waiting = set(futures)
    while waiting:
        done, waiting = wait(waiting, return_when=FIRST_COMPLETED)
        for future in done:
            index = futures[future]
            exc = future.exception()
            if isinstance(exc, BrokenProcessPool):
                lost.append(index)
            elif isinstance(exc, KeyboardInterrupt):
                raise exc
            elif exc is not None:  # the pool itself failed the trial, e.g. an unpicklable result
                tally.record(TrialOutcome(index, False, None, _reason(exc), 0.0))
            else:
                tally.record(future.result())
    return lost


def _settle_lost(lost: dict[int, float], tally: _Tally, retry: bool) -> list[int]:
    """Fail the lost trials that were running; the ones that had not started are returned to
    run again if `retry`, failed otherwise."""
    now = time.time()
    again = []
    for index, started in sorted(lost.items()):
        if started > 0.0:
            tally.record(TrialOutcome(index, False, None, CRASHED, max(now - started, 0.0)))
        elif retry:
            again.append(index)
        else:
            tally.record(TrialOutcome(index, False, None, NOT_RUN, 0.0))
    return again


# --- Ray ---------------------------------------------------------------------------------


def _import_ray() -> Any:
    # Ray is an optional extra (`hsr_handover[cluster]`): imported only when asked for.
    try:
        import ray
    except ImportError as exc:
        raise ClusterUnavailable(RAY_MISSING) from exc
    return ray


RAY_CONNECT_TIMEOUT_S = 5.0
"""s to wait for the cluster's address to answer: Ray itself retries an address where nothing
listens for minutes."""


def _check_reachable(address: str) -> None:
    """Raise ClusterUnavailable at once when nothing answers at `address` ("host:port" or
    "ray://host:port"; other forms, such as "auto", are left to Ray)."""
    target = address.removeprefix("ray://")
    host, _, port = target.rpartition(":")
    if not host or not port.isdigit():
        return
    try:
        socket.create_connection((host.strip("[]"), int(port)), RAY_CONNECT_TIMEOUT_S).close()
    except OSError as error:
        reason = f"nothing answers at {target} ({error.strerror or error})"
        raise ClusterUnavailable(f"--ray-address: no Ray cluster at {address}: {reason}") from None


def _run_on_ray(
    function: Callable[[Any], Any], specs: list[Any], address: str, tally: _Tally
) -> None:
    ray = _import_ray()
    connected_here = not ray.is_initialized()
    if connected_here:
        _check_reachable(address)
        try:
            ray.init(address=address)
        except ConnectionError as exc:
            reason = first_line(exc)
            message = f"--ray-address: no Ray cluster at {address}: {reason}"
            raise ClusterUnavailable(message) from exc
    try:
        _stream_ray(ray, function, specs, tally)
    finally:
        if connected_here:
            ray.shutdown()


def _stream_ray(ray: Any, function: Callable[[Any], Any], specs: list[Any], tally: _Tally) -> None:
    """One task per trial, outcomes recorded as `ray.wait` hands them back."""
    # One retry of a task whose worker or node died, like the local pool's one fresh pool; a
    # worker process is replaced after TRIALS_PER_WORKER trials, as locally.
    remote = ray.remote(max_retries=1, max_calls=TRIALS_PER_WORKER)(_call)
    refs = {remote.remote(function, index, spec): index for index, spec in enumerate(specs)}
    waiting = list(refs)
    try:
        while waiting:
            ready, waiting = ray.wait(waiting, num_returns=1)
            for ref in ready:
                tally.record(_ray_outcome(ray, ref, refs[ref]))
    except BaseException:
        for ref in waiting:
            ray.cancel(ref)
        raise


def _ray_outcome(ray: Any, ref: Any, index: int) -> TrialOutcome:
    """The task's outcome, or a failed one if Ray lost it (`_call` itself catches the trial's
    own exceptions)."""
    try:
        return ray.get(ref)
    except Exception as exc:  # WorkerCrashedError, a module the cluster cannot import, ...
        # RayTaskError's own first line is "ray::_call() (pid=..., ip=...)": the cause says more.
        cause = getattr(exc, "cause", None)
        reason = _reason(cause if isinstance(cause, BaseException) else exc)
        return TrialOutcome(index, False, None, reason, 0.0)
