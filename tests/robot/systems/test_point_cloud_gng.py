"""The scene map: frame learning (layer 1), and the PointCloudGng, DepthDownsampler and
AttentionFocus systems on their own contexts."""

from __future__ import annotations

import numpy as np
import pytest
from pydrake.common.value import AbstractValue
from pydrake.perception import PointCloud
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.robot.perception.attention import AttentionRegion, FocusChange
from hsr_handover.robot.perception.cloud_map import (
    SCENE_GNG_PARAMS,
    GraphSnapshot,
    Workspace,
    learn_frame,
)
from hsr_handover.robot.systems.attention_focus import AttentionFocus
from hsr_handover.robot.systems.depth_downsampler import DepthDownsampler
from hsr_handover.robot.systems.point_cloud_gng import STATS, PointCloudGng
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S
from hsr_handover.topology.growing_neural_gas import GrowingNeuralGas

WORKSPACE = Workspace((0.0, -1.0, 0.0), (2.0, 1.0, 2.0))


def _plane(n: int, seed: int = 0) -> np.ndarray:
    """Points on a 1 m x 1 m horizontal square at z = 0.7 (a table top)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0.5, 1.5, n), rng.uniform(-0.5, 0.5, n), np.full(n, 0.7)])


def test_learn_frame_crops_to_the_workspace_and_reports_why_it_did_nothing():
    gng = GrowingNeuralGas(**SCENE_GNG_PARAMS, random_state=0)
    outside = _plane(500) + [0, 0, 5.0]
    report = learn_frame(gng, outside, WORKSPACE)
    assert (report.n_points, report.status, gng.n_nodes) == (0, "no points in the workspace", 0)
    assert learn_frame(gng, np.zeros((0, 3)), WORKSPACE).status == "empty point cloud"
    mixed = np.vstack([_plane(4000), outside, np.full((100, 3), np.nan)])
    for _ in range(20):
        report = learn_frame(gng, mixed, WORKSPACE, n_signals=2000)
    assert report.status == "ok" and report.n_points == 4000
    assert np.all(np.abs(gng.nodes[:, 2] - 0.7) < 0.02)  # nothing learnt from the outliers
    assert report.quantisation_error < 0.06


def test_attention_gathers_nodes_in_the_attended_region():
    """Gain 16 on a surface gives about sqrt(16) = 4x the node density (docs/design.md §3.1)."""
    points = _plane(20000)
    region = AttentionRegion("hand", np.array([1.0, 0.0, 0.7]), 0.2)
    points_inside = region.contains(points).mean()

    def density_ratio(regions) -> float:
        gng = GrowingNeuralGas(**SCENE_GNG_PARAMS, random_state=1)
        for _ in range(40):
            learn_frame(gng, points, WORKSPACE, regions, n_signals=5000)
        nodes_inside = region.contains(gng.nodes).mean()
        return (nodes_inside / points_inside) / ((1 - nodes_inside) / (1 - points_inside))

    assert 0.7 < density_ratio([]) < 1.5
    assert density_ratio([region]) > 4.0


def _cloud(points: np.ndarray) -> PointCloud:
    cloud = PointCloud(len(points))
    cloud.mutable_xyzs()[:] = points.T
    return cloud


def test_point_cloud_gng_learns_at_its_rate_and_outputs_the_graph():
    system = PointCloudGng(SCENE_GNG_PARAMS, WORKSPACE, period=0.1, n_signals=3000, seed=2)
    context = system.CreateDefaultContext()
    system.GetInputPort("point_cloud").FixValue(context, _cloud(_plane(5000)))
    assert system.GetOutputPort("frame_report").Eval(context).status == "no frame yet"
    Simulator(system, context).AdvanceTo(1.01)  # ticks at 0.0, 0.1, ..., 1.0
    graph: GraphSnapshot = system.GetOutputPort("graph").Eval(context)
    stats = dict(zip(STATS, system.GetOutputPort("stats").Eval(context), strict=True))
    assert graph.time == pytest.approx(1.0 + PROCESSING_DELAY_S)
    assert stats["node_count"] == len(graph.nodes) > 50
    assert stats["point_count"] == 5000 and 0 < stats["quantisation_error"] < 0.1
    assert graph.edges.max() < len(graph.nodes) and len(graph.clusters) == len(graph.nodes)


def test_point_cloud_gng_rests_while_the_robot_is_not_watching():
    system = PointCloudGng(SCENE_GNG_PARAMS, WORKSPACE, period=0.1, n_signals=3000, seed=2)
    context = system.CreateDefaultContext()
    system.GetInputPort("point_cloud").FixValue(context, _cloud(_plane(5000)))
    system.GetInputPort("watching").FixValue(context, [0.0])
    simulator = Simulator(system, context)
    simulator.AdvanceTo(0.55)
    assert system.GetOutputPort("frame_report").Eval(context).status == "no frame yet"
    assert len(system.GetOutputPort("graph").Eval(context).nodes) == 0
    system.GetInputPort("watching").FixValue(context, [1.0])
    simulator.AdvanceTo(1.01)
    graph: GraphSnapshot = system.GetOutputPort("graph").Eval(context)
    assert graph.time == pytest.approx(1.0 + PROCESSING_DELAY_S) and len(graph.nodes) > 20
    system.GetInputPort("watching").FixValue(context, [0.0])
    simulator.AdvanceTo(1.51)
    assert system.GetOutputPort("graph").Eval(context).time == graph.time  # kept as it was


class _TickingCamera(LeafSystem):
    """Holds a cloud captured every `period` s, like the HeadCamera: frame k is a plane at
    height k (m), so which frame a map learnt shows in its nodes' height."""

    def __init__(self, period: float):
        super().__init__()
        self._frame = self.DeclareDiscreteState(1)
        self.DeclarePeriodicDiscreteUpdateEvent(period, 0.0, self._capture)
        self.DeclareVectorOutputPort("frame", 1, self._frame_number)
        self.DeclareAbstractOutputPort(
            "point_cloud", lambda: AbstractValue.Make(PointCloud()), self._cloud
        )
        self.DeclareAbstractOutputPort(
            "image_time", lambda: AbstractValue.Make(0.0), self._image_time
        )
        self._period = period

    def _capture(self, context, discrete_state):
        discrete_state.set_value([round(context.get_time() / self._period)])

    def _frame_number(self, context, output):
        output.SetFromVector(context.get_discrete_state_vector().value())

    def _cloud(self, context, output):
        plane = _plane(2000)
        plane[:, 2] = 0.5 + context.get_discrete_state_vector()[0]
        output.set_value(_cloud(plane))

    def _image_time(self, context, output):
        output.set_value(context.get_discrete_state_vector()[0] * self._period)


