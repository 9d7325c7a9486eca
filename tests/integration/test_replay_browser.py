"""The replay in a real browser (headless Chromium, software WebGL): it opens from a file://
URL with no console error and no network request, draws the scene, and moves with the
recording; a browser without WebGL is told so in words. On the demo's replay, the overlays
tell the truth over time (the rays only while the robot watches, the halo on the held object,
the scene map grey at rest), a user's untick holds through play and seek, and the legend names
each overlay. Each test prints the pixel counts it measured (`pytest -s`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import Box, Rgba
from pydrake.math import RigidTransform

from hsr_handover.replay.meshcat_replay import (
    WEBGL_MISSING,
    make_local_meshcat,
    start_recording,
    write_replay,
)
from hsr_handover.replay.overlays import (
    ARM_MAP,
    GAZE_RAY,
    HANDOVER_POINT,
    MUTUAL_AREA,
    OVERLAYS,
    PALM_PATH,
    PERSON_RANGE,
    POINTING_RAY,
    SCENE_MAP,
    TARGET,
    Overlay,
)
from tests.browser import (
    changed_pixels,
    distinct_colours,
    open_replay,
    red_mask,
    red_pixels,
    require_browser,
)
from tests.meshcat_html import meshcat_commands, visibility_keys

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
        replay.set_visible(MUTUAL_AREA.path, False)
        carrying_without = replay.frame(times["carry"] + 1.0)
        assert replay.errors == [] and replay.network_requests() == []
    for frame in (watching, handing_over):
        assert distinct_colours(frame) > 200
    # The arm out at the person against the robot standing ready: a large part of the view.
    assert changed_pixels(watching, handing_over) > 0.02 * watching.shape[0] * watching.shape[1]
    # The mutual area's red nodes, on from the carry's plan, and gone when switched off.
    assert red_pixels(carrying) - red_pixels(carrying_without) > 50


DEMO_OVERLAYS = (SCENE_MAP, POINTING_RAY, GAZE_RAY, TARGET, PALM_PATH, ARM_MAP, PERSON_RANGE,
                 MUTUAL_AREA, HANDOVER_POINT)  # fmt: skip
OVERLAY_PIXELS = 20  # changed pixels that say an overlay is drawn (a 640 x 480 view)
SAME_PIXELS = 5  # changed pixels two renders of one scene may differ by
GREY = 0x9E9E9E  # overlays.RESTING_RGBA as three.js holds it


def _shown_intervals(replay: Path, path: str, end: float) -> list[tuple[float, float]]:
    """The [start, stop) intervals in which the recording shows `path` (until `end`)."""
    keys = visibility_keys(meshcat_commands(replay.read_bytes()))[path]
    stops = [time for time, _ in keys[1:]] + [end]
    return [(time, stop) for (time, shown), stop in zip(keys, stops, strict=True) if shown]


def _on_and_off(replay, overlay: Overlay, time: float) -> int:
    """Pixels the overlay changes at `time`: drawn, then switched off on its own path."""
    on = replay.frame(time)
    replay.set_visible(overlay.path, False)
    off = replay.frame(time)
    replay.set_visible(overlay.path, True)
    return changed_pixels(on, off)


def test_the_rays_show_while_the_robot_watches_and_are_gone_at_10_s(demo):
    last_start, last_stop = _shown_intervals(demo.replay, POINTING_RAY.mark, demo.report.sim_time)[
        -1
    ]
    assert last_stop < demo.report.cycle.phase_times["approach"] + 0.5  # it rests once it acts
    seen = (last_start + last_stop) / 2
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        drawn = {time: _on_and_off(replay, POINTING_RAY, time) for time in (seen, 10.0)}
        replay.frame(seen)
        shown_then = replay.shown(POINTING_RAY.mark)
        replay.frame(10.0)
        shown_at_10 = [replay.shown(overlay.mark) for overlay in (POINTING_RAY, GAZE_RAY)]
        assert replay.errors == []
    print(f"pointing ray: {drawn[seen]} px at {seen:.2f} s, {drawn[10.0]} px at 10 s")
    assert shown_then and drawn[seen] > OVERLAY_PIXELS
    assert shown_at_10 == [False, False] and drawn[10.0] <= SAME_PIXELS


@pytest.mark.parametrize("overlay", [TARGET, POINTING_RAY, HANDOVER_POINT], ids=lambda o: o.name)
def test_an_unticked_overlay_stays_hidden_through_play_and_seek(demo, overlay: Overlay):
    times = demo.report.cycle.phase_times
    start, stop = _shown_intervals(demo.replay, overlay.mark, demo.report.sim_time)[0]
    time = min((start + stop) / 2, times["carry"] + 2.0)
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        on = replay.frame(time)
        ticked = replay.click_checkbox(overlay.path)  # as the user does
        off = replay.frame(time)
        replay.frame(max(0.0, time - 1.0))
        replay.play(2.0)  # plays through `time` and its keyframes
        played = replay.frame(time)
        after = replay.frame(time + 0.5), replay.shown(overlay.mark), replay.ticked(overlay.path)
        replay.set_visible(overlay.path, True)  # as set_property does from a script
        back = replay.frame(time)
        assert replay.errors == []
    print(f"{overlay.name} at {time:.2f} s: {changed_pixels(on, off)} px on/off, "
          f"{changed_pixels(off, played)} px changed after play")  # fmt: skip
    assert not ticked and changed_pixels(on, off) > OVERLAY_PIXELS
    assert changed_pixels(off, played) <= SAME_PIXELS  # still hidden after playing
    assert after[1:] == (False, False)  # hidden after a seek, its box still unticked
    assert changed_pixels(on, back) <= SAME_PIXELS  # ticked again, drawn again


def test_the_halo_is_on_the_held_object_during_the_carry(demo):
    times = demo.report.cycle.phase_times
    name = "yellow_box"
    box = f"/drake/visualizer/{name}/{name}"  # the recorded world's box, for comparison only
    carry = np.linspace(times["carry"] + 0.3, times["present"] - 0.3, 6)
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        offsets, shown, drawn = [], [], []
        for time in carry:
            drawn.append(_on_and_off(replay, TARGET, float(time)))
            shown.append(replay.shown(TARGET.mark))
            offsets.append(
                np.linalg.norm(replay.world_position(TARGET.mark) - replay.world_position(box))
            )
        assert replay.errors == []
    print(f"halo: {drawn} px during the carry; off the box by {np.round(offsets, 3)} m")
    # The driving robot may pass between the viewer's camera and the box for a moment.
    in_view = sum(pixels > OVERLAY_PIXELS for pixels in drawn)
    assert all(shown) and max(offsets) < 0.03 and in_view > len(carry) / 2


def test_the_scene_map_is_grey_while_it_rests(demo):
    script = """path => {
      const names = path.split("/").filter(part => part);
      const layer = names.reduce((node, name) => node.children[name], viewer.scene_tree);
      const shown = Object.values(layer.children).filter(n => n.object.visible);
      return shown.map(n => { const m = n.children.nodes.children["<object>"].object.material;
                              return [m.color.getHex(), m.vertexColors]; });
    }"""
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        replay.frame(2.0)
        learning = replay.evaluate(script, SCENE_MAP.path)
        replay.frame(10.0)
        resting = replay.evaluate(script, SCENE_MAP.path)
        drawn = _on_and_off(replay, SCENE_MAP, 10.0)
    print(f"scene map at rest: {drawn} px")
    assert learning == [[0xFFFFFF, True]]  # one map, coloured by cluster
    assert resting == [[GREY, False]] and drawn > OVERLAY_PIXELS


def test_the_legend_names_each_overlay_and_the_controls_show_one_entry_each(demo):
    script = """root => {
      const overlays = viewer.scene_tree.children[root];
      const rows = [];
      for (const [name, layer] of Object.entries(overlays.children)) {
        const own = layer.folder.domElement.parentElement.style.display;
        const children = Object.values(layer.children).map(
          child => child.folder.domElement.parentElement.style.display);
        rows.push([name, own, children.length > 0 && children.every(d => d === "none")]);
      }
      return rows;
    }"""
    with open_replay(demo.replay) as replay:
        replay.wait_for_viewer()
        legend = replay.page.locator("#overlay-legend")
        visible = legend.is_visible()
        rows = legend.locator("li").evaluate_all("items => items.map(i => i.dataset.overlay)")
        text = legend.inner_text()
        controls = replay.evaluate(script, OVERLAYS.strip("/"))
        canvas = replay.frame(1.0)
    assert visible and rows == [overlay.name for overlay in DEMO_OVERLAYS]
    assert all(overlay.label in text for overlay in DEMO_OVERLAYS)
    assert sorted(controls) == sorted([o.name, "", True] for o in DEMO_OVERLAYS)
    assert distinct_colours(canvas) > 200  # the legend leaves the scene drawn
