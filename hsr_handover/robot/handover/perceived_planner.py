"""The cycle's planner (`CyclePlanner`) on what the robot perceives: each request plans in a
planning scene built from the latest perceived scene (table, objects, the person's capsules),
seeded by the arm's effectivity map; the person's reach comes from the perceived skeleton."""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Sequence

import numpy as np
from pydrake.math import RigidTransform

from hsr_handover.hsr import PALM_FRAME
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.mutual_area import within_reach
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.planning.follow import plan_follow
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.inverse_kinematics import palm_goal
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.plan import Plan
from hsr_handover.robot.planning.plan_view import PlanView, palm_path
from hsr_handover.robot.planning.planner import (
    HANDOVER,
    Held,
    person_clearance,
    plan_back_off,
    plan_grasp,
    plan_handover,
    plan_posture,
    plan_put_back,
    plan_retreat,
)
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.stopwatch import Stopwatch
from hsr_handover.robot.planning.timing import joint_limits

SIDE_NAMES = {"r": "right", "l": "left"}
SCENE = "scene"  # the stage that builds the planning scene from the percepts


def pads_centre(palm_pose: RigidTransform) -> np.ndarray:
    """The centre between the finger pads (m, world) of a hand whose frame is at `palm_pose`."""
    return palm_pose.multiply([0.0, 0.0, PAD_OFFSET])


