"""Topological maps of the perceiving-acting cycle (paper 3.1): numpy + numba, no Drake.

- ``GrowingNeuralGas``: adaptive GNG over point clouds (perception), docs/design.md §3.1.
- ``GrowingCellStructures``: simplicial maps with joint-vector payloads (action),
  docs/design.md §3.2.
- ``metrics``: quantisation, squared and topographic error, node density.
"""

from hsr_handover.topology.growing_cell_structures import CellPath, GrowingCellStructures
from hsr_handover.topology.growing_neural_gas import GrowingNeuralGas

__all__ = ["CellPath", "GrowingCellStructures", "GrowingNeuralGas"]
