"""RequiredInputs: fails at initialisation, naming the port, when a required input is left
unconnected.

Inputs at a diagram's boundary (the station's commands) feed Drake's C++ systems, which would
fail at the first step as "u1 of a Multiplexer"; this system reads the same exported inputs and
says which one to connect. It computes nothing afterwards, so the per-step path stays in C++.
"""

from __future__ import annotations

from collections.abc import Sequence

from pydrake.systems.framework import Context, EventStatus, LeafSystem


class RequiredInputs(LeafSystem):
    """Vector inputs `inputs` ((name, size) pairs) that must be connected or fixed; checked by
    an initialisation event, which raises RuntimeError naming the first one that is not."""

    def __init__(self, inputs: Sequence[tuple[str, int]]):
        super().__init__()
        self._inputs = [self.DeclareVectorInputPort(name, size) for name, size in inputs]
        self.DeclareInitializationPublishEvent(self._check)

    def _check(self, context: Context) -> EventStatus:
        for port in self._inputs:
            if not port.HasValue(context):
                raise RuntimeError(
                    f"input {port.get_name()!r} of {self.get_name()!r} is not connected: "
                    "connect it (e.g. to the robot's output of that name) or fix its value"
                )
        return EventStatus.Succeeded()
