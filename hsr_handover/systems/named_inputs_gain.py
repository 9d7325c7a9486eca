"""NamedInputsGain: y = D @ [u_0; u_1; ...] over named vector inputs that must be connected."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.systems.framework import BasicVector, Context, LeafSystem


class NamedInputsGain(LeafSystem):
    """Stacks the named vector inputs, in order, and multiplies them by `D`; output `output_name`.

    Drake's Multiplexer and MatrixGain do the same sum, but an unconnected input would fail as
    "u0 of a Multiplexer"; here it fails naming the port and what to do about it, because these
    inputs stand at a diagram's boundary (the station's commands).
    """

    def __init__(self, inputs: Sequence[tuple[str, int]], D: np.ndarray, output_name: str):
        super().__init__()
        D = np.asarray(D, dtype=float)
        if D.ndim != 2 or D.shape[1] != sum(size for _, size in inputs):
            sizes = [size for _, size in inputs]
            raise ValueError(f"D: expected {sum(sizes)} columns for inputs {sizes}, got {D.shape}")
        self._D = D
        self._inputs = [self.DeclareVectorInputPort(name, size) for name, size in inputs]
        # Recomputed only when an input changes, not every step of the plant that reads it.
        self.DeclareVectorOutputPort(
            output_name, D.shape[0], self._calc,
            prerequisites_of_calc={self.all_input_ports_ticket()},
        )  # fmt: skip

    def _calc(self, context: Context, output: BasicVector) -> None:
        for port in self._inputs:
            if not port.HasValue(context):
                raise RuntimeError(
                    f"input {port.get_name()!r} of {self.get_name()!r} is not connected: "
                    "connect it (e.g. to the robot's output of that name) or fix its value"
                )
        stacked = np.concatenate([port.Eval(context) for port in self._inputs])
        output.SetFromVector(self._D @ stacked)
