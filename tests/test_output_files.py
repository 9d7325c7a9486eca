"""A command's outputs are written together: all of them, or none and no temporary."""

from __future__ import annotations

import pytest

from hsr_handover.output_files import partial_name, write_together


def _write(text: str):
    return lambda path: path.write_text(text)


def test_every_output_lands_at_its_path_once_all_are_written(tmp_path):
    seen = []
    csv, figure = tmp_path / "rows.csv", tmp_path / "figure.svg"

    def plot(path):
        seen.append(path)
        assert not csv.exists()  # nothing is in place while another is still being written
        path.write_text("<svg/>")

    write_together({csv: _write("a,b\n"), figure: plot})
    assert csv.read_text() == "a,b\n" and figure.read_text() == "<svg/>"
    assert seen == [partial_name(figure)] and seen[0].suffix == ".svg"  # the format is kept
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figure.svg", "rows.csv"]


def test_a_failing_output_leaves_none_behind(tmp_path):
    def broken(path):
        path.write_text("half a figure")
        raise RuntimeError("the figure failed")

    outputs = {tmp_path / "rows.csv": _write("a\n"), tmp_path / "summary.json": _write("{}"),
               tmp_path / "figure.png": broken}  # fmt: skip
    with pytest.raises(RuntimeError, match="the figure failed"):
        write_together(outputs)
    assert list(tmp_path.iterdir()) == []


def test_an_existing_output_is_only_replaced_when_all_succeed(tmp_path):
    summary = tmp_path / "summary.json"
    summary.write_text("old")
    with pytest.raises(ZeroDivisionError):
        write_together({summary: _write("new"), tmp_path / "x.csv": lambda path: 1 / 0})
    assert summary.read_text() == "old"
