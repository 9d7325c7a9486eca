"""ObjectDetector: colour-segmentation object detection on the head camera's RGB-D frames."""

from __future__ import annotations

from collections.abc import Mapping

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.object_detection import (
    DetectionResult,
    DetectorSettings,
    check_palette,
    detect_objects,
)


class ObjectDetector(LeafSystem):
    """Detects the palette-coloured objects in each frame (paper section 4.3).

    Inputs `color_image` (ImageRgba8U), `depth_image` (ImageDepth32F, metres) and `camera_pose`
    (RigidTransform X_WC), as the HeadCamera gives them. Output `detections`: a DetectionResult,
    recomputed only when an input changes (the camera holds its frames between captures).
    `camera` holds the intrinsics of the images' size.
    """

    def __init__(
        self,
        camera: PinholeCamera,
        palette: Mapping[str, tuple[float, float, float]] = OBJECT_COLORS,
        settings: DetectorSettings = DetectorSettings(),  # noqa: B008 (frozen, so shared safely)
    ):
        super().__init__()
        check_palette(palette, settings)
        self._camera, self._palette, self._settings = camera, dict(palette), settings
        self._color_port = self.DeclareAbstractInputPort(
            "color_image", AbstractValue.Make(ImageRgba8U())
        )
        self._depth_port = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose_port = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self.DeclareAbstractOutputPort(
            "detections",
            lambda: AbstractValue.Make(DetectionResult((), "no frame yet")),
            self._calc_detections,
            prerequisites_of_calc={self.all_input_ports_ticket()},
        )

    def _calc_detections(self, context: Context, output: AbstractValue) -> None:
        color: ImageRgba8U = self._color_port.Eval(context)
        depth: ImageDepth32F = self._depth_port.Eval(context)
        X_WC: RigidTransform = self._pose_port.Eval(context)
        result = detect_objects(
            color.data[:, :, :3],
            depth.data[:, :, 0],
            self._camera,
            X_WC.GetAsMatrix4(),
            self._palette,
            self._settings,
        )
        output.set_value(result)
