"""TableEstimator: the table's top, fitted to the head camera's point clouds over time."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.perception import PointCloud
from pydrake.systems.framework import Context, LeafSystem, State

from hsr_handover.perception.cloud_map import Workspace
from hsr_handover.perception.table_fit import NO_POINTS, TableFitParams, TableMap, TableReport
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S


class TableEstimator(LeafSystem):
    """Adds each frame's `point_cloud` (world frame) to a `TableMap`, `delay` s after each
    capture, every `period` s. Output `table`: a TableReport (the estimate so far, or why
    there is none)."""

    def __init__(
        self,
        workspace: Workspace,
        period: float,
        params: TableFitParams | None = None,
        delay: float = PROCESSING_DELAY_S,
    ):
        super().__init__()
        if not 0 < delay < period:
            raise ValueError(f"delay: expected 0 < delay < period ({period} s), got {delay}")
        self._cloud = self.DeclareAbstractInputPort("point_cloud", AbstractValue.Make(PointCloud()))
        self._map = self.DeclareAbstractState(AbstractValue.Make(TableMap(workspace, params)))
        self._report = self.DeclareAbstractState(
            AbstractValue.Make(TableReport(None, 0, NO_POINTS))
        )
        self.DeclareStateOutputPort("table", self._report)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, delay, self._add_frame)

    def _add_frame(self, context: Context, state: State) -> None:
        table_map: TableMap = state.get_mutable_abstract_state(self._map).get_value()
        cloud: PointCloud = self._cloud.Eval(context)
        table_map.add(cloud.xyzs().T)
        state.get_mutable_abstract_state(self._report).set_value(table_map.report())
