"""An experiment's report as one self-contained HTML page (`--report DIR`): the rates beside the
paper's with their 95 % intervals, the figure, the text summary, and the per-trial table, sortable
by any column, each trial linked to its replay when the trials wrote replays (`--html-dir`).

Nothing is fetched: the figure is embedded, the sorting is a few lines of inline script, and a
replay link is a path relative to the page.
"""

from __future__ import annotations

import base64
import html
import os
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import NamedTuple

from hsr_handover.experiments.reporting import format_cell, wilson_interval

PAGE = "index.html"


class RateRow(NamedTuple):
    """One rate of the summary table: ours and, where the paper has it, the paper's, each as
    (successes, trials)."""

    name: str
    ours: tuple[int, int]
    paper: tuple[int, int] | None = None


_STYLE = """
body { font-family: sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
th { background: #eee; }
#trials th { cursor: pointer; }
#trials th.sorted::after { content: " \\25B2"; }
#trials th.sorted.descending::after { content: " \\25BC"; }
td.text { text-align: left; }
img { max-width: 100%; }
pre { background: #f6f6f6; padding: 0.8em; white-space: pre-wrap; }
"""

# Click a header to sort by it; click again to reverse. Numbers sort as numbers, blanks last.
_SORT = """
document.querySelectorAll('#trials th').forEach((header, column) => {
  header.addEventListener('click', () => {
    const body = document.querySelector('#trials tbody');
    const descending = header.classList.contains('sorted') &&
                       !header.classList.contains('descending');
    const headers = document.querySelectorAll('#trials th');
    headers.forEach(h => h.classList.remove('sorted', 'descending'));
    header.classList.add('sorted');
    if (descending) header.classList.add('descending');
    const key = row => row.children[column].dataset.sort ?? row.children[column].textContent;
    const rows = Array.from(body.rows);
    rows.sort((a, b) => {
      const x = key(a), y = key(b);
      if (x === '' || y === '') return (x === '') - (y === '');
      const nx = Number(x), ny = Number(y);
      const order = isNaN(nx) || isNaN(ny) ? x.localeCompare(y) : nx - ny;
      return descending ? -order : order;
    });
    rows.forEach(row => body.appendChild(row));
  });
});
"""


def write_report(
    directory: Path,
    title: str,
    rates: Sequence[RateRow],
    summary_lines: Sequence[str],
    plot: Callable[[Path], None],
    rows: Sequence[dict],
    columns: Sequence[str],
    replays: Path | None = None,
) -> Path:
    """Write `directory`/index.html and return its path. `plot(path)` draws the figure;
    `rows` are the per-trial rows shown in `columns`; with `replays`, the folder the trials'
    replays were written to, each row links to its trial's."""
    directory = Path(directory)
    parts = [
        f"<h1>{html.escape(title)}</h1>",
        _rates_table(rates),
        f'<img alt="the figure" src="data:image/png;base64,{_figure_png(plot)}">',
        f"<pre>{html.escape(chr(10).join(summary_lines))}</pre>",
        f"<h2>Trials ({len(rows)})</h2>",
        _trials_table(rows, columns, _replay_links(rows, replays, directory)),
    ]
    page = (
        "<!DOCTYPE html>\n<html><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>\n"
        + "\n".join(parts)
        + f"\n<script>{_SORT}</script></body></html>\n"
    )
    path = directory / PAGE
    path.write_text(page)
    return path


def _figure_png(plot: Callable[[Path], None]) -> str:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "figure.png"
        plot(path)
        return base64.b64encode(path.read_bytes()).decode("ascii")


def _rate_cells(counts: tuple[int, int] | None) -> str:
    if counts is None or not counts[1]:
        return "<td>n/a</td><td></td><td></td>"
    successes, trials = counts
    low, high = wilson_interval(successes, trials)
    return (f"<td>{100 * successes / trials:.1f} %</td><td>{100 * low:.1f}-{100 * high:.1f} %"
            f"</td><td>{successes}/{trials}</td>")  # fmt: skip


def _rates_table(rates: Sequence[RateRow]) -> str:
    header = ("<tr><th></th><th>ours</th><th>95 % interval</th><th>trials</th>"
              "<th>paper</th><th>95 % interval</th><th>trials</th></tr>")  # fmt: skip
    body = "".join(
        f"<tr><td class='text'>{html.escape(rate.name)}</td>{_rate_cells(rate.ours)}"
        f"{_rate_cells(rate.paper)}</tr>"
        for rate in rates
    )
    return f"<table id='rates'>{header}{body}</table>"


def _replay_links(rows: Sequence[dict], replays: Path | None, page_dir: Path) -> dict[int, str]:
    """Trial index -> the replay's path relative to the page, for the replays that exist (the
    folder read once: `trial_007_<outcome>.html`, `experiment.replay_name`)."""
    if replays is None:
        return {}
    written = {}
    for path in sorted(Path(replays).glob("trial_*_*.html")):
        index = path.name.split("_")[1]
        if index.isdigit():
            written.setdefault(int(index), path)
    wanted = {int(row["index"]) for row in rows}
    return {i: os.path.relpath(path, page_dir) for i, path in written.items() if i in wanted}


def _trials_table(rows: Sequence[dict], columns: Sequence[str], links: dict[int, str]) -> str:
    shown = [*columns, "replay"] if links else list(columns)
    header = "".join(f"<th>{html.escape(column)}</th>" for column in shown)
    body = []
    for row in rows:
        cells = [_cell(row.get(column, "")) for column in columns]
        if links:
            target = links.get(int(row["index"]))
            link = f"<a href='{html.escape(target)}'>replay</a>" if target else ""
            cells.append(f"<td class='text'>{link}</td>")
        body.append(f"<tr>{''.join(cells)}</tr>")
    return (f"<table id='trials'><thead><tr>{header}</tr></thead>"
            f"<tbody>{''.join(body)}</tbody></table>")  # fmt: skip


def _cell(value) -> str:
    if isinstance(value, bool):
        return f"<td data-sort='{int(value)}'>{'yes' if value else 'no'}</td>"
    if isinstance(value, float):
        shown = "" if value != value else format_cell(value)
        return f"<td data-sort='{shown}'>{shown}</td>"
    if isinstance(value, int):
        return f"<td>{value}</td>"
    return f"<td class='text'>{html.escape(str(value))}</td>"
