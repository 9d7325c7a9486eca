"""The table fitted to point clouds: the algorithm (layer 1) and TableEstimator on its own
context."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydrake.perception import PointCloud
from pydrake.systems.analysis import Simulator

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.cloud_map import Workspace
from hsr_handover.robot.perception.table_fit import (
    NO_POINTS,
    NO_TABLE,
    TableFitParams,
    TableMap,
    top_height,
)
from hsr_handover.robot.systems.table_estimator import TableEstimator

WORKSPACE = Workspace((0.0, -1.5, 0.05), (2.5, 1.5, 2.0))
CENTER, SIZE, YAW, HEIGHT = np.array([1.2, 0.1]), np.array([1.2, 0.7]), 0.3, 0.74


def _top(spacing_near: float, spacing_far: float, rng, part=(0.0, 1.0)) -> np.ndarray:
    """A rotated table top sampled on a grid that thins out with distance (as a grazing view
    samples it), over the fraction `part` of its length."""
    xs, x = [], -SIZE[0] / 2 + part[0] * SIZE[0]
    while x <= -SIZE[0] / 2 + part[1] * SIZE[0]:
        xs.append(x)
        x += spacing_near + (spacing_far - spacing_near) * (x + SIZE[0] / 2) / SIZE[0]
    ys = np.arange(-SIZE[1] / 2, SIZE[1] / 2 + 1e-9, spacing_near)
    local = np.array([(x, y) for x in xs for y in ys])
    c, s = math.cos(YAW), math.sin(YAW)
    xy = CENTER + local @ np.array([[c, s], [-s, c]])
    z = HEIGHT + rng.normal(0.0, 0.002, len(xy))  # depth noise
    return np.column_stack([xy, z])


def _clutter(rng) -> np.ndarray:
    """What else a camera sees: the floor, a cup on the table, and the front of a person's
    torso 4 cm beyond the table's far corner, upright, so it crosses the top's height."""
    floor = np.column_stack(
        [rng.uniform(0, 2.5, 3000), rng.uniform(-1.5, 1.5, 3000), np.zeros(3000)]
    )
    angle = rng.uniform(0, 2 * np.pi, 800)
    cup = np.column_stack([1.1 + 0.035 * np.cos(angle), 0.1 + 0.035 * np.sin(angle),
                           HEIGHT + rng.uniform(0, 0.1, 800)])  # fmt: skip
    torso = np.column_stack([np.full(6000, 1.92), rng.uniform(-0.2, 0.2, 6000),
                             rng.uniform(0.5, 1.4, 6000)])  # fmt: skip
    return np.vstack([floor, cup, torso, np.full((50, 3), np.nan)])


def _assert_is_the_table(estimate, atol=0.02) -> None:
    assert estimate is not None
    assert estimate.height == pytest.approx(HEIGHT, abs=0.003)
    np.testing.assert_allclose(estimate.center, CENTER, atol=atol)
    np.testing.assert_allclose(estimate.size, SIZE, atol=atol)
    assert estimate.yaw == pytest.approx(YAW, abs=0.03)


def test_the_top_is_fitted_through_clutter_and_a_sparse_far_side():
    rng = np.random.default_rng(0)
    table_map = TableMap(WORKSPACE)
    assert table_map.add(np.vstack([_top(0.005, 0.03, rng), _clutter(rng)])) == "ok"
    _assert_is_the_table(table_map.estimate())
    corners = table_map.estimate().corners()
    assert np.linalg.norm(corners.mean(axis=0) - CENTER) < 0.02
    assert table_map.report().status == "ok" and table_map.report().frames == 1


def test_views_of_parts_of_the_table_add_up_to_all_of_it():
    rng = np.random.default_rng(1)
    table_map = TableMap(WORKSPACE)
    table_map.add(np.vstack([_top(0.01, 0.01, rng, part=(0.0, 0.55)), _clutter(rng)]))
    near_half = table_map.estimate()
    assert near_half.size[0] < 0.8 * SIZE[0]
    table_map.add(np.vstack([_top(0.01, 0.01, rng, part=(0.45, 1.0)), _clutter(rng)]))
    _assert_is_the_table(table_map.estimate())


def _looking_down_at(local_x: float) -> tuple[PinholeCamera, np.ndarray]:
    """A camera 2 m up over the table's axis at `local_x` along it, looking straight down,
    its square image 0.9 m across at the top's height."""
    c, s = math.cos(YAW), math.sin(YAW)
    along, across = np.array([c, s, 0.0]), np.array([-s, c, 0.0])
    X_WC = np.eye(4)
    X_WC[:3, :3] = np.column_stack([across, along, [0.0, 0.0, -1.0]])
    X_WC[:3, 3] = [*(CENTER + local_x * along[:2]), 2.0]
    fov = 2 * math.atan(0.45 / (2.0 - HEIGHT))
    return PinholeCamera.from_fov_x(300, 300, fov), X_WC


