"""CycleVisualizer: what the robot thinks, drawn in Meshcat over the run: the
pointing and gaze rays, the recognised target, the palm's planned path, the arm's effectivity
nodes at the handover base, the person's reachable range, the mutual area in red (paper
fig. 14) and the handover point. Each is its own entry under CYCLE in Meshcat's tree, so the
viewer's controls switch it on and off.

A recording replays transforms and properties, not new objects: the rays, the target's mark
and the handover point are drawn once and moved and shown by recorded keyframes; a new path or
new maps are new snapshots whose visibility the recording animates
(`meshcat_recording.Snapshots`).
"""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import Cylinder, Meshcat, Rgba, Sphere
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.perception import BaseField, Fields, PointCloud
from pydrake.systems.framework import Context, LeafSystem

from hsr_handover.replay.meshcat_recording import Snapshots, set_pose, set_visible
from hsr_handover.robot.handover.plan_view import PlanView
from hsr_handover.robot.intent import IntentState
from hsr_handover.robot.perception.object_detection import DetectionResult

CYCLE = "/cycle"
RAY_LENGTH = 1.2  # m drawn of each ray from its origin
RAY_RADIUS = 0.006  # m
RAYS = {"pointing_ray": Rgba(0.95, 0.5, 0.0, 1.0), "gaze_ray": Rgba(0.1, 0.7, 0.9, 1.0)}
TARGET_RADIUS = 0.08  # m: a halo round the object recognised
TARGET_RGBA = Rgba(1.0, 0.9, 0.0, 0.35)
HANDOVER_POINT_RADIUS = 0.03  # m
HANDOVER_POINT_RGBA = Rgba(1.0, 0.8, 0.0, 1.0)
PATH_RGBA = Rgba(0.6, 0.1, 0.8, 1.0)
PATH_WIDTH = 3.0
POINT_SIZE = 0.02  # m
MAP_RGBA = {  # the effectivity figures' colours, here and in `hsr-handover effectivity`
    "arm_map": Rgba(0.2, 0.6, 0.2, 1.0),  # green, as in fig. 8
    "person_range": Rgba(0.2, 0.4, 0.9, 0.6),
    "mutual_area": Rgba(0.9, 0.1, 0.1, 1.0),  # red, as in fig. 14
}
KEEP = 60  # snapshots kept of each changing layer (a cycle plans a handful of times)


