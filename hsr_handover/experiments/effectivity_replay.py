"""Figs. 8 and 14 in the replay (issue 9, part 3): the arm's effectivity map at the robot's
handover base, the person's reachable range, the mutual area in red and the handover point,
drawn over the recorded watch. Each is its own entry under EFFECTIVITY in Meshcat's tree, so the
viewer's controls switch it on and off; they are drawn once the figures are known, so the
replay shows them throughout.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from pydrake.geometry import Meshcat, Rgba, Sphere
from pydrake.math import RigidTransform
from pydrake.perception import BaseField, Fields, PointCloud

if TYPE_CHECKING:  # effectivity draws with this module
    from hsr_handover.experiments.effectivity import EffectivityResult

EFFECTIVITY = "effectivity"
LAYER_RGBA = {
    "arm_map": Rgba(0.2, 0.6, 0.2, 1.0),  # green, as in fig. 8
    "person_range": Rgba(0.2, 0.4, 0.9, 0.6),
    "mutual_area": Rgba(0.9, 0.1, 0.1, 1.0),  # red, as in fig. 14
}
POINT_SIZE = 0.02  # m
HANDOVER_POINT_RADIUS = 0.03  # m
HANDOVER_POINT_RGBA = Rgba(1.0, 0.8, 0.0, 1.0)


def effectivity_layers(result: EffectivityResult) -> dict[str, np.ndarray]:
    """The point sets (n, 3, world) to draw, by layer name; a layer with nothing is left out."""
    layers = {}
    if result.person is not None:
        layers["person_range"] = result.person.nodes
    handover = result.handover
    if handover is not None and handover.robot_nodes is not None:
        layers["arm_map"] = handover.robot_nodes[~handover.mutual]
        layers["mutual_area"] = handover.robot_nodes[handover.mutual]
    return {name: points for name, points in layers.items() if len(points)}


def draw_effectivity(meshcat: Meshcat, result: EffectivityResult) -> list[str]:
    """Draw the figures' layers and the handover point; the Meshcat paths drawn."""
    paths = []
    for name, points in effectivity_layers(result).items():
        cloud = PointCloud(len(points), Fields(BaseField.kXYZs))
        cloud.mutable_xyzs()[:] = np.asarray(points, dtype=float).T
        paths.append(f"{EFFECTIVITY}/{name}")
        meshcat.SetObject(paths[-1], cloud, POINT_SIZE, LAYER_RGBA[name])
    handover = result.handover
    if handover is not None and handover.point is not None:
        paths.append(f"{EFFECTIVITY}/handover_point")
        meshcat.SetObject(paths[-1], Sphere(HANDOVER_POINT_RADIUS), HANDOVER_POINT_RGBA)
        meshcat.SetTransform(paths[-1], RigidTransform(handover.point))
    return paths
