"""DepthDownsampler: a depth image resized to the resolution perception learns from."""

from __future__ import annotations

import cv2
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, LeafSystem
from pydrake.systems.sensors import ImageDepth32F


class DepthDownsampler(LeafSystem):
    """Input `depth_image` (ImageDepth32F, any size); output `depth_image` at width x height.

    Nearest-neighbour, not averaging: a mean across an object's edge would invent points in
    the air between the object and what lies behind it. The paper learns from 200 x 200.
    """

    def __init__(self, width: int, height: int):
        super().__init__()
        if width <= 0 or height <= 0:
            raise ValueError(f"width, height: expected positive sizes, got {width} x {height}")
        self._size = (width, height)
        self._input = self.DeclareAbstractInputPort(
            "depth_image", AbstractValue.Make(ImageDepth32F())
        )
        self.DeclareAbstractOutputPort(
            "depth_image", lambda: AbstractValue.Make(ImageDepth32F(width, height)), self._calc
        )

    def _calc(self, context: Context, output: AbstractValue) -> None:
        image: ImageDepth32F = self._input.Eval(context)
        result = output.get_mutable_value()
        if image.width() == 0 or image.height() == 0:
            result.mutable_data[:] = float("nan")  # no frame yet: nothing seen, not "near"
            return
        resized = cv2.resize(image.data[:, :, 0], self._size, interpolation=cv2.INTER_NEAREST)
        result.mutable_data[:, :, 0] = resized
