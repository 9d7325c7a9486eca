"""How close a planned HSR configuration comes to the world as it truly is, for scoring plans:
the station's own plant and geometry, frozen at one moment (the objects and the person where
they were), with the HSR put at the configuration. Ground truth: for benchmarks and
experiments only, never for the robot's decisions.
"""

from __future__ import annotations

import math

import numpy as np
from pydrake.systems.framework import Context

from hsr_handover.station.builder import Station

NEAR = 0.5  # m: distances beyond this are not computed


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
        self._owner: dict = {}
        names = {station.table: "table", station.person: "person"}
        names.update({instance: name for name, instance in station.objects.items()})
        for instance, name in names.items():
            for body in plant.GetBodyIndices(instance):
                for gid in plant.GetCollisionGeometriesForBody(plant.get_body(body)):
                    self._owner[gid] = name
        self._robot = {
            gid
            for body in plant.GetBodyIndices(station.robot)
            for gid in plant.GetCollisionGeometriesForBody(plant.get_body(body))
        }

    def __call__(self, q: np.ndarray, ignore: tuple[str, ...] = ()) -> tuple[float, str]:
        """The least distance (m) from the HSR at `q` to anything but the objects named (by
        their scenario names) in `ignore`, and what it is; (inf, "") when nothing is near."""
        plant = self._station.plant
        positions = plant.GetPositions(self._plant_context).copy()
        positions[self._slots] = q
        plant.SetPositions(self._plant_context, positions)
        query = plant.get_geometry_query_input_port().Eval(self._plant_context)
        best, nearest = math.inf, ""
        for pair in query.ComputeSignedDistancePairwiseClosestPoints(NEAR):
            robot_a, robot_b = pair.id_A in self._robot, pair.id_B in self._robot
            if robot_a == robot_b:
                continue
            other = self._owner.get(pair.id_B if robot_a else pair.id_A, "")
            if other and other not in ignore and pair.distance < best:
                best, nearest = float(pair.distance), other
        return best, nearest