def test_an_edge_at_the_edge_of_the_view_stays_open_until_seen_past():
    rng = np.random.default_rng(2)
    table_map = TableMap(WORKSPACE)
    table_map.add(np.vstack([_top(0.01, 0.01, rng, part=(0.0, 0.55)), _clutter(rng)]),
                  view=_looking_down_at(-0.45))  # fmt: skip
    # The near end and both sides were seen to end; the far part never came into view.
    half = table_map.estimate()
    (open_edge,) = np.flatnonzero(half.open_edges)
    axis, sign = divmod(int(open_edge), 2)
    outward = (1.0 if sign == 0 else -1.0) * np.array(
        [math.cos(half.yaw + axis * math.pi / 2), math.sin(half.yaw + axis * math.pi / 2)]
    )
    assert outward @ [math.cos(YAW), math.sin(YAW)] > 0.99  # toward the part never seen
    table_map.add(np.vstack([_top(0.01, 0.01, rng, part=(0.45, 1.0)), _clutter(rng)]),
                  view=_looking_down_at(0.4))  # fmt: skip
    estimate = table_map.estimate()
    _assert_is_the_table(estimate)
    assert estimate.open_edges == (False, False, False, False)
    # Without views nothing is known past any edge.
    blind = TableMap(WORKSPACE)
    blind.add(np.vstack([_top(0.01, 0.01, rng), _clutter(rng)]))
    assert blind.estimate().open_edges == (True, True, True, True)


def test_frames_looking_away_from_the_top_do_not_move_its_height():
    """The camera looks up at a standing person for longer than it saw the table: each such
    frame's fullest level is the person's (a forearm held out at 1.15 m), yet the top stays
    where the frames that saw it put it."""
    rng = np.random.default_rng(4)
    table_map = TableMap(WORKSPACE)
    for _ in range(2):
        table_map.add(np.vstack([_top(0.01, 0.02, rng), _clutter(rng)]))
    forearm = np.column_stack([rng.uniform(1.6, 1.9, 1500), rng.uniform(0.0, 0.08, 1500),
                               1.15 + rng.normal(0.0, 0.002, 1500)])  # fmt: skip
    for _ in range(5):
        assert table_map.add(np.vstack([forearm, _clutter(rng)[3000:]])) == "ok"
    assert np.median(table_map.heights_) == pytest.approx(1.15, abs=0.01)  # most frames
    _assert_is_the_table(table_map.estimate())


def test_no_table_is_reported_and_never_guessed():
    rng = np.random.default_rng(2)
    table_map = TableMap(WORKSPACE)
    assert table_map.report().status == NO_POINTS and table_map.report().estimate is None
    assert table_map.add(np.zeros((0, 3))) == NO_POINTS
    assert table_map.add(np.full((10, 3), np.nan)) == NO_POINTS
    floor_only = _clutter(rng)[:3000]
    assert table_map.add(floor_only) == NO_POINTS
    patch = np.column_stack(
        [rng.uniform(1.0, 1.1, 500), rng.uniform(0, 0.1, 500), np.full(500, 0.8)]
    )
    assert table_map.add(patch) == "ok"  # a surface at a table's height, but too small
    report = table_map.report()
    assert (report.estimate, report.status, report.frames) == (None, NO_TABLE, 1)


def test_the_height_is_the_fullest_level_not_the_mean():
    rng = np.random.default_rng(3)
    levels = np.concatenate([np.full(5000, 0.74), rng.uniform(0.4, 1.2, 3000)])
    assert top_height(levels, TableFitParams()) == pytest.approx(0.74, abs=1e-6)
    assert top_height(np.array([0.1, 1.5]), TableFitParams()) is None


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"heights": (1.0, 0.5)}, "heights: expected 0 <= low < high"),
        ({"cell_m": 0.0}, "cell_m: expected a positive value"),
        ({"gap_m": -1.0}, "gap_m: expected a positive value"),
    ],
)
def test_bad_parameters_are_named(change, message):
    with pytest.raises(ValueError, match=message):
        TableFitParams(**change)


def test_table_estimator_fits_the_clouds_it_is_given_once_a_period():
    period = 0.2
    estimator = TableEstimator(WORKSPACE, period)
    context = estimator.CreateDefaultContext()
    assert estimator.GetOutputPort("table").Eval(context).status == NO_POINTS
    cloud = PointCloud(0)
    points = np.vstack(
        [_top(0.01, 0.02, np.random.default_rng(4)), _clutter(np.random.default_rng(5))]
    )
    cloud.resize(len(points))
    cloud.mutable_xyzs()[:] = points.T
    estimator.GetInputPort("point_cloud").FixValue(context, cloud)
    simulator = Simulator(estimator, context)
    simulator.AdvanceTo(0.5 * period)  # the first frame is added just after t = 0
    report = estimator.GetOutputPort("table").Eval(context)
    assert report.frames == 1
    _assert_is_the_table(report.estimate)
    simulator.AdvanceTo(2.5 * period)
    assert estimator.GetOutputPort("table").Eval(context).frames == 3
    with pytest.raises(ValueError, match="delay: expected 0 < delay < period"):
        TableEstimator(WORKSPACE, period, delay=period)
