"""The cycle's planner (`CyclePlanner`) on what the robot perceives: each request plans in a
planning scene built from the latest perceived scene (table, objects, the person's capsules),
seeded by the arm's effectivity map; the person's reach comes from the perceived skeleton."""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence

import numpy as np
from pydrake.math import RigidTransform

from hsr_handover.hsr import GRIPPER_JOINT, PALM_FRAME
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.person_map import HumanArm, PersonEffectivity
from hsr_handover.robot.handover.cycle_types import PlannedMotions
from hsr_handover.robot.handover.plan_view import PlanView, palm_path
from hsr_handover.robot.planning.follow import plan_follow
from hsr_handover.robot.planning.grasps import PAD_OFFSET
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.planner import (
    Held,
    Plan,
    plan_back_off,
    plan_grasp,
    plan_handover,
    plan_posture,
    plan_put_back,
    plan_retreat,
)
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.retarget import Retargeting
from hsr_handover.robot.planning.timing import TimedPath, joint_limits

SIDE_NAMES = {"r": "right", "l": "left"}


class TimedMotion:
    """A toppra-timed path as a cycle `Motion`."""

    def __init__(self, timed: TimedPath):
        self.duration = timed.duration
        self._trajectory = timed.trajectory

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        return self._trajectory.state(time)


class RetargetedMotion:
    """A ruckig state-to-state motion as a cycle `Motion`."""

    def __init__(self, motion: Retargeting):
        self.duration = motion.duration
        self._motion = motion

    def state(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        position, velocity, _ = self._motion.at(time)
        return position, velocity


def _view(plan: Plan, motions, palm, person: PersonEffectivity | None) -> PlanView:
    """The plan as the replay shows it: the palm's path, and a handover's maps and point."""
    path = palm_path((motion for _, motion in motions), palm)
    pose = plan.pose
    if pose is None or pose.robot_nodes is None or person is None:
        return PlanView(path)
    return PlanView(path, pose.robot_nodes, pose.mutual, person.nodes, pose.point)


def pads_centre(palm_pose: RigidTransform) -> np.ndarray:
    """The centre between the finger pads (m, world) of a hand whose frame is at `palm_pose`."""
    return palm_pose.multiply([0.0, 0.0, PAD_OFFSET])


class PerceivedPlanner:
    """Plans for the cycle from the percepts last given to `perceive`; it keeps no other state
    between plans, so contexts may share it."""

    def __init__(self, arm_map: ArmEffectivity):
        self._arm_map = arm_map
        self.robot = PlanningScene(PerceivedScene(None))  # the HSR alone: its kinematics
        self.limits = joint_limits(self.robot.plant)
        self._percepts: tuple[PerceivedScene, tuple[HumanArm, ...]] = (PerceivedScene(None), ())
        self._scene: PlanningScene | None = None

    def perceive(self, scene: PerceivedScene, arms: tuple[HumanArm, ...]) -> None:
        """The perceived scene to plan in and the person's arms the robot may hand to, the one
        to try first first (none if unseen; `person_map.receiving_arms`)."""
        if scene is not self._percepts[0]:
            self._scene = None
        self._percepts = (scene, tuple(arms))

    def _planning(self) -> PlanningScene:
        if self._scene is None:
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

    def _motions(
        self, plan: Plan, started: float, person: PersonEffectivity | None = None
    ) -> PlannedMotions:
        if not plan.ok:
            return PlannedMotions(
                ok=False, reason=plan.reason, seconds=time.perf_counter() - started
            )
        motions = tuple((motion.name, TimedMotion(motion.timed)) for motion in plan.motions)
        seconds = time.perf_counter() - started  # the replay's view is not planning
        view = _view(plan, motions, self.palm, person)
        return PlannedMotions(
            ok=True, reason="ok", motions=motions, seconds=seconds, held=plan.held, view=view
        )

    def grasp(self, label: str, q: np.ndarray) -> PlannedMotions:
        started = time.perf_counter()
        plan = plan_grasp(self._planning(), self._arm_map, label, q, self.limits)
        return self._motions(plan, started)

    def carry(self, q: np.ndarray, held: Held | None) -> PlannedMotions:
        """To the handover point of the first of the person's arms that has one."""
        started = time.perf_counter()
        arms = self._percepts[1]
        if not arms:
            return PlannedMotions(ok=False, reason="no person perceived to hand over to")
        reasons = []
        for arm in arms:
            person = PersonEffectivity(arm)
            plan = plan_handover(self._planning(), self._arm_map, person, q, self.limits, held)
            if plan.ok:
                return dataclasses.replace(self._motions(plan, started, person), receiving=arm.side)
            reasons.append(f"{SIDE_NAMES[arm.side]} arm: {plan.reason}")
        return self._motions(dataclasses.replace(plan, reason="; ".join(reasons)), started)

    def follow(
        self, q: np.ndarray, v: np.ndarray, aim: np.ndarray, held: Held | None
    ) -> PlannedMotions:
        """A state-to-state move (ruckig) holding the object out at `aim` (m, world), or, where
        the object there would be inside the person's perceived capsules, at the nearest point
        round it where it fits (`planning.follow`)."""
        started = time.perf_counter()
        scene = self._planning()
        palm = self.palm_pose(q).rotation().matrix()  # the hand keeps the turn it has
        goal = PalmGoal(np.asarray(aim, dtype=float), palm[:, 2], palm[:, 1],
                        2 * q[scene.index(GRIPPER_JOINT)])  # fmt: skip
        found = plan_follow(scene, goal, q, v, held, self.limits)
        if found.motion is None:
            return PlannedMotions(
                ok=False, reason=found.reason, seconds=time.perf_counter() - started
            )
        motions = (("follow", RetargetedMotion(found.motion)),)
        view = PlanView(palm_path((m for _, m in motions), self.palm))
        seconds = time.perf_counter() - started
        return PlannedMotions(ok=True, reason="ok", motions=motions, seconds=seconds, view=view)

    def put_back(
        self, q: np.ndarray, held: Held, lifted: np.ndarray, came: Sequence[np.ndarray] = ()
    ) -> PlannedMotions:
        """Holding `held`, back to `lifted` (where the grasp lifted it to) along the way it
        `came`, then down to where it was grasped (`plan_put_back`)."""
        started = time.perf_counter()
        plan = plan_put_back(self._planning(), q, held, lifted, self.limits, came)
        return self._motions(plan, started)

    def back_off(self, q: np.ndarray, let_go: Held) -> PlannedMotions:
        """The palm straight back from the object just let go of (`plan_back_off`)."""
        started = time.perf_counter()
        return self._motions(plan_back_off(self._planning(), q, self.limits, let_go.label), started)

    def posture(self, q: np.ndarray, goal: np.ndarray) -> PlannedMotions:
        """From `q` to the posture `goal` (plant positions), holding nothing."""
        started = time.perf_counter()
        return self._motions(plan_posture(self._planning(), q, goal, self.limits), started)

    def retreat(
        self, q: np.ndarray, held: Held | None, let_go: Held | None = None
    ) -> PlannedMotions:
        started = time.perf_counter()
        released = let_go.label if let_go is not None else ""
        plan = plan_retreat(self._planning(), q, self.limits, held, released)
        return self._motions(plan, started)
