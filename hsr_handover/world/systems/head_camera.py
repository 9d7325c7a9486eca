"""HeadCamera: an RGB-D camera that captures at its frame rate and holds each frame.

Drake's RgbdSensorDiscrete holds four images, and its 16-bit depth image costs a second depth
render per frame (about a fifth of the camera's time on a CPU renderer); it also renders every
frame whether or not anything reads it. This system gives only what a head camera gives
(colour, 32-bit depth, optionally the label image, and the camera pose at the moment of
capture), and renders a frame's images only when they are first read: a capture latches the
scene's poses, and the images are rendered from those.
"""

from __future__ import annotations

from collections.abc import Mapping

from pydrake.common.value import AbstractValue
from pydrake.geometry import (
    ColorRenderCamera,
    DepthRenderCamera,
    FrameId,
    FramePoseVector,
    QueryObject,
)
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem, State
from pydrake.systems.sensors import CameraInfo, ImageDepth32F, ImageLabel16I, ImageRgba8U


class HeadCamera(LeafSystem):
    """Captures every 1 / `rate_hz` s, and at initialisation, from `parent_frame` at pose
    `X_PC`; renders a capture's images when they are first evaluated.

    It renders a SceneGraph of its own (the camera scene, `station.camera_scene`) holding
    copies of the world's frames (`frames`: world FrameId -> camera scene FrameId;
    `parent_frame` among them). At a capture it latches the world's poses (input
    `frame_poses`, the plant's geometry poses) into output `scene_poses`, which poses the
    camera scene; its `query_object` input is the camera scene's. So a frame's images are the
    scene at its capture instant whenever they are read, and a frame nobody reads is never
    rendered.

    Outputs: `color_image` (ImageRgba8U), `depth_image` (ImageDepth32F, metres; +inf beyond
    range, 0 too near, as Drake renders), `label_image` (ImageLabel16I, empty when
    `render_label` is False: labels are ground truth, for scoring only), `camera_pose`
    (RigidTransform X_WC, camera z forward, x right, y down), `image_time` (s) and
    `scene_poses`.
    """

    def __init__(
        self,
        color_camera: ColorRenderCamera,
        depth_camera: DepthRenderCamera,
        parent_frame: FrameId,
        X_PC: RigidTransform,
        rate_hz: float,
        frames: Mapping[FrameId, FrameId],
        render_label: bool = True,
    ):
        super().__init__()
        if not rate_hz > 0:
            raise ValueError(f"rate_hz: expected a positive frame rate, got {rate_hz}")
        if parent_frame not in frames:
            raise ValueError("frames: expected a copy of the camera's parent frame")
        self._color_camera, self._depth_camera = color_camera, depth_camera
        self._parent, self._X_PC, self._render_label = parent_frame, X_PC, render_label
        self._frames = dict(frames)
        self._scene_parent = self._frames[parent_frame]  # the mount's copy, rendered from
        self._query_port = self.DeclareAbstractInputPort(
            "query_object", AbstractValue.Make(QueryObject())
        )
        self._frame_poses = self.DeclareAbstractInputPort(
            "frame_poses", AbstractValue.Make(FramePoseVector())
        )
        self._states = {
            "scene_poses": self.DeclareAbstractState(AbstractValue.Make(FramePoseVector())),
            "camera_pose": self.DeclareAbstractState(AbstractValue.Make(RigidTransform())),
            "image_time": self.DeclareAbstractState(AbstractValue.Make(float("nan"))),
        }
        for name, index in self._states.items():
            self.DeclareStateOutputPort(name, index)
        self._declare_images(color_camera.core().intrinsics())
        self.DeclarePeriodicUnrestrictedUpdateEvent(1.0 / rate_hz, 0.0, self._capture)
        self.DeclareInitializationUnrestrictedUpdateEvent(self._capture)

    @property
    def color_camera(self) -> ColorRenderCamera:
        return self._color_camera

    @property
    def depth_camera(self) -> DepthRenderCamera:
        return self._depth_camera

    def _declare_images(self, intrinsics: CameraInfo) -> None:
        # An image depends on the capture alone: rendered once per capture, when first read.
        capture = {self.abstract_state_ticket(self._states["scene_poses"])}
        width, height = intrinsics.width(), intrinsics.height()
        label_size = (width, height) if self._render_label else (0, 0)
        images = {
            "color_image": (ImageRgba8U(width, height), self._render_color),
            "depth_image": (ImageDepth32F(width, height), self._render_depth),
            "label_image": (ImageLabel16I(*label_size), self._render_label_image),
        }
        for name, (model, calc) in images.items():
            self.DeclareAbstractOutputPort(
                name,
                lambda model=model: AbstractValue.Make(model),
                calc,
                prerequisites_of_calc=capture,
            )

    def _capture(self, context: Context, state: State) -> None:
        poses: FramePoseVector = self._frame_poses.Eval(context)
        latched = FramePoseVector()
        for world_frame, scene_frame in self._frames.items():
            latched.set_value(scene_frame, poses.value(world_frame))
        captured = {
            "scene_poses": latched,
            "camera_pose": poses.value(self._parent) @ self._X_PC,
            "image_time": context.get_time(),
        }
        for name, value in captured.items():
            state.get_mutable_abstract_state(self._states[name]).set_value(value)

    def _query(self, context: Context) -> tuple[QueryObject, FrameId]:
        return self._query_port.Eval(context), self._scene_parent

    def _render_color(self, context: Context, output: AbstractValue) -> None:
        query, parent = self._query(context)
        output.set_value(query.RenderColorImage(self._color_camera, parent, self._X_PC))

    def _render_depth(self, context: Context, output: AbstractValue) -> None:
        query, parent = self._query(context)
        output.set_value(query.RenderDepthImage(self._depth_camera, parent, self._X_PC))

    def _render_label_image(self, context: Context, output: AbstractValue) -> None:
        if not self._render_label:
            return  # the allocated empty image
        query, parent = self._query(context)
        output.set_value(query.RenderLabelImage(self._color_camera, parent, self._X_PC))
