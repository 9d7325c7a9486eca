"""A four-legged table whose top size and height come from the scenario."""

from __future__ import annotations

from hsr_handover.world.scene.sdf_shapes import box_geometry, box_inertia, inertial, model, shape

TABLE_TOP_RGBA = (0.55, 0.42, 0.30, 1.0)
TABLE_LEG_RGBA = (0.25, 0.22, 0.20, 1.0)
LEG_WIDTH = 0.05


def table_sdf(depth: float, width: float, height: float, thickness: float) -> str:
    """SDFormat for a table in its own frame: floor at z = 0, top surface at z = `height`,
    top centred on the origin, `depth` along x and `width` along y. Welded by the station."""
    top_z = height - thickness / 2
    leg_length = height - thickness
    body = shape(
        "top", box_geometry((depth, width, thickness)), (0, 0, top_z, 0, 0, 0), TABLE_TOP_RGBA
    )
    inset_x, inset_y = depth / 2 - LEG_WIDTH, width / 2 - LEG_WIDTH
    for index, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        pose = (sx * inset_x, sy * inset_y, leg_length / 2, 0, 0, 0)
        body += shape(
            f"leg{index}", box_geometry((LEG_WIDTH, LEG_WIDTH, leg_length)), pose, TABLE_LEG_RGBA
        )
    mass = 20.0
    link = f'<link name="table">{inertial(mass, box_inertia(mass, (depth, width, height)))}'
    return model("table", link + body + "</link>")
