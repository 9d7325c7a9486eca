"""The replay in a real browser (headless Chromium, software WebGL): it opens from a file://
URL with no console error and no network request, draws the scene, and moves with the
recording; a browser without WebGL is told so in words."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import Box, Rgba
from pydrake.math import RigidTransform

from hsr_handover.replay.cycle_visualizer import CYCLE
from hsr_handover.replay.meshcat_replay import (
    WEBGL_MISSING,
    make_local_meshcat,
    start_recording,
    write_replay,
)
from tests.browser import (
    changed_pixels,
    distinct_colours,
    open_replay,
    red_mask,
    red_pixels,
    require_browser,
)

REPLAY_LIMIT_BYTES = 15_000_000  # the bound for a 20 s run at the default replay rate


@pytest.fixture(scope="module")
def moving_box(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A replay of a red box sliding 1 m along x over 2 s."""
    require_browser()
    meshcat = make_local_meshcat()
    start_recording(meshcat, 20.0)
    meshcat.SetObject("/box", Box(0.3, 0.3, 0.3), Rgba(0.9, 0.1, 0.1, 1.0))
    for step in range(41):
        time = 0.05 * step
        meshcat.SetTransform("/box", RigidTransform([time / 2, 0.0, 0.15]), time_in_recording=time)
    return write_replay(meshcat, tmp_path_factory.mktemp("replay") / "box.html")


def test_a_recorded_motion_plays_back_where_it_was_recorded(moving_box: Path):
    with open_replay(moving_box) as replay:
        replay.wait_for_viewer()
        start, end = replay.frame(0.0), replay.frame(2.0)
        assert replay.errors == [] and replay.network_requests() == []
        assert replay.duration() == pytest.approx(2.0, abs=0.06)
        assert not replay.page.locator("#webgl-missing").is_visible()
    assert distinct_colours(start) > 50  # a drawn scene, not a blank canvas
    red_start, red_end = np.argwhere(red_mask(start)), np.argwhere(red_mask(end))
    assert len(red_start) > 200 and len(red_end) > 200  # the box, in both frames
    assert abs(red_end[:, 1].mean() - red_start[:, 1].mean()) > 20  # moved across the view


def test_a_browser_without_webgl_is_told_so_in_words(moving_box: Path):
    with open_replay(moving_box, webgl=False) as replay:
        notice = replay.page.locator("#webgl-missing")
        notice.wait_for(state="visible", timeout=30_000)
        assert WEBGL_MISSING.split(".")[0] in notice.inner_text()


def test_the_demo_handover_replays_with_the_robot_moving_and_its_mutual_area(demo):
    size = demo.replay.stat().st_size
    assert size < REPLAY_LIMIT_BYTES * demo.report.sim_time / 20.0
    times = demo.report.cycle.phase_times
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        assert replay.duration() == pytest.approx(demo.report.sim_time, abs=0.2)
        watching, handing_over = replay.frame(1.0), replay.frame(times["release"])
        carrying = replay.frame(times["carry"] + 1.0)
        replay.set_visible(f"{CYCLE}/mutual_area", False)
        carrying_without = replay.frame(times["carry"] + 1.0)
        assert replay.errors == [] and replay.network_requests() == []
    for frame in (watching, handing_over):
        assert distinct_colours(frame) > 200
    # The arm out at the person against the robot standing ready: a large part of the view.
    assert changed_pixels(watching, handing_over) > 0.02 * watching.shape[0] * watching.shape[1]
    # The mutual area's red nodes, on from the carry's plan, and gone when switched off.
    assert red_pixels(carrying) - red_pixels(carrying_without) > 50
