"""Graspable objects: cups (solid cylinders) and boxes in distinct, saturated colours that the
robot's colour segmentation can tell apart from the person, the table and the robot."""

from __future__ import annotations

from collections.abc import Sequence

from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.world.scene.sdf_shapes import (
    box_geometry,
    box_inertia,
    cylinder_geometry,
    cylinder_inertia,
    inertial,
    model,
    shape,
)

OBJECT_SHAPES = {"cup": 2, "box": 3}  # shape -> number of size values
OBJECT_FRICTION = 1.0
OBJECT_CONTACT = (
    "<drake:compliant_hydroelastic/><drake:mesh_resolution_hint>0.01</drake:mesh_resolution_hint>"
    "<drake:hydroelastic_modulus>1e7</drake:hydroelastic_modulus>"
    "<drake:hunt_crossley_dissipation>5</drake:hunt_crossley_dissipation>"
)
"""Compliant like the gripper's pads, so that a grasp is a contact patch (a compliant pad on a
rigid object falls back to point contact); the mesh hint makes a cup's cylinder mesh."""


def object_height(shape_name: str, size: Sequence[float]) -> float:
    """Height of an upright object: a cup's size is [diameter, height], a box's [x, y, z]."""
    return size[1] if shape_name == "cup" else size[2]


def object_sdf(name: str, shape_name: str, size: Sequence[float], color: str, mass: float) -> str:
    """SDFormat for a free object with its frame at the centre of its bounding box."""
    rgba = (*OBJECT_COLORS[color], 1.0)
    if shape_name == "cup":
        radius, length = size[0] / 2, size[1]
        geometry, moments = (
            cylinder_geometry(radius, length),
            cylinder_inertia(mass, radius, length),
        )
    else:
        geometry, moments = box_geometry(size), box_inertia(mass, size)
    link = (
        f'<link name="{name}">{inertial(mass, moments)}'
        f"{shape(name, geometry, (0,) * 6, rgba, OBJECT_FRICTION, OBJECT_CONTACT)}</link>"
    )
    return model(name, link)
