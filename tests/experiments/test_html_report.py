"""An experiment's report page (`--report DIR`): the rates beside the paper's with their
intervals, the figure embedded, the trials sortable and linked to their replays; in a real
browser, and from the command line."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from hsr_handover.cli import main  # noqa: E402
from hsr_handover.experiments.html_report import RateRow, write_report  # noqa: E402
from hsr_handover.experiments.intent import trial as intent_trial  # noqa: E402
from hsr_handover.experiments.intent.trial import IntentExperiment  # noqa: E402
from hsr_handover.experiments.intent.trials import make_trials  # noqa: E402
from hsr_handover.experiments.trials import TrialOutcome  # noqa: E402
from hsr_handover.scenario import load_scenario  # noqa: E402
from tests.browser import open_replay  # noqa: E402
from tests.paths import SCENARIOS  # noqa: E402

ROWS = [
    {"index": 0, "target": "red_cup", "latency_s": 2.5, "recognised": True},
    {"index": 1, "target": "<script>alert(1)</script>", "latency_s": math.nan, "recognised": False},
    {"index": 2, "target": "blue_cup", "latency_s": 1.25, "recognised": True},
    {"index": 3, "target": "green_cup", "latency_s": 10.0, "recognised": True},
]
COLUMNS = ("index", "target", "latency_s", "recognised")


def _plot(path: Path) -> None:
    figure, axes = plt.subplots(figsize=(2, 2))
    axes.plot([0, 1], [1, 0])
    figure.savefig(path)
    plt.close(figure)


@pytest.fixture
def page(tmp_path) -> Path:
    replays = tmp_path / "replays"
    replays.mkdir()
    for index in (0, 2):
        (replays / f"trial_{index:03d}_recognised.html").write_text("<html></html>")
    rates = [RateRow("recognised, right", (9, 10), (56, 60)), RateRow("false triggers", (0, 4))]
    (tmp_path / "report").mkdir()
    return write_report(tmp_path / "report", "A title", rates, ["line one", "a < b"], _plot,
                        ROWS, COLUMNS, replays)  # fmt: skip


def test_the_page_holds_the_rates_the_figure_and_the_trials(tmp_path):
    (tmp_path / "report").mkdir()
    (tmp_path / "replays").mkdir()
    (tmp_path / "replays" / "trial_002_recognised.html").write_text("")
    rates = [RateRow("recognised, right", (56, 60), (56, 60)), RateRow("false triggers", (0, 4))]
    path = write_report(tmp_path / "report", "A title", rates, ["a < b"], _plot, ROWS, COLUMNS,
                        tmp_path / "replays")  # fmt: skip
    text = path.read_text()
    assert path.name == "index.html"
    assert "<td>93.3 %</td><td>84.1-97.4 %</td><td>56/60</td>" in text  # Wilson's interval
    assert text.count("<td>n/a</td>") == 1  # no paper figure for false triggers
    assert "data:image/png;base64," in text and "a &lt; b" in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text and "<script>alert" not in text
    assert text.count("<a href=") == 1 and "href='../replays/trial_002_recognised.html'" in text
    assert "Trials (4)" in text


def test_in_a_browser_the_trials_sort_by_a_column_and_link_to_their_replays(page):
    with open_replay(page, webgl=False) as opened:
        browser = opened.page

        def column(name: str) -> list[str]:
            position = COLUMNS.index(name) + 1
            return browser.eval_on_selector_all(
                f"#trials tbody tr td:nth-child({position})",
                "cells => cells.map(c => c.textContent)",
            )

        browser.click("#trials th:has-text('latency_s')")
        assert column("latency_s") == ["1.25", "2.5", "10", ""]  # numbers as numbers, blank last
        browser.click("#trials th:has-text('latency_s')")
        assert column("latency_s") == ["10", "2.5", "1.25", ""]
        links = browser.eval_on_selector_all("#trials a", "links => links.map(a => a.href)")
        assert len(links) == 2
        assert all(Path(link.removeprefix("file://")).exists() for link in links)
        assert opened.errors == [] and opened.network_requests() == []


def test_the_command_writes_the_report_beside_its_other_outputs(tmp_path, monkeypatch, capsys):
    """The experiment's trials stand in (the trials themselves are tested elsewhere): the page
    lists every trial, failed ones too."""
    base = load_scenario(SCENARIOS / "intent_reference.yaml")

    def run(scenario, trials, distractors, seed, *rest):
        specs = make_trials(scenario, trials, distractors, seed)
        outcomes = [
            TrialOutcome(spec.index, spec.index != 1, {"index": spec.index, "kind": spec.kind,
                         "target": spec.target, "arm": spec.arm, "recognised": spec.target,
                         "latency_s": 1.0} if spec.index != 1 else None,
                         "" if spec.index != 1 else "ValueError: boom", 1.0)
            for spec in specs
        ]  # fmt: skip
        return IntentExperiment(specs, outcomes, base, seed, 1.0)

    monkeypatch.setattr(intent_trial, "run_intent_experiment", run)
    report = tmp_path / "report"
    code = main(["experiment", "intent", str(SCENARIOS / "intent_reference.yaml"), "--trials",
                 "3", "--distractors", "1", "--report", str(report)])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    text = (report / "index.html").read_text()
    assert "Trials (4)" in text and "ValueError: boom" in text
    assert f"wrote {report / 'index.html'}" in capsys.readouterr().out
