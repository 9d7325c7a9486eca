"""TableEstimator: the table's top, fitted to the head camera's point clouds over time."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.perception import PointCloud
from pydrake.systems.framework import Context, LeafSystem, State

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.cloud_map import Workspace
from hsr_handover.robot.perception.table_fit import NO_POINTS, TableFitParams, TableMap, TableReport
from hsr_handover.systems.frame_timing import PROCESSING_DELAY_S


class TableEstimator(LeafSystem):
    """Adds each frame's `point_cloud` (world frame) to a `TableMap`, `delay` s after each
    capture, every `period` s. With a `camera` (the intrinsics of the cloud's image) it also
    reads `camera_pose` (X_WC of the capture) and marks what the camera had in view, so the
    estimate says which edges the top may run on past. Output `table`: a TableReport (the
    estimate so far, or why there is none)."""

    def __init__(
        self,
        workspace: Workspace,
        period: float,
        params: TableFitParams | None = None,
        delay: float = PROCESSING_DELAY_S,
        camera: PinholeCamera | None = None,
    ):
        super().__init__()
        if not 0 < delay < period:
            raise ValueError(f"delay: expected 0 < delay < period ({period} s), got {delay}")
        self._cloud = self.DeclareAbstractInputPort("point_cloud", AbstractValue.Make(PointCloud()))
        self._camera = camera
        self._pose = None
        if camera is not None:
            self._pose = self.DeclareAbstractInputPort(
                "camera_pose", AbstractValue.Make(RigidTransform())
            )
        self._map = self.DeclareAbstractState(AbstractValue.Make(TableMap(workspace, params)))
        self._report = self.DeclareAbstractState(
            AbstractValue.Make(TableReport(None, 0, NO_POINTS))
        )
        self.DeclareStateOutputPort("table", self._report)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, delay, self._add_frame)

    def _add_frame(self, context: Context, state: State) -> None:
        table_map: TableMap = state.get_mutable_abstract_state(self._map).get_value()
        cloud: PointCloud = self._cloud.Eval(context)
        view = None
        if self._camera is not None:
            view = (self._camera, self._pose.Eval(context).GetAsMatrix4())
        table_map.add(cloud.xyzs().T, view)
        state.get_mutable_abstract_state(self._report).set_value(table_map.report())
