"""Small SDFormat snippets shared by the scene's model builders.

Inertias are those of solid primitives about their own centre, so every body is physically
valid by construction.
"""

from __future__ import annotations

from collections.abc import Sequence


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


def shape(
    name: str,
    geometry: str,
    pose: Sequence[float],
    rgba: Sequence[float] | None,
    friction: float = 0.8,
    proximity: str = "",
) -> str:
    """A visual (when rgba is given) and a collision element with the same geometry and pose;
    `proximity` is Drake's <drake:proximity_properties> body for the collision, if any."""
    visual = ""
    if rgba is not None:
        visual = (
            f'<visual name="{name}_visual"><pose>{fmt(pose)}</pose>{geometry}'
            f"<material><diffuse>{fmt(rgba)}</diffuse></material></visual>"
        )
    properties = f"<drake:proximity_properties>{proximity}</drake:proximity_properties>"
    collision = (
        f'<collision name="{name}_collision"><pose>{fmt(pose)}</pose>{geometry}'
        f"{properties if proximity else ''}<surface><friction><ode><mu>{friction:.6g}</mu>"
        f"<mu2>{friction:.6g}</mu2></ode></friction></surface></collision>"
    )
    return visual + collision


def model(name: str, body: str, static: bool = False) -> str:
    """A whole SDFormat document holding one model."""
    return (
        f'<?xml version="1.0"?><sdf version="1.9"><model name="{name}">'
        f"<static>{'true' if static else 'false'}</static>{body}</model></sdf>"
    )