class CycleVisualizer(LeafSystem):
    """Inputs `intent` (IntentState), `intent_rays` ((pointing, gaze) Rays or None),
    `detections` (DetectionResult) and `plan_view` (PlanView); draws them every
    `publish_period` s under `/cycle/...`. Like Drake's MeshcatVisualizer, what has been drawn
    is kept in the system: publish events cannot change the Context."""

    def __init__(self, meshcat: Meshcat, publish_period: float = 0.1):
        super().__init__()
        if not publish_period > 0:
            raise ValueError(f"publish_period: expected a positive period, got {publish_period}")
        self._meshcat = meshcat
        self._intent = self.DeclareAbstractInputPort("intent", AbstractValue.Make(IntentState()))
        self._rays = self.DeclareAbstractInputPort("intent_rays", AbstractValue.Make((None, None)))
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        self._plan = self.DeclareAbstractInputPort("plan_view", AbstractValue.Make(PlanView()))
        self._path = Snapshots(meshcat, f"{CYCLE}/palm_path", KEEP)
        self._maps = {name: Snapshots(meshcat, f"{CYCLE}/{name}", KEEP) for name in MAP_RGBA}
        self._drawn: PlanView | None = None
        self._visible: dict[str, bool] = {}
        self.DeclareInitializationPublishEvent(self._draw_fixed)
        self.DeclarePeriodicPublishEvent(publish_period, 0.0, self._publish)
        self.DeclareForcedPublishEvent(self._publish)

    def _draw_fixed(self, context: Context) -> None:
        """The objects that only move: drawn once, hidden until there is something to show."""
        self._meshcat.Delete(CYCLE)
        self._drawn, self._visible = None, {}
        for snapshots in (self._path, *self._maps.values()):
            snapshots.clear()
        for name, rgba in RAYS.items():
            self._meshcat.SetObject(f"{CYCLE}/{name}", Cylinder(RAY_RADIUS, RAY_LENGTH), rgba)
        self._meshcat.SetObject(f"{CYCLE}/target", Sphere(TARGET_RADIUS), TARGET_RGBA)
        self._meshcat.SetObject(
            f"{CYCLE}/handover_point", Sphere(HANDOVER_POINT_RADIUS), HANDOVER_POINT_RGBA
        )
        for name in (*RAYS, "target", "handover_point"):
            self._show(name, False, context.get_time())

    def _publish(self, context: Context) -> None:
        time = context.get_time()
        for name, ray in zip(RAYS, self._rays.Eval(context), strict=True):
            self._place(name, None if ray is None else _ray_pose(ray), time)
        self._place("target", self._target_centre(context), time)
        view: PlanView = self._plan.Eval(context)
        self._draw_plan(view, time)
        self._drawn = view

    def _target_centre(self, context: Context) -> RigidTransform | None:
        target = self._intent.Eval(context).target
        for detection in self._detections.Eval(context).detections:
            if detection.label == target and np.all(np.isfinite(detection.center)):
                return RigidTransform(np.asarray(detection.center, dtype=float))
        return None

    def _draw_plan(self, view: PlanView, time: float) -> None:
        """New snapshots of what changed (values compared: ports hand out copies)."""
        drawn = self._drawn
        if drawn is None or not np.array_equal(view.palm_path, drawn.palm_path):
            if len(view.palm_path) > 1:
                self._path.show(lambda path: self._line(path, view.palm_path), time)
            else:
                self._path.hide(time)
        if drawn is not None and _same_point(view.handover_point, drawn.handover_point):
            return
        layers = {"arm_map": view.arm_nodes[~view.mutual], "person_range": view.person_nodes,
                  "mutual_area": view.arm_nodes[view.mutual]}  # fmt: skip
        for name, points in layers.items():
            if len(points):
                self._maps[name].show(lambda path, p=points, n=name: self._cloud(path, p, n), time)
            else:
                self._maps[name].hide(time)
        point = view.handover_point
        self._place("handover_point", None if point is None else RigidTransform(point), time)

    def _place(self, name: str, pose: RigidTransform | None, time: float) -> None:
        if pose is not None:
            set_pose(self._meshcat, f"{CYCLE}/{name}", pose, time)
        self._show(name, pose is not None, time)

    def _show(self, name: str, visible: bool, time: float) -> None:
        if self._visible.get(name) != visible:  # a keyframe only where it changes
            set_visible(self._meshcat, f"{CYCLE}/{name}", visible, time)
            self._visible[name] = visible

    def _line(self, path: str, points: np.ndarray) -> None:
        self._meshcat.SetLine(path, np.asfortranarray(points.T), PATH_WIDTH, PATH_RGBA)

    def _cloud(self, path: str, points: np.ndarray, name: str) -> None:
        draw_points(self._meshcat, path, points, MAP_RGBA[name])


def draw_points(meshcat: Meshcat, path: str, points: np.ndarray, rgba: Rgba) -> None:
    """Points (n, 3, world) drawn at `path`, POINT_SIZE each, in one colour."""
    cloud = PointCloud(len(points), Fields(BaseField.kXYZs))
    cloud.mutable_xyzs()[:] = np.asarray(points, dtype=float).T
    meshcat.SetObject(path, cloud, POINT_SIZE, rgba)


def _same_point(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    return (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))


def _ray_pose(ray) -> RigidTransform:
    """The pose of a RAY_LENGTH cylinder (along its z, centred) lying along `ray`."""
    direction = np.asarray(ray.direction, dtype=float)
    rotation = RotationMatrix.MakeFromOneVector(direction, 2)
    return RigidTransform(rotation, np.asarray(ray.origin) + RAY_LENGTH / 2 * direction)
