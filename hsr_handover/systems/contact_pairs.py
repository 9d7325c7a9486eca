"""The pairs of geometries in contact in a plant's ContactResults, point and hydroelastic alike."""

from __future__ import annotations

from pydrake.geometry import GeometryId
from pydrake.multibody.plant import ContactResults


def contact_pairs(results: ContactResults) -> list[tuple[GeometryId, GeometryId]]:
    """(id, id) of every pair of geometries in contact."""
    pairs = []
    for i in range(results.num_point_pair_contacts()):
        pair = results.point_pair_contact_info(i).point_pair()
        pairs.append((pair.id_A, pair.id_B))
    for i in range(results.num_hydroelastic_contacts()):
        surface = results.hydroelastic_contact_info(i).contact_surface()
        pairs.append((surface.id_M(), surface.id_N()))
    return pairs
