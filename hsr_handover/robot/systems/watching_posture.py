"""WatchingPosture: a robot that only watches holds its posture, turns its head and raises its
torso where the objects would hide a pointing arm (`handover.watch_view`), as the handover
cycle's robot does while it watches."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import BasicVector, Context, LeafSystem, State

from hsr_handover.hsr import COMMANDED_JOINTS, HEAD_JOINTS
from hsr_handover.robot.handover.scene_memory import remember
from hsr_handover.robot.handover.watch_view import WatchView
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.planner import plan_posture
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.timing import joint_limits

WATCH_TICK_S = 0.1  # s between the decisions, at the gaze's and the camera's instants
BODY_ROWS = [row for row, joint in enumerate(COMMANDED_JOINTS) if joint not in HEAD_JOINTS]
HEAD_ROWS = [COMMANDED_JOINTS.index(joint) for joint in HEAD_JOINTS]


@dataclasses.dataclass
class _Watch:
    """What it carries between ticks: the scene with what is out of view remembered, and
    where it watches from."""

    scene: PerceivedScene | None = None
    view: WatchView = dataclasses.field(default_factory=WatchView)


def _plan(scene: PerceivedScene, q: np.ndarray, posture: np.ndarray) -> Motion | None:
    """A motion from `q` to `posture` clear of the perceived `scene`, None if there is none."""
    planning = PlanningScene(scene)
    plan = plan_posture(planning, q, posture, joint_limits(planning.plant))
    return plan.motions[0] if plan.ok else None


class WatchingPosture(LeafSystem):
    """Inputs: `head_command` ([pan, tilt, pan rate, tilt rate], the GazeController's),
    `skeleton` (the lifted Skeleton), `scene` (PerceivedScene) and `hsr_state_measured`
    ([q; v] of COMMANDED_JOINTS). Output `hsr_desired_state`: `posture` ([q; v] of
    COMMANDED_JOINTS), its body's rows following the raise once one is planned (clear of what
    it perceives: `plan_posture`), its head's taken from `head_command`. Output `watch_lift`:
    the arm lift (m) it watches from, 0 until it has raised."""

    def __init__(self, posture: np.ndarray):
        super().__init__()
        self._posture = np.array(posture, dtype=float)
        n = len(COMMANDED_JOINTS)
        if self._posture.shape != (2 * n,):
            raise ValueError(f"posture: expected {2 * n} values, got {self._posture.shape}")
        self._robot = PlanningScene(PerceivedScene(None))  # the HSR alone: its kinematics
        self._plant_rows = np.array([self._robot.index(joint) for joint in COMMANDED_JOINTS])
        self._head = self.DeclareVectorInputPort("head_command", 4)
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self._scene = self.DeclareAbstractInputPort(
            "scene", AbstractValue.Make(PerceivedScene(None))
        )
        self._state = self.DeclareVectorInputPort("hsr_state_measured", 2 * n)
        self._watch = self.DeclareAbstractState(AbstractValue.Make(_Watch()))
        self.DeclareVectorOutputPort("hsr_desired_state", 2 * n, self._calc_state)
        self.DeclareVectorOutputPort(
            "watch_lift", 1, self._calc_lift,
            prerequisites_of_calc={self.abstract_state_ticket(self._watch)},
        )  # fmt: skip
        self.DeclarePeriodicUnrestrictedUpdateEvent(WATCH_TICK_S, 0.0, self._tick)

    def _tick(self, context: Context, state: State) -> None:
        watch: _Watch = state.get_mutable_abstract_state(self._watch).get_value()
        time = context.get_time()
        if not watch.view.settled(time):
            return  # the scene is read only while it may weigh the view
        watch.scene = remember(watch.scene, self._scene.Eval(context))
        skeleton = self._skeleton.Eval(context)
        watch.view.weigh(time, self._robot, self._measured(context), skeleton.points,
                         skeleton.confidence, watch.scene.objects,
                         functools.partial(_plan, watch.scene))  # fmt: skip

    def _measured(self, context: Context) -> np.ndarray:
        """The measured positions (plant order; the gripper as the robot model's default)."""
        measured = self._state.Eval(context)[: len(COMMANDED_JOINTS)]
        self._robot.set_positions(dict(zip(COMMANDED_JOINTS, measured, strict=True)))
        return self._robot.positions()

    def _calc_state(self, context: Context, output: BasicVector) -> None:
        command = self._posture.copy()
        raised = context.get_abstract_state(self._watch).get_value().view.raised
        n = len(COMMANDED_JOINTS)
        if raised is not None:
            q, v = raised.state(context.get_time())
            command[BODY_ROWS] = q[self._plant_rows[BODY_ROWS]]
            command[[n + row for row in BODY_ROWS]] = v[self._plant_rows[BODY_ROWS]]
        command[[*HEAD_ROWS, *(n + row for row in HEAD_ROWS)]] = self._head.Eval(context)
        output.SetFromVector(command)

    def _calc_lift(self, context: Context, output: BasicVector) -> None:
        raised = context.get_abstract_state(self._watch).get_value().view.raised
        output.SetFromVector([0.0 if raised is None else raised.lift])
