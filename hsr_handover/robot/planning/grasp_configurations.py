"""The configurations of a grasp: for the first grasp candidate and base
placement that inverse kinematics confirms, the grasp itself (pads round the target, which
alone may be touched), the pre-grasp standing off along the approach (everything avoided) and
the lift (the object held, straight up, the base still). "unreachable" when none is found,
never an exception.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

import numpy as np

from hsr_handover.hsr import BASE_JOINTS
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.perception.object_shapes import ObjectShape
from hsr_handover.robot.planning.base_placement import BasePlacement, place_base
from hsr_handover.robot.planning.grasps import Grasp, grasp_candidates
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, solve_palm_ik
from hsr_handover.robot.planning.outcome import Outcome
from hsr_handover.robot.planning.perceived_scene import Capsule
from hsr_handover.robot.planning.planning_scene import PlanningScene

UNREACHABLE = "unreachable"
IN_THE_WAY = 0.05
"""m: a perceived part of the person (margin included) nearer the object's footprint than this
leaves the fingers no room round it, and an unreachable grasp's reason names it."""


@dataclasses.dataclass(frozen=True, kw_only=True)
class GraspConfigurations(Outcome):
    """`ok` with the `grasp`, `q_pregrasp`, `q_grasp` (open round the object) and `q_lifted`
    (closed on it, lifted) (plant positions), or not with the `reason`; the `ik_solves`
    tried."""

    grasp: Grasp | None = None
    q_pregrasp: np.ndarray | None = None
    q_grasp: np.ndarray | None = None
    q_lifted: np.ndarray | None = None
    ik_solves: int = 0


def grasp_configurations(
    scene: PlanningScene, arm_map: ArmEffectivity | None, label: str, q_now: np.ndarray
) -> GraspConfigurations:
    """Grasp the perceived object `label` from the robot's configuration `q_now`; with
    `arm_map` None, IK starts from the arm as it is (the unseeded baseline)."""
    shape = scene.scene.object_named(label)
    if shape is None:
        return GraspConfigurations(ok=False, reason=f"{UNREACHABLE}: {label!r} is not in the scene")
    robot_xy = q_now[[scene.index(BASE_JOINTS[0]), scene.index(BASE_JOINTS[1])]]
    solves = 0
    for grasp, placement in _placements(scene, arm_map, grasp_candidates(shape, robot_xy), q_now):
        goal = PalmGoal(grasp.point, grasp.approach, grasp.closing, grasp.opening)
        at_grasp = solve_palm_ik(scene, goal, placement.q, ignore=(label,))
        solves += 1
        if not at_grasp.ok:
            continue
        before = dataclasses.replace(goal, point=grasp.pregrasp_point)
        at_pregrasp = solve_palm_ik(scene, before, at_grasp.q)
        held = dataclasses.replace(goal, point=grasp.lifted_point, opening=grasp.width)
        lifted = solve_palm_ik(scene, held, at_grasp.q, ignore=(label,), base_fixed=True)
        solves += 2
        if at_pregrasp.ok and lifted.ok:
            return GraspConfigurations(
                ok=True, reason="ok", grasp=grasp, q_pregrasp=at_pregrasp.q, q_grasp=at_grasp.q,
                q_lifted=lifted.q, ik_solves=solves,
            )  # fmt: skip
    reason = f"{UNREACHABLE}: no grasp of {label!r} passed inverse kinematics"
    near = _person_near(shape, scene.scene.person)
    if near is not None:
        reason += f" (the person's {near.part or 'body'} is within {IN_THE_WAY * 100:.0f} cm of it)"
    return GraspConfigurations(ok=False, reason=reason, ik_solves=solves)


def _person_near(shape: ObjectShape, person: tuple[Capsule, ...]) -> Capsule | None:
    """The capsule of the perceived person nearest the object's solid, if it is within
    IN_THE_WAY of the footprint's enclosing circle at any height of the object."""
    heights = np.linspace(shape.bottom, shape.bottom + shape.height, 5)
    axis = np.column_stack([np.tile(shape.center, (len(heights), 1)), heights])
    gaps = [float(capsule.distance(axis).min()) - shape.radius for capsule in person]
    if not gaps or min(gaps) >= IN_THE_WAY:
        return None
    return person[int(np.argmin(gaps))]


def _placements(
    scene: PlanningScene, arm_map: ArmEffectivity | None, grasps: list[Grasp], q_now: np.ndarray
) -> Iterator[tuple[Grasp, BasePlacement]]:
    """Each grasp with each base placement for it, best first; then, as a last resort, the
    grasps from above with the base turned round the object (`place_base`'s `turned`)."""
    for turned in (False, True):
        for grasp in grasps:
            for placement in place_base(scene, arm_map, grasp.point, grasp.approach,
                                        grasp.closing, q_now, turned=turned):  # fmt: skip
                yield grasp, placement
