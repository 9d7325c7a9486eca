"""SkeletonLifter: the robot lifts the pose detector's 2-D keypoints to 3-D with its depth image."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F

from hsr_handover.interface.keypoints import NO_DEPTH_IMAGE, Detection
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.robot.perception.skeleton import Skeleton, lift_detection


class SkeletonLifter(LeafSystem):
    """Inputs `keypoints` (Detection: COCO-18 pixels and confidences, simulated or recorded),
    `depth_image` (ImageDepth32F, m) and `camera_pose` (RigidTransform X_WC). Output `skeleton`
    (Skeleton): each keypoint lifted to the body surface seen at its pixel (paper 3.2), or an
    empty skeleton that says why. `camera` holds the depth image's intrinsics."""

    def __init__(self, camera: PinholeCamera):
        super().__init__()
        self._camera = camera
        self._keypoints = self.DeclareAbstractInputPort(
            "keypoints", AbstractValue.Make(Detection.missing(NO_DEPTH_IMAGE))
        )
        self._depth = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self._pose = self.DeclareAbstractInputPort(
            "camera_pose", AbstractValue.Make(RigidTransform())
        )
        self.DeclareAbstractOutputPort(
            "skeleton",
            lambda: AbstractValue.Make(Skeleton.missing(NO_DEPTH_IMAGE)),
            self._lift,
            prerequisites_of_calc={self.all_input_ports_ticket()},
        )

    @property
    def camera(self) -> PinholeCamera:
        """The depth image's intrinsics."""
        return self._camera

    def _lift(self, context: Context, output: AbstractValue) -> None:
        image: ImageDepth32F = self._depth.Eval(context)
        if image.size() == 0:
            output.set_value(Skeleton.missing(NO_DEPTH_IMAGE))
            return
        detection: Detection = self._keypoints.Eval(context)
        X_WC = self._pose.Eval(context).GetAsMatrix4()
        output.set_value(lift_detection(detection, image.data[:, :, 0], self._camera, X_WC))