def test_point_cloud_gng_learns_the_frame_captured_at_its_own_tick():
    builder = DiagramBuilder()
    camera = builder.AddSystem(_TickingCamera(0.1))
    params = {**SCENE_GNG_PARAMS, "mu1": 0.5}  # follows the newest frame within one frame
    workspace = Workspace((-1.0, -1.0, 0.0), (1.0, 1.0, 10.0))
    gng = builder.AddSystem(PointCloudGng(params, workspace, period=0.1, n_signals=3000))
    builder.Connect(camera.GetOutputPort("point_cloud"), gng.GetInputPort("point_cloud"))
    builder.Connect(camera.GetOutputPort("image_time"), gng.GetInputPort("image_time"))
    diagram = builder.Build()
    simulator = Simulator(diagram)
    for tick in (1, 2, 3):
        simulator.AdvanceTo(0.1 * tick + 0.05)
        context = gng.GetMyContextFromRoot(simulator.get_context())
        report = gng.GetOutputPort("frame_report").Eval(context)
        graph = gng.GetOutputPort("graph").Eval(context)
        assert report.image_time == pytest.approx(0.1 * tick)
        assert graph.time == pytest.approx(0.1 * tick + PROCESSING_DELAY_S)
        # Frame `tick` is the plane at height tick + 0.5; the previous one is 1 m lower. Nodes
        # that won this frame's signals stand on it, and none can stand higher.
        assert graph.nodes[:, 2].max() == pytest.approx(tick + 0.5, abs=0.05)


def test_point_cloud_gng_needs_its_delay_inside_the_period():
    with pytest.raises(ValueError, match="delay"):
        PointCloudGng(SCENE_GNG_PARAMS, WORKSPACE, period=0.1, delay=0.1)


def test_point_cloud_gng_survives_empty_and_nan_clouds():
    system = PointCloudGng(SCENE_GNG_PARAMS, WORKSPACE, period=0.1)
    context = system.CreateDefaultContext()
    system.GetInputPort("point_cloud").FixValue(context, _cloud(np.full((100, 3), np.nan)))
    Simulator(system, context).AdvanceTo(0.3)
    report = system.GetOutputPort("frame_report").Eval(context)
    assert report.status == "no points in the workspace" and report.n_nodes == 0
    assert len(system.GetOutputPort("graph").Eval(context).nodes) == 0


def test_depth_downsampler_keeps_values_and_fills_missing_frames_with_nan():
    system = DepthDownsampler(200, 200)
    context = system.CreateDefaultContext()
    system.get_input_port().FixValue(context, ImageDepth32F())
    assert np.isnan(system.get_output_port().Eval(context).data).all()
    image = ImageDepth32F(640, 480)
    image.mutable_data[:, :320, 0] = 1.0
    image.mutable_data[:, 320:, 0] = np.inf
    system.get_input_port().FixValue(context, image)
    out = system.get_output_port().Eval(context).data[:, :, 0]
    assert out.shape == (200, 200)
    assert set(np.unique(out[:, :100])) == {1.0} and np.isinf(out[:, 100:]).all()


class _Percepts:
    def __init__(self, points=None, confidence=None, detections=()):
        self.points, self.confidence, self.detections = points, confidence, detections


class _Detection:
    def __init__(self, label, center):
        self.label, self.center = label, np.asarray(center, dtype=float)


def test_attention_focus_follows_its_schedule_in_the_percepts():
    system = AttentionFocus([FocusChange(1.0, "object", "red"), FocusChange(0.0, "none")])
    context = system.CreateDefaultContext()
    port = system.GetOutputPort("attention")
    context.SetTime(2.0)
    assert port.Eval(context) == ()  # nothing connected: nothing perceived
    detections = _Percepts(detections=[_Detection("red", [0.8, -0.2, 0.77])])
    system.GetInputPort("detections").FixValue(context, detections)
    (region,) = port.Eval(context)
    np.testing.assert_allclose(region.center, [0.8, -0.2, 0.77])
    context.SetTime(0.5)
    assert port.Eval(context) == ()
