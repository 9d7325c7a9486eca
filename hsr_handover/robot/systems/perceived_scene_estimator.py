"""PerceivedSceneEstimator: what the planner must avoid, from the robot's percepts."""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.depth_view import DepthView
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.object_shapes import measure_objects
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.perception.table_fit import TableReport
from hsr_handover.robot.planning.perceived_scene import (
    PERSON_MARGIN,
    PerceivedScene,
    extend_past_view,
    person_capsules,
)


class PerceivedSceneEstimator(LeafSystem):
    """The planning scene's contents (docs/design.md §3.4), computed when asked for.

    Inputs: `table` (TableReport), `detections` (DetectionResult: every detection is an
    obstacle, confirmed by the map or not), `depth_image` (ImageDepth32F of the detections'
    capture), `camera_pose` (RigidTransform X_WC) and `skeleton` (the lifted Skeleton).
    Output `scene`: a PerceivedScene: the fitted table (its edges at the edge of the camera's
    view pushed out: the top may run on unseen), each detected object as a cylinder or box
    standing on it (none before the table is seen), the person's capsules widened by
    `person_margin` (m) and stamped with the time (a hip, knee or ankle lifted over the table
    left out), and the depth image they were seen in (a
    `DepthView`, by which the supervisor forgets what the camera now sees through). `camera`
    holds the intrinsics of the depth image's size.
    """

    def __init__(self, camera: PinholeCamera, person_margin: float = PERSON_MARGIN):
        super().__init__()
        if not person_margin >= 0:
            raise ValueError(f"person_margin: expected a distance >= 0 m, got {person_margin}")
        self._camera, self._margin = camera, person_margin
        self._table = self.DeclareAbstractInputPort(
            "table", AbstractValue.Make(TableReport(None, 0, "not read"))
        )
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self._depth = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self.DeclareAbstractOutputPort(
            "scene", lambda: AbstractValue.Make(PerceivedScene(None)), self._calc_scene
        )

    def _calc_scene(self, context: Context, output: AbstractValue) -> None:
        table = self._table.Eval(context).estimate
        pose = self._pose.Eval(context)
        skeleton = self._skeleton.Eval(context)
        person = person_capsules(
            skeleton.points, skeleton.confidence, pose.translation(), self._margin,
            seen_at=context.get_time(), table=table,
        )  # fmt: skip
        depth = np.array(self._depth.Eval(context).data[:, :, 0])  # kept: the image is reused
        X_WC = pose.GetAsMatrix4()
        objects = ()
        if table is not None:
            detections = self._detections.Eval(context).detections
            objects = tuple(measure_objects(detections, depth, self._camera, X_WC, table.height))
            table = extend_past_view(table, X_WC[:2, 3])
        view = DepthView(self._camera, X_WC, depth)
        output.set_value(PerceivedScene(table, objects, person, view))
