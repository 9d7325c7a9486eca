"""HeadCamera: an RGB-D camera that renders at its frame rate and holds each frame.

Drake's RgbdSensorDiscrete holds four images, and its 16-bit depth image costs a second depth
render per frame (about a fifth of the camera's time on a CPU renderer). This system renders
only what a head camera gives: colour, 32-bit depth, optionally the label image, and the
camera pose at the moment of capture.
"""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.geometry import ColorRenderCamera, DepthRenderCamera, FrameId, QueryObject
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem, State
from pydrake.systems.sensors import CameraInfo, ImageDepth32F, ImageLabel16I, ImageRgba8U

from hsr_handover.perception.pinhole import PinholeCamera


def to_camera_info(camera: PinholeCamera) -> CameraInfo:
    """The same intrinsics as Drake's CameraInfo, for renderers and point-cloud systems."""
    return CameraInfo(camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy)


class HeadCamera(LeafSystem):
    """Renders from `parent_frame` at pose `X_PC` every 1 / `rate_hz` s, and at initialisation.

    Input `query_object`. Outputs `color_image` (ImageRgba8U), `depth_image` (ImageDepth32F,
    metres; +inf beyond range, 0 too near, as Drake renders), `label_image` (ImageLabel16I,
    empty when `render_label` is False: labels are ground truth, for scoring only),
    `camera_pose` (RigidTransform X_WC, camera z forward, x right, y down) and `image_time` (s).
    """

    def __init__(
        self,
        color_camera: ColorRenderCamera,
        depth_camera: DepthRenderCamera,
        parent_frame: FrameId,
        X_PC: RigidTransform,
        rate_hz: float,
        render_label: bool = True,
    ):
        super().__init__()
        if not rate_hz > 0:
            raise ValueError(f"rate_hz: expected a positive frame rate, got {rate_hz}")
        self._color_camera, self._depth_camera = color_camera, depth_camera
        self._parent, self._X_PC, self._render_label = parent_frame, X_PC, render_label
        intrinsics = color_camera.core().intrinsics()
        width, height = intrinsics.width(), intrinsics.height()
        self._query_port = self.DeclareAbstractInputPort(
            "query_object", AbstractValue.Make(QueryObject())
        )
        label_size = (width, height) if render_label else (0, 0)
        self._states = {
            "color_image": self.DeclareAbstractState(
                AbstractValue.Make(ImageRgba8U(width, height))
            ),
            "depth_image": self.DeclareAbstractState(
                AbstractValue.Make(ImageDepth32F(width, height))
            ),
            "label_image": self.DeclareAbstractState(
                AbstractValue.Make(ImageLabel16I(*label_size))
            ),
            "camera_pose": self.DeclareAbstractState(AbstractValue.Make(RigidTransform())),
            "image_time": self.DeclareAbstractState(AbstractValue.Make(float("nan"))),
        }
        for name, index in self._states.items():
            self.DeclareStateOutputPort(name, index)
        self.DeclarePeriodicUnrestrictedUpdateEvent(1.0 / rate_hz, 0.0, self._capture)
        self.DeclareInitializationUnrestrictedUpdateEvent(self._capture)

    @property
    def color_camera(self) -> ColorRenderCamera:
        return self._color_camera

    @property
    def depth_camera(self) -> DepthRenderCamera:
        return self._depth_camera

    def _capture(self, context: Context, state: State) -> None:
        query: QueryObject = self._query_port.Eval(context)
        images = {
            "color_image": query.RenderColorImage(self._color_camera, self._parent, self._X_PC),
            "depth_image": query.RenderDepthImage(self._depth_camera, self._parent, self._X_PC),
            "camera_pose": query.GetPoseInWorld(self._parent) @ self._X_PC,
            "image_time": context.get_time(),
        }
        if self._render_label:
            images["label_image"] = query.RenderLabelImage(
                self._color_camera, self._parent, self._X_PC
            )
        for name, value in images.items():
            state.get_mutable_abstract_state(self._states[name]).set_value(value)
