"""The station: the simulated world and its sensors, joined to the robot only by ports."""

from hsr_handover.world.station.builder import (
    Station,
    build_station,
    check_initial_clearance,
    initial_overlaps,
)
from hsr_handover.world.station.world import person_pose

__all__ = [
    "Station", "build_station", "check_initial_clearance", "initial_overlaps", "person_pose",
]  # fmt: skip
