"""Toy trials for tests/test_trials.py. They live in a module of their own, at top level, so
`spawn` workers and Ray workers can import them by name (`tests.trial_functions`)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np


def draw(spec: dict) -> list[float]:
    """Random numbers from the spec's own seed: the same whichever worker draws them."""
    rng = np.random.default_rng(spec["seed"])
    return rng.normal(size=4).tolist()


def sleep_then_finish(spec: dict) -> dict:
    """Sleep for the spec's time, then say when this trial finished."""
    time.sleep(spec["sleep"])
    return {"value": spec["value"], "finished": time.time()}


def fail_if_asked(spec: dict) -> int:
    if spec.get("fail"):
        raise ValueError("no depth image\nand a second line the reason leaves out")
    return spec["value"]


def exit_if_asked(spec: dict) -> int:
    """`os._exit(1)` (a worker dying without a word) when the spec says so, once the file
    `spec["release"]` exists (if one is named), so the test decides when the crash happens."""
    if spec.get("exit"):
        release = spec.get("release")
        deadline = time.monotonic() + 30.0
        while release is not None and not Path(release).exists() and time.monotonic() < deadline:
            time.sleep(0.02)
        os._exit(1)
    time.sleep(spec.get("sleep", 0.0))
    return spec["value"]


def interrupt(spec: dict) -> None:
    raise KeyboardInterrupt


def fail_or_exit_or_draw(spec: dict) -> list[float]:
    """All three kinds of trial in one batch (the Ray test starts its cluster once)."""
    if spec.get("fail"):
        fail_if_asked(spec)
    if spec.get("exit"):
        exit_if_asked(spec)
    return draw(spec)


def worker_pid(spec: dict) -> int:
    """The process that ran this trial."""
    time.sleep(spec.get("sleep", 0.0))
    return os.getpid()
