"""Cross-check object detections against the scene map: an object the colour detector found
should also be a bump of nodes in the GNG learnt from depth. A detection with no nodes near
its centre is colour without geometry (a printed patch, a reflection) or a wrong depth."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from hsr_handover.robot.perception.cloud_map import GraphSnapshot

# The scene map spends 200-300 nodes on a table-top scene, about 5-8 cm apart: a real object has
# a node within that spacing of its centre; a detection with a wrong depth, floating in the air
# or sunk into the table, has none.
SUPPORT_RADIUS = 0.08  # m
MIN_SUPPORT = 1  # nodes


@dataclasses.dataclass(frozen=True)
class DetectionSupport:
    """How many map nodes lie within SUPPORT_RADIUS of a detection's centre, the map cluster
    most of them belong to (-1 for none), and whether that is enough to confirm it."""

    label: str
    nodes: int
    cluster: int
    confirmed: bool


def confirmed_candidates(
    detections: Sequence, supports: Sequence[DetectionSupport]
) -> list[tuple[str, np.ndarray]]:
    """(label, centre) of the detections (anything with `label` and `center`) that the map
    confirms: the candidates a request may name."""
    confirmed = {support.label for support in supports if support.confirmed}
    return [(d.label, d.center) for d in detections if d.label in confirmed]


def support_of(
    detections: Sequence[tuple[str, np.ndarray]], graph: GraphSnapshot
) -> tuple[DetectionSupport, ...]:
    """Support of each (label, centre) detection in the map; NaN centres get none."""
    supports = []
    for label, center in detections:
        with np.errstate(invalid="ignore"):
            near = np.linalg.norm(graph.nodes - center, axis=1) <= SUPPORT_RADIUS
        count = int(near.sum())
        cluster = int(np.bincount(graph.clusters[near]).argmax()) if count else -1
        supports.append(DetectionSupport(label, count, cluster, count >= MIN_SUPPORT))
    return tuple(supports)