class PerceivedPlanner:
    """Plans for the cycle in the perceived scene, towards the person's arms, it was made with
    (`perceiving` gives one for newer percepts). It changes only by building its planning
    scene on first use, a function of its percepts, so copies of the cycle in several Drake
    contexts may share it."""

    def __init__(
        self,
        arm_map: ArmEffectivity,
        scene: PerceivedScene | None = None,
        arms: tuple[HumanArm, ...] = (),
    ):
        """`scene` to plan in (None: the HSR alone) and the person's `arms` the robot may hand
        to, the one to try first first (none if unseen; `person_map.receiving_arms`)."""
        self._arm_map = arm_map
        # The HSR alone, for its kinematics: a scratch plant context, set and read in one call.
        self.robot = PlanningScene(PerceivedScene(None))
        self.limits = joint_limits(self.robot.plant)
        self._percepts = (PerceivedScene(None) if scene is None else scene, tuple(arms))
        self._scene: PlanningScene | None = None

    def perceiving(self, scene: PerceivedScene, arms: tuple[HumanArm, ...]) -> PerceivedPlanner:
        """A planner for the scene and arms perceived now: this one if they are the ones it
        has, else a copy (sharing the robot's kinematics, and the planning scene when the
        scene is the same)."""
        arms = tuple(arms)
        if scene is self._percepts[0] and arms == self._percepts[1]:
            return self
        planner = copy.copy(self)
        planner._percepts = (scene, arms)
        if scene is not self._percepts[0]:
            planner._scene = None
        return planner

    def _planning(self, watch: Stopwatch) -> PlanningScene:
        """The planning scene of its percepts, built (and timed) once for them."""
        if self._scene is None:
            with watch.stage(SCENE):
                self._scene = PlanningScene(self._percepts[0])
        return self._scene

    def palm(self, q: np.ndarray) -> np.ndarray:
        """The pads' centre (m, world) with the HSR at `q`."""
        return pads_centre(self.palm_pose(q))

    def palm_pose(self, q: np.ndarray) -> RigidTransform:
        """The hand's frame (PALM_FRAME, where the wrist's sensor reads) with the HSR at `q`."""
        plant, context = self.robot.plant, self.robot.plant_context
        plant.SetPositions(context, q)
        return plant.GetFrameByName(PALM_FRAME).CalcPoseInWorld(context)

    def _viewed(
        self, plan: Plan, watch: Stopwatch, person: PersonEffectivity | None = None
    ) -> Plan:
        """`plan` with the planning scene's build time added to its stages, and, when it is
        ok, what the replay shows of it (which is not planning, so not timed)."""
        seconds = plan.seconds | {SCENE: watch.seconds.get(SCENE, 0.0)}
        if not plan.ok:
            return dataclasses.replace(plan, seconds=seconds)
        path = palm_path(plan.motions, self.palm)
        pose = plan.pose
        if pose is None or pose.robot_nodes is None or person is None:
            view = PlanView(path)
        else:
            view = PlanView(path, pose.robot_nodes, pose.mutual, person.nodes, pose.point)
        return dataclasses.replace(plan, seconds=seconds, view=view)

    def grasp(self, label: str, q: np.ndarray) -> Plan:
        watch = Stopwatch()
        plan = plan_grasp(self._planning(watch), self._arm_map, label, q, self.limits)
        return self._viewed(plan, watch)

    def carry(self, q: np.ndarray, held: Held | None) -> Plan:
        """To the handover point of the first of the person's arms that has one."""
        watch = Stopwatch()
        arms = self._percepts[1]
        if not arms:
            return Plan(ok=False, reason="no person perceived to hand over to", target=HANDOVER)
        reasons, seconds = [], {}
        for arm in arms:
            person = PersonEffectivity(arm)
            plan = plan_handover(self._planning(watch), self._arm_map, person, q, self.limits, held)
            seconds = {stage: seconds.get(stage, 0.0) + s for stage, s in plan.seconds.items()}
            plan = dataclasses.replace(plan, seconds=seconds)
            if plan.ok:
                return self._viewed(dataclasses.replace(plan, receiving=arm.side), watch, person)
            reasons.append(f"{SIDE_NAMES[arm.side]} arm: {plan.reason}")
        return self._viewed(dataclasses.replace(plan, reason="; ".join(reasons)), watch)

    def person_clearance(
        self, path: Sequence[np.ndarray], held: Held | None, within: float
    ) -> float:
        """The least clearance (m) of the configurations `path`, holding `held`, to the
        person as perceived now (`planner.person_clearance`); inf beyond `within`."""
        return person_clearance(self._planning(Stopwatch()), path, held, within)

    def person_reaches(self, point: np.ndarray) -> bool:
        """Whether one of the person's perceived arms may reach for `point` (m, world): within
        its `leaning_reach`. A person reaches at full stretch, and leans, for what is held out
        to them (a handover point is chosen nearer, `mutual_area.MOST_REACH`)."""
        arms = self._percepts[1]
        return any(bool(within_reach(arm, point, arm.leaning_reach)[0]) for arm in arms)

    def follow(self, q: np.ndarray, v: np.ndarray, aim: np.ndarray, held: Held | None) -> Plan:
        """A state-to-state move (ruckig) holding the object out at `aim` (m, world), or, where
        the object there would be inside the person's perceived capsules, at the nearest point
        round it where it fits (`planning.follow`)."""
        watch = Stopwatch()
        scene = self._planning(watch)
        # The hand keeps the turn it has.
        goal = dataclasses.replace(palm_goal(scene, q), point=np.asarray(aim, dtype=float))
        plan = plan_follow(scene, goal, q, v, held, self.limits, self._arm_map)
        return self._viewed(plan, watch)

    def put_back(
        self, q: np.ndarray, held: Held, lifted: np.ndarray, came: Sequence[np.ndarray] = ()
    ) -> Plan:
        """Holding `held`, back to `lifted` (where the grasp lifted it to) along the way it
        `came`, then down to where it was grasped (`plan_put_back`)."""
        watch = Stopwatch()
        plan = plan_put_back(self._planning(watch), q, held, lifted, self.limits, came)
        return self._viewed(plan, watch)

    def back_off(self, q: np.ndarray, let_go: Held) -> Plan:
        """The palm straight back from the object just let go of (`plan_back_off`)."""
        watch = Stopwatch()
        plan = plan_back_off(self._planning(watch), q, self.limits, let_go.label)
        return self._viewed(plan, watch)

    def posture(self, q: np.ndarray, goal: np.ndarray) -> Plan:
        """From `q` to the posture `goal` (plant positions), holding nothing."""
        watch = Stopwatch()
        return self._viewed(plan_posture(self._planning(watch), q, goal, self.limits), watch)

    def retreat(self, q: np.ndarray, held: Held | None, let_go: Held | None = None) -> Plan:
        watch = Stopwatch()
        released = let_go.label if let_go is not None else ""
        plan = plan_retreat(self._planning(watch), q, self.limits, held, released)
        return self._viewed(plan, watch)
