"""PointCloudGng: the robot's topological map of the scene, learnt from the head camera."""

from __future__ import annotations

import dataclasses

from pydrake.common.value import AbstractValue
from pydrake.perception import PointCloud
from pydrake.systems.framework import BasicVector, Context, LeafSystem, State

from hsr_handover.robot.perception.attention import DEFAULT_ATTENTION_WEIGHT
from hsr_handover.robot.perception.cloud_map import (
    SIGNALS_PER_FRAME,
    FrameReport,
    GraphSnapshot,
    Workspace,
    learn_frame,
)
from hsr_handover.robot.systems.watching import declare_watching_input, is_watching
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S
from hsr_handover.topology.growing_neural_gas import GrowingNeuralGas

STATS = ("node_count", "mean_node_error", "quantisation_error", "point_count")


class PointCloudGng(LeafSystem):
    """Adaptive Growing Neural Gas over world-frame point clouds, learning one frame every
    `period` s, `delay` s after each camera capture.

    Inputs: `point_cloud` (PointCloud in the world frame, e.g. from DepthImageToPointCloud),
    `attention` (a tuple of AttentionRegion; optional, unconnected means no attention),
    `image_time` (float, s, the capture time of the frame behind the cloud; optional, recorded
    in the report) and `watching` (optional: while it is 0 the map keeps what it has and reads
    no frame, see `watching`). Outputs: `graph` (GraphSnapshot), `frame_report` (FrameReport:
    what the last frame did, or why it did nothing) and `stats` (vector: node count, mean node
    error, quantisation error of the frame in m, point count).

    Learning `delay` s after the capture learns the frame captured at this tick (see
    `frame_timing`).
    """

    def __init__(
        self,
        gng_params: dict,
        workspace: Workspace,
        period: float,
        n_signals: int = SIGNALS_PER_FRAME,
        attention_weight: float = DEFAULT_ATTENTION_WEIGHT,
        seed: int = 0,
        delay: float = PROCESSING_DELAY_S,
    ):
        super().__init__()
        if not 0 < delay < period:
            raise ValueError(f"delay: expected 0 < delay < period ({period} s), got {delay}")
        self._workspace, self._n_signals = workspace, n_signals
        self._attention_weight = attention_weight
        self._cloud = self.DeclareAbstractInputPort("point_cloud", AbstractValue.Make(PointCloud()))
        self._attention = self.DeclareAbstractInputPort("attention", AbstractValue.Make(()))
        self._image_time = self.DeclareAbstractInputPort(
            "image_time", AbstractValue.Make(float("nan"))
        )
        self._watching = declare_watching_input(self)
        learner = GrowingNeuralGas(**gng_params, random_state=seed)
        self._learner = self.DeclareAbstractState(AbstractValue.Make(learner))
        self._graph = self.DeclareAbstractState(AbstractValue.Make(GraphSnapshot.empty()))
        empty = FrameReport(0, 0, float("nan"), float("nan"), "no frame yet")
        self._report = self.DeclareAbstractState(AbstractValue.Make(empty))
        self.DeclareStateOutputPort("graph", self._graph)
        self.DeclareStateOutputPort("frame_report", self._report)
        self.DeclareVectorOutputPort("stats", len(STATS), self._calc_stats)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, delay, self._learn)

    def _optional(self, port, context: Context, default):
        return port.Eval(context) if port.HasValue(context) else default

    def _learn(self, context: Context, state: State) -> None:
        if not is_watching(self._watching, context):
            return
        learner: GrowingNeuralGas = state.get_mutable_abstract_state(self._learner).get_value()
        cloud: PointCloud = self._cloud.Eval(context)
        regions = self._optional(self._attention, context, ())
        report = learn_frame(
            learner, cloud.xyzs().T, self._workspace, regions, self._n_signals,
            self._attention_weight,
        )  # fmt: skip
        image_time = self._optional(self._image_time, context, float("nan"))
        report = dataclasses.replace(report, image_time=image_time)
        state.get_mutable_abstract_state(self._report).set_value(report)
        graph = GraphSnapshot.of(learner, context.get_time())
        state.get_mutable_abstract_state(self._graph).set_value(graph)

    def _calc_stats(self, context: Context, output: BasicVector) -> None:
        report: FrameReport = context.get_abstract_state(self._report).get_value()
        output.SetFromVector(
            [report.n_nodes, report.mean_node_error, report.quantisation_error, report.n_points]
        )
