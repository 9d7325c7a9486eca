"""What the experiments' reports share: Wilson intervals on rates, figures by their suffix."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from hsr_handover.experiments.reporting import (  # noqa: E402
    PNG_DPI,
    bars_beside_paper,
    save_figure,
    wilson_interval,
)


def test_the_wilson_interval_matches_its_closed_form():
    for successes, trials in ((56, 60), (0, 10), (10, 10), (3, 7)):
        z, p = 1.959963984540054, successes / trials
        centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
        half = z / (1 + z * z / trials) * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials**2))
        low, high = wilson_interval(successes, trials)
        assert low == pytest.approx(max(centre - half, 0.0), abs=1e-9)
        assert high == pytest.approx(min(centre + half, 1.0), abs=1e-9)
    assert all(math.isnan(v) for v in wilson_interval(0, 0))


@pytest.mark.parametrize(
    "suffix, head", [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")]
)
def test_a_figure_is_written_in_the_format_its_suffix_names(tmp_path, suffix, head):
    figure, axes = plt.subplots(figsize=(2.0, 1.5))
    axes.plot([0, 1], [0, 1])
    path = tmp_path / f"figure{suffix}"
    save_figure(figure, path)
    assert path.read_bytes().startswith(head)
    if suffix == ".png":
        width, height = (int.from_bytes(path.read_bytes()[16 + 4 * k : 20 + 4 * k], "big")
                         for k in range(2))  # fmt: skip
        assert (width, height) == (2 * PNG_DPI, int(1.5 * PNG_DPI))


def test_a_figure_with_another_suffix_is_refused(tmp_path):
    figure, _ = plt.subplots()
    with pytest.raises(ValueError, match="expected a suffix in"):
        save_figure(figure, tmp_path / "figure.jpg")
    plt.close(figure)


def test_the_bars_carry_their_counts_and_intervals():
    figure, axes = plt.subplots()
    bars_beside_paper(axes, ["left", "right"], [(4, 4), (1, 4)], [(47, 60), (56, 60)])
    texts = [text.get_text() for text in axes.texts]
    assert texts == ["100.0 %\n4/4", "25.0 %\n1/4", "78.3 %\n47/60", "93.3 %\n56/60"]
    errorbars = [c for c in axes.containers if hasattr(c, "lines")]
    spans = [seg[:, 1] for c in errorbars for col in c.lines[2] for seg in col.get_segments()]
    low, high = wilson_interval(1, 4)
    assert any(np.allclose(span, [100 * low, 100 * high]) for span in spans)
    plt.close(figure)
