"""The replay's legend: one row per overlay drawn, in its colour, under one root; the script
that keeps the overlays' children out of the viewer's controls."""

from __future__ import annotations

import json
import re

import numpy as np
from pydrake.geometry import Sphere

from hsr_handover.replay.legend import LEGEND_ID, legend_html, with_legend
from hsr_handover.replay.meshcat_replay import make_local_meshcat, start_recording, write_replay
from hsr_handover.replay.overlays import (
    CATALOGUE,
    MUTUAL_AREA,
    OVERLAYS,
    SCENE_MAP,
    TARGET,
    draw_points,
    drawn_overlays,
    swatch_css,
)

ROWS = re.compile(r'<li data-overlay="([a-z_]+)"><span class="swatch" style="background: ([^"]+)"')


def test_every_overlay_has_its_own_path_under_the_one_root():
    paths = [overlay.path for overlay in CATALOGUE]
    assert len(set(paths)) == len(paths)
    assert all(path.startswith(f"{OVERLAYS}/") and path.count("/") == 2 for path in paths)


def test_the_legend_names_each_overlay_drawn_in_its_colour(tmp_path):
    meshcat = make_local_meshcat()
    start_recording(meshcat, 20.0)
    draw_points(meshcat, f"{MUTUAL_AREA.path}/0000", np.zeros((3, 3)), MUTUAL_AREA.rgba)
    meshcat.SetObject(TARGET.mark, Sphere(0.08), TARGET.rgba)
    assert drawn_overlays(meshcat) == [TARGET, MUTUAL_AREA]  # in the legend's order
    page = write_replay(meshcat, tmp_path / "replay.html").read_text()
    assert page.count(f'id="{LEGEND_ID}"') == 1
    assert ROWS.findall(page) == [("target", swatch_css(TARGET)),
                                  ("mutual_area", "rgba(230, 26, 26, 1.00)")]  # fmt: skip
    assert TARGET.label in page and MUTUAL_AREA.label in page
    assert swatch_css(TARGET).endswith("0.60)")  # a translucent colour, still seen


def test_the_tidy_script_lists_the_overlays_drawn():
    page = with_legend("<html><body></body></html>", [SCENE_MAP, TARGET])
    (layers,) = re.findall(r"var layers = (\[.*?\]);", page)
    assert json.loads(layers) == [["overlays", "scene_map"], ["overlays", "target"]]
    assert page.index(f'id="{LEGEND_ID}"') < page.index("</body>")


def test_a_replay_with_no_overlay_has_no_legend():
    assert with_legend("<html><body></body></html>", []) == "<html><body></body></html>"
    assert "scene map" in legend_html([SCENE_MAP])
