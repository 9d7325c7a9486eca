"""How close a planned HSR configuration comes to the world as it truly is, for scoring plans:
the station's own plant and geometry, frozen at one moment (the objects and the person where
they were), with the HSR put at the configuration. Ground truth: for benchmarks and
experiments only, never for the robot's decisions.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np
from pydrake.systems.framework import Context

from hsr_handover.hsr import PALM_FRAME
from hsr_handover.world.station.builder import Station

NEAR = 0.5  # m: distances beyond this are not computed
ROBOT, TABLE, PERSON, HAND = "robot", "table", "person", "hand"


def geometry_owners(station: Station) -> dict:
    """Every collision geometry's owner in the station: ROBOT, TABLE, PERSON, HAND (either of
    the person's hands) or the object's scenario name."""
    plant = station.plant
    instances = {station.robot: ROBOT, station.table: TABLE, station.person: PERSON}
    instances.update({instance: name for name, instance in station.objects.items()})
    owner = {}
    for instance, name in instances.items():
        for index in plant.GetBodyIndices(instance):
            body = plant.get_body(index)
            who = HAND if name == PERSON and body.name().endswith("hand") else name
            for geometry in plant.GetCollisionGeometriesForBody(body):
                owner[geometry] = who
    return owner


class TrueClearance:
    """Signed distances between the HSR and the table, the objects and the person.

    `station_context` is the station's context at the moment to freeze (it is copied);
    `joint_names` name the entries of the configurations to be scored (the planning plant's
    position order)."""

    def __init__(self, station: Station, station_context: Context, joint_names: list[str]):
        self._station = station
        self._context = station.diagram.CreateDefaultContext()
        self._context.SetTimeStateAndParametersFrom(station_context)
        plant = station.plant
        self._plant_context = station.diagram.GetMutableSubsystemContext(plant, self._context)
        self._slots = np.array([plant.GetJointByName(name, station.robot).position_start()
                                for name in joint_names])  # fmt: skip
        owners = geometry_owners(station)
        self._robot = {gid for gid, owner in owners.items() if owner == ROBOT}
        self._owner = {gid: PERSON if owner == HAND else owner
                       for gid, owner in owners.items() if owner != ROBOT}  # fmt: skip
        self._hand = plant.GetFrameByName(PALM_FRAME, station.robot).body()
        self._held = None  # (the object's body, its pose in the hand) while holding

    @contextlib.contextmanager
    def holding(self, name: str, q_grasp: np.ndarray) -> Iterator[None]:
        """Within the block, the true object `name` rides in the hand as it would if the hand
        closed on it where it truly stands with the HSR at `q_grasp`: it counts as part of the
        robot, and its distances to everything else are scored too."""
        plant = self._station.plant
        (index,) = plant.GetBodyIndices(self._station.objects[name])
        body = plant.get_body(index)
        self._put(q_grasp)
        X_HO = self._hand.EvalPoseInWorld(self._plant_context).inverse() @ body.EvalPoseInWorld(
            self._plant_context
        )
        X_WO = body.EvalPoseInWorld(self._plant_context)
        carried = set(plant.GetCollisionGeometriesForBody(body))
        self._robot |= carried
        self._held = (body, X_HO)
        try:
            yield
        finally:
            self._held = None
            self._robot -= carried
            plant.SetFreeBodyPose(self._plant_context, body, X_WO)

    def _put(self, q: np.ndarray) -> None:
        """The HSR at `q`, and the object held (if any) in its hand."""
        plant = self._station.plant
        positions = plant.GetPositions(self._plant_context).copy()
        positions[self._slots] = q
        plant.SetPositions(self._plant_context, positions)
        if self._held is not None:
            body, X_HO = self._held
            X_WH = self._hand.EvalPoseInWorld(self._plant_context)
            plant.SetFreeBodyPose(self._plant_context, body, X_WH @ X_HO)

    def __call__(self, q: np.ndarray, ignore: tuple[str, ...] = ()) -> tuple[float, str]:
        """The least distance (m) from the HSR at `q` to anything but the objects named (by
        their scenario names) in `ignore`, and what it is; (inf, "") when nothing is near.
        While `holding`, the object held is part of the HSR and not ignored."""
        self._put(q)
        query = self._station.plant.get_geometry_query_input_port().Eval(self._plant_context)
        best, nearest = math.inf, ""
        for pair in query.ComputeSignedDistancePairwiseClosestPoints(NEAR):
            robot_a, robot_b = pair.id_A in self._robot, pair.id_B in self._robot
            if robot_a == robot_b:
                continue
            other = self._owner.get(pair.id_B if robot_a else pair.id_A, "")
            if other and other not in ignore and pair.distance < best:
                best, nearest = float(pair.distance), other
        return best, nearest
