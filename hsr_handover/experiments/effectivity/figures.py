"""The paper's figs. 8 and 14 on a scenario: the arm's effectivity map with
eq. 11's palm error, and, from what the robot perceives after a few seconds of watching, the
scene's map, the person's range, the mutual area at the robot's handover base and the handover
point.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from hsr_handover.experiments.effectivity.replay import draw_effectivity
from hsr_handover.experiments.watch import WATCH_S, watch
from hsr_handover.kinematics.hsr_arm import palm_position, sample_arm_joints
from hsr_handover.replay.meshcat_replay import write_replay
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity, load_or_build
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.planning.handover_pose import HandoverPose, plan_handover_pose
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.scenario import Scenario

RANDOM_TARGETS = 2000  # reachable palm positions for eq. 11's error away from the nodes


@dataclasses.dataclass(frozen=True)
class EffectivityResult:
    """What the figures show (world frame, m, unless said otherwise)."""

    arm_nodes: np.ndarray  # the arm map's nodes, base frame
    arm_edges: np.ndarray
    palm_error_nodes_m: float  # eq. 11 medians
    palm_error_random_m: float
    scene_nodes: np.ndarray  # the perceived scene's GNG
    person: PersonEffectivity | None
    handover: HandoverPose | None
    status: str
    wall_s: float

    def summary(self) -> dict:
        """The JSON's figures."""
        handover, person = self.handover, self.person
        mutual = None if handover is None or handover.mutual is None else int(handover.mutual.sum())
        return {
            "status": self.status,
            "arm_nodes": len(self.arm_nodes),
            "palm_error_median_m": {"nodes": self.palm_error_nodes_m,
                                    "random_targets": self.palm_error_random_m},
            "scene_nodes": len(self.scene_nodes),
            "person_arm": None if person is None else {
                "side": person.arm.side, "upper_m": person.arm.upper,
                "forearm_m": person.arm.forearm, "hand_m": person.arm.hand,
                "nodes": len(person.nodes)},
            "mutual_nodes": mutual,
            "ideal_point": None if handover is None else handover.ideal.tolist(),
            "handover_point": None if handover is None or handover.point is None
            else handover.point.tolist(),
            "handover_base": None if handover is None or handover.q is None
            else handover.q[:3].tolist(),
            "wall_s": self.wall_s,
        }  # fmt: skip


def palm_errors(arm_map: ArmEffectivity, seed: int = 1) -> tuple[float, float]:
    """Eq. 11's median palm error (m) at the map's nodes and at random reachable targets."""
    targets = palm_position(sample_arm_joints(RANDOM_TARGETS, np.random.default_rng(seed)))
    return (float(np.median(arm_map.palm_errors(arm_map.nodes))),
            float(np.median(arm_map.palm_errors(targets))))  # fmt: skip


def run_effectivity(
    scenario: Scenario, watch_s: float = WATCH_S, replay: Path | None = None
) -> EffectivityResult:
    """Watch the scenario for `watch_s` (perception on, whatever the file says; the head looks
    round the table first), then compute the figures from the percepts. With `replay`, the
    watch is written there as an HTML replay with the figures drawn over it."""
    start = time.perf_counter()
    arm_map, _ = load_or_build()
    at_nodes, at_random = palm_errors(arm_map)
    watched = watch(scenario, watch_s, look_around=True, replay=replay is not None)
    scene = watched.scene
    graph = watched.percept("gng_graph")
    arm = watched.person_arm()
    person, handover, status = None, None, "no person seen (both shoulders needed)"
    if arm is not None:
        person = PersonEffectivity(arm)
        planning = PlanningScene(scene)
        planning.set_positions(watched.measured_positions())
        handover = plan_handover_pose(planning, arm_map, person, planning.positions())
        status = handover.reason
    result = EffectivityResult(arm_map.nodes, arm_map.cells.edges, at_nodes, at_random,
                               np.asarray(graph.nodes), person, handover, status,
                               time.perf_counter() - start)  # fmt: skip
    if watched.meshcat is not None:
        draw_effectivity(watched.meshcat, result.person, result.handover, result.arm_edges)
        write_replay(watched.meshcat, replay)
    return result
