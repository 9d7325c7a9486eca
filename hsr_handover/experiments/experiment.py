"""What the trial experiments (intent, handover) share: the trials as run with their outcomes
and settings, one row per trial whether it ran or crashed, and running them."""

from __future__ import annotations

import dataclasses
import os
import re
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hsr_handover.experiments.layouts import layout_columns
from hsr_handover.experiments.trial_classes import trial_classes
from hsr_handover.experiments.trials import Progress, TrialOutcome, run_trials
from hsr_handover.scenario import Scenario


@dataclasses.dataclass
class TrialExperiment:
    """The trials as run, their outcomes, and the settings that made them. A subclass says what
    a crashed trial's row holds (`crashed_row`)."""

    trials: list[Any]
    outcomes: list[TrialOutcome]
    base: Scenario
    seed: int
    wall_s: float
    layouts: str = "scenario"

    def rows(self) -> list[dict]:
        """One row per trial: the trial's own result, or what it was and why it crashed; each
        with what `described` says of the trial."""
        return [
            {**self.described(trial), "error": "", **outcome.result} if outcome.ok
            else {**self.described(trial), **self.crashed_row(trial), "index": trial.index,
                  "error": outcome.error}
            for trial, outcome in zip(self.trials, self.outcomes, strict=True)
        ]  # fmt: skip

    def crashed_row(self, trial: Any) -> dict:
        """What a crashed trial's row says of it besides its index and error."""
        raise NotImplementedError

    def described(self, trial: Any) -> dict:
        """What every row says of its trial, ran or crashed: the classes of its layout
        (`trial_classes`) and the layout drawn for it (`layout_*`, when generated)."""
        return {**trial_classes(trial.scenario), **layout_columns(trial.layout)}

    @classmethod
    def run(
        cls,
        make_trials: Callable[[Scenario, int, int, int], list[Any]],
        run_trial: Callable[[Any], dict],
        base: Scenario,
        counts: tuple[int, int],
        seed: int,
        workers: int | None,
        ray_address: str | None,
        progress: Progress | None,
        html_dir: Path | None = None,
        layouts: str = "scenario",
        scenario_dir: Path | None = None,
    ):
        """Make the trials (`make_trials(base, *counts, seed, layouts=layouts)`) and run them;
        with `html_dir`, each trial writes its replay there (`replay_name`), with
        `scenario_dir` its scenario as it runs."""
        start = time.perf_counter()
        specs = make_trials(base, *counts, seed, layouts=layouts)
        if html_dir is not None:
            specs = [dataclasses.replace(spec, replay_dir=str(html_dir)) for spec in specs]
        if scenario_dir is not None:
            specs = [dataclasses.replace(spec, scenario_dir=str(scenario_dir)) for spec in specs]
        outcomes = run_trials(run_trial, specs, workers, ray_address, progress)
        return cls(specs, outcomes, base, seed, time.perf_counter() - start, layouts)


def rate(hits: int, count: int) -> float:
    """hits / count, NaN when there is nothing to count."""
    return hits / count if count else float("nan")


def replay_name(index: int, outcome: str) -> str:
    """A trial's replay file: `trial_007_person-contact.html` (index, then outcome)."""
    slug = re.sub(r"[^a-z0-9]+", "-", outcome.lower()).strip("-") or "unknown"
    return f"trial_{index:03d}_{slug}.html"


def replay_while_running(replay_dir: str, index: int) -> Path | None:
    """Where a trial writes its replay until its outcome is known (None: no replay asked)."""
    return Path(replay_dir) / f".trial_{index:03d}.html" if replay_dir else None


def name_replay(written: Path | None, index: int, outcome: str) -> None:
    """Give a written replay its final name, by trial and outcome."""
    if written is not None:
        os.replace(written, written.parent / replay_name(index, outcome))
