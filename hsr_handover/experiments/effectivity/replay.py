"""Figs. 8 and 14 in the replay, drawn over the recorded watch as the paper draws them: the
arm's effectivity map, nodes and edges, round a second HSR standing at the base pose the robot
would hand over from (its arm at the handover point; the recorded robot stays where it
watched from), the person's reachable range, the mutual area in red and the handover point.
Each is an overlay under OVERLAYS (`replay.overlays`), so the viewer's controls switch it on
and off and the legend names its colour; they are drawn once the figures are known, so the
replay shows them throughout.
"""

from __future__ import annotations

import numpy as np
from pydrake.geometry import Meshcat, Rgba, Sphere
from pydrake.math import RigidTransform

from hsr_handover.replay.overlays import (
    ARM_MAP,
    HANDOVER_POINT,
    HANDOVER_POINT_RADIUS,
    MUTUAL_AREA,
    PERSON_RANGE,
    PLANNED_ROBOT,
    Overlay,
    draw_edges,
    draw_points,
)
from hsr_handover.replay.robot_pose import draw_robot
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.planning.handover_pose import HandoverPose

EDGE_ALPHA = 0.3  # a map's edges, fainter than its nodes
LAYERS: dict[str, Overlay] = {o.name: o for o in (PERSON_RANGE, ARM_MAP, MUTUAL_AREA)}


def effectivity_layers(
    person: PersonEffectivity | None, handover: HandoverPose | None
) -> dict[str, np.ndarray]:
    """The point sets (n, 3, world) to draw, by layer name; a layer with nothing is left out."""
    layers = {}
    if person is not None:
        layers[PERSON_RANGE.name] = person.nodes
    if handover is not None and handover.robot_nodes is not None:
        layers[ARM_MAP.name] = handover.robot_nodes[~handover.mutual]
        layers[MUTUAL_AREA.name] = handover.robot_nodes[handover.mutual]
    return {name: points for name, points in layers.items() if len(points)}


def draw_effectivity(
    meshcat: Meshcat,
    person: PersonEffectivity | None,
    handover: HandoverPose | None,
    arm_edges: np.ndarray | None = None,
) -> list[str]:
    """Draw the person's range (its nodes: its edges would hide the arm's), the arm's map with
    its mutual area and, given `arm_edges` (the map's edges, pairs of node indices), its edges,
    the handover point and the robot at its planned handover pose. Returns the overlays' paths
    drawn."""
    drawn = []
    for name, points in effectivity_layers(person, handover).items():
        overlay = LAYERS[name]
        draw_points(meshcat, f"{overlay.path}/nodes", points, overlay.rgba)
        drawn.append(overlay.path)
    if handover is not None and handover.robot_nodes is not None and arm_edges is not None:
        _draw_map_edges(meshcat, ARM_MAP, handover.robot_nodes, arm_edges)
        drawn.append(ARM_MAP.path)
    if handover is not None and handover.point is not None:
        meshcat.SetObject(HANDOVER_POINT.mark, Sphere(HANDOVER_POINT_RADIUS), HANDOVER_POINT.rgba)
        meshcat.SetTransform(HANDOVER_POINT.mark, RigidTransform(handover.point))
        drawn.append(HANDOVER_POINT.path)
    if handover is not None and handover.q is not None:
        draw_robot(meshcat, PLANNED_ROBOT.path, handover.q, PLANNED_ROBOT.rgba)
        drawn.append(PLANNED_ROBOT.path)
    return list(dict.fromkeys(drawn))  # each once, in the order drawn


def _draw_map_edges(
    meshcat: Meshcat, overlay: Overlay, nodes: np.ndarray, edges: np.ndarray
) -> None:
    """A map's edges under its overlay, in its colour but fainter."""
    if len(edges):
        rgba = overlay.rgba
        faint = Rgba(rgba.r(), rgba.g(), rgba.b(), EDGE_ALPHA)
        draw_edges(meshcat, f"{overlay.path}/edges", nodes, edges, faint)
