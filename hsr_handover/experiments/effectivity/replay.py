"""Figs. 8 and 14 in the replay: the arm's effectivity map at the robot's
handover base, the person's reachable range, the mutual area in red and the handover point,
drawn over the recorded watch. Each is its own entry under EFFECTIVITY in Meshcat's tree, so the
viewer's controls switch it on and off; they are drawn once the figures are known, so the
replay shows them throughout.
"""

from __future__ import annotations

import numpy as np
from pydrake.geometry import Meshcat, Sphere
from pydrake.math import RigidTransform

from hsr_handover.replay.cycle_visualizer import (
    HANDOVER_POINT_RADIUS,
    HANDOVER_POINT_RGBA,
    MAP_RGBA,
    draw_points,
)
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.planning.handover_pose import HandoverPose

EFFECTIVITY = "effectivity"


def effectivity_layers(
    person: PersonEffectivity | None, handover: HandoverPose | None
) -> dict[str, np.ndarray]:
    """The point sets (n, 3, world) to draw, by layer name; a layer with nothing is left out."""
    layers = {}
    if person is not None:
        layers["person_range"] = person.nodes
    if handover is not None and handover.robot_nodes is not None:
        layers["arm_map"] = handover.robot_nodes[~handover.mutual]
        layers["mutual_area"] = handover.robot_nodes[handover.mutual]
    return {name: points for name, points in layers.items() if len(points)}


def draw_effectivity(
    meshcat: Meshcat, person: PersonEffectivity | None, handover: HandoverPose | None
) -> list[str]:
    """Draw the person's range, the arm's map with its mutual area and the handover point; the
    Meshcat paths drawn."""
    paths = []
    for name, points in effectivity_layers(person, handover).items():
        paths.append(f"{EFFECTIVITY}/{name}")
        draw_points(meshcat, paths[-1], points, MAP_RGBA[name])
    if handover is not None and handover.point is not None:
        paths.append(f"{EFFECTIVITY}/handover_point")
        meshcat.SetObject(paths[-1], Sphere(HANDOVER_POINT_RADIUS), HANDOVER_POINT_RGBA)
        meshcat.SetTransform(paths[-1], RigidTransform(handover.point))
    return paths
