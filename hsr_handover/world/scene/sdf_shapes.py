"""Small SDFormat snippets shared by the scene's model builders.

Inertias are those of solid primitives about their own centre, so every body is physically
valid by construction.

Spheres and capsules are drawn coarse (`coarse_sphere`, `coarse_capsule`): Drake's VTK renderer
tessellates a primitive sphere or capsule finely, about 0.8 and 1.6 ms each per colour image
whatever the image size, and the person's thirteen of them were most of the head camera's
render time. A 16-segment sphere is within 2 % of its radius of the true surface; collision
keeps the exact primitive.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.math import RollPitchYaw

SPHERE_MESH = "package://hsr_handover/shapes/sphere.obj"  # a unit sphere, 288 triangles


def fmt(values: Sequence[float]) -> str:
    """Space-separated numbers as SDFormat wants them."""
    return " ".join(f"{v:.6g}" for v in values)


def box_inertia(mass: float, size: Sequence[float]) -> tuple[float, float, float]:
    x, y, z = size
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)


def cylinder_inertia(mass: float, radius: float, length: float) -> tuple[float, float, float]:
    side = mass * (3 * radius * radius + length * length) / 12
    return (side, side, mass * radius * radius / 2)


def inertial(mass: float, moments: Sequence[float], pose: Sequence[float] = (0,) * 6) -> str:
    ixx, iyy, izz = moments
    return f"""<inertial><pose>{fmt(pose)}</pose><mass>{mass:.6g}</mass><inertia>
<ixx>{ixx:.6g}</ixx><iyy>{iyy:.6g}</iyy><izz>{izz:.6g}</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz>
</inertia></inertial>"""


def box_geometry(size: Sequence[float]) -> str:
    return f"<geometry><box><size>{fmt(size)}</size></box></geometry>"


def cylinder_geometry(radius: float, length: float) -> str:
    return (
        f"<geometry><cylinder><radius>{radius:.6g}</radius>"
        f"<length>{length:.6g}</length></cylinder></geometry>"
    )


def sphere_geometry(radius: float) -> str:
    return f"<geometry><sphere><radius>{radius:.6g}</radius></sphere></geometry>"


def capsule_geometry(radius: float, length: float) -> str:
    return (
        f"<geometry><capsule><radius>{radius:.6g}</radius>"
        f"<length>{length:.6g}</length></capsule></geometry>"
    )


def coarse_sphere(radius: float) -> str:
    """A sphere's geometry to draw: the coarse unit mesh, scaled."""
    scale = fmt((radius,) * 3)
    return f"<geometry><mesh><uri>{SPHERE_MESH}</uri><scale>{scale}</scale></mesh></geometry>"


def coarse_capsule(
    name: str, radius: float, length: float, pose: Sequence[float], rgba: Sequence[float]
) -> str:
    """A capsule (its axis the pose's z) drawn as a cylinder capped by two coarse spheres."""
    axis = RollPitchYaw(*pose[3:]).ToRotationMatrix().col(2) * (length / 2)
    drawn = visual(name, cylinder_geometry(radius, length), pose, rgba)
    for end, sign in (("top", 1.0), ("bottom", -1.0)):
        centre = np.asarray(pose[:3]) + sign * axis
        drawn += visual(f"{name}_{end}", coarse_sphere(radius), (*centre, 0, 0, 0), rgba)
    return drawn


def visual(name: str, geometry: str, pose: Sequence[float], rgba: Sequence[float]) -> str:
    """A <visual> element named `name`_visual."""
    return (
        f'<visual name="{name}_visual"><pose>{fmt(pose)}</pose>{geometry}'
        f"<material><diffuse>{fmt(rgba)}</diffuse></material></visual>"
    )


def shape(
    name: str,
    geometry: str,
    pose: Sequence[float],
    rgba: Sequence[float] | None,
    friction: float = 0.8,
    proximity: str = "",
    drawn: str | None = None,
) -> str:
    """A visual (when rgba is given) and a collision element with the same geometry and pose;
    `proximity` is Drake's <drake:proximity_properties> body for the collision, if any; `drawn`
    replaces the visual (a coarse stand-in for the same surface)."""
    visual_element = ""
    if rgba is not None:
        visual_element = drawn if drawn is not None else visual(name, geometry, pose, rgba)
    properties = f"<drake:proximity_properties>{proximity}</drake:proximity_properties>"
    collision = (
        f'<collision name="{name}_collision"><pose>{fmt(pose)}</pose>{geometry}'
        f"{properties if proximity else ''}<surface><friction><ode><mu>{friction:.6g}</mu>"
        f"<mu2>{friction:.6g}</mu2></ode></friction></surface></collision>"
    )
    return visual_element + collision


def capsule_shape(
    name: str, radius: float, length: float, pose: Sequence[float], rgba: Sequence[float]
) -> str:
    """A capsule that collides as itself and is drawn coarse."""
    drawn = coarse_capsule(name, radius, length, pose, rgba)
    return shape(name, capsule_geometry(radius, length), pose, rgba, drawn=drawn)


def sphere_shape(name: str, radius: float, pose: Sequence[float], rgba: Sequence[float]) -> str:
    """A sphere that collides as itself and is drawn coarse."""
    drawn = visual(name, coarse_sphere(radius), pose, rgba)
    return shape(name, sphere_geometry(radius), pose, rgba, drawn=drawn)


def model(name: str, body: str, static: bool = False) -> str:
    """A whole SDFormat document holding one model."""
    return (
        f'<?xml version="1.0"?><sdf version="1.9"><model name="{name}">'
        f"<static>{'true' if static else 'false'}</static>{body}</model></sdf>"
    )
