"""HandoverSupervisor: the robot's perceiving-acting cycle as a Drake system.

Inputs, all percepts: `hsr_state_measured` and `gripper_opening_measured` (the joint sensors),
`hsr_wrist_wrench_measured` (the wrist's force-torque sensor),
`intent` (the IntentEstimator's state), `perceived_scene`, `skeleton` (lifted) and
`detections`, and optionally `head_command` (the GazeController's: the head is its after the
look round whenever the cycle looks at nothing in particular; unconnected, the head holds the
ready posture's). Every TICK_S it looks round first (the head panned to the table's ends), then
steps the `HandoverCycle` on what it perceives; the cycle plans through a `PerceivedPlanner`.
Once it has seen the person's shoulders and the objects, it raises its torso if the objects
would hide a pointing arm from its camera (`watch_view`), and watches from there.
Outputs: `hsr_desired_state` ([q; v] of COMMANDED_JOINTS: the motion under way, else where it
stands; the ready posture before any), `gripper_desired_opening`, `cycle` (the record),
`plan_view` (PlanView: what the plans show in the replay), `watching` (1 while the cycle
watches for a request, else 0: the perception that serves only the watch rests, see
`systems.watching`) and `commanded_trajectories` (every motion started so far, as the HSR's
trajectory controllers would be sent it: `interface.joint_trajectory`).

While the robot lifts and carries, it watches for a correction itself (`CorrectionWatch`), on
the frames it reads anyway (one in three), until the person asks for another object
(`Percepts.correction`). The estimator, kept awake for it, had the camera render every frame
while the robot acted.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import BasicVector, Context, LeafSystem, State

from hsr_handover.hsr import COMMANDED_JOINTS, GRIPPER_KEY, HEAD_JOINTS
from hsr_handover.interface import COMMANDED_TRAJECTORIES
from hsr_handover.interface.joint_trajectory import JointTrajectory
from hsr_handover.robot.effectivity.arm_map import ArmEffectivity
from hsr_handover.robot.effectivity.person_map import (
    RECEIVING_SIDES,
    STEADY_FRAMES,
    HumanArm,
    receiving_arms,
)
from hsr_handover.robot.handover.correction_watch import CorrectionWatch
from hsr_handover.robot.handover.cycle import HandoverCycle
from hsr_handover.robot.handover.cycle_types import CycleRecord, Percepts, Phase
from hsr_handover.robot.handover.gaze import look_at
from hsr_handover.robot.handover.look_round import (
    LOOK_AROUND_PANS,
    LOOK_DWELL_S,
    LOOK_ROUND_S,
    LOOK_ROUND_TILT,
    look_round_pan,
)
from hsr_handover.robot.handover.perceived_planner import PerceivedPlanner, pads_centre
from hsr_handover.robot.handover.person_points import face_point, person_point, wrist
from hsr_handover.robot.handover.scene_memory import remember
from hsr_handover.robot.handover.watch_view import WatchView
from hsr_handover.robot.intent import IntentParams, IntentState
from hsr_handover.robot.perception.facing import SteadyFacing
from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.robot.planning.plan import Motion
from hsr_handover.robot.planning.plan_view import PlanView
from hsr_handover.robot.systems.watching import WATCHING

TICK_S = 0.1  # s between the supervisor's decisions
RAISE = "raise"  # the move to the posture it watches from, as a commanded motion
PAN, TILT = (COMMANDED_JOINTS.index(joint) for joint in HEAD_JOINTS)
BODY_ROWS = [row for row, joint in enumerate(COMMANDED_JOINTS) if joint not in HEAD_JOINTS]
VIEW_AFTER_S = LOOK_DWELL_S * len(LOOK_AROUND_PANS)
"""s: where to watch from is first weighed as the look round turns back to where it began,
the objects on both sides seen (a raise of 0.6 m then ends by about 5 s), and again whenever
another object comes into view until a request is recognised."""


@dataclasses.dataclass
class _Memory:
    """What the supervisor carries between ticks: the cycle's state machine (`machine`, whose
    `record` the `cycle` port gives), the latest STEADY_FRAMES skeletons (newest first: the
    arms' shoulders are steady over them), the person's arms as last seen with both shoulders,
    the way their torso faces (voted over the watch's frames: later, the robot's own arm comes
    between the camera and the chest), the head's aim, the scene with what is out of view
    remembered, and where it watches from."""

    machine: HandoverCycle
    correcting: CorrectionWatch  # for another object asked for, once it has lifted
    skeletons: tuple[Skeleton, ...] = ()
    arms: tuple[HumanArm, ...] = ()
    facing: SteadyFacing = dataclasses.field(default_factory=SteadyFacing)
    head: tuple[float, float] | None = None  # (pan, tilt) rad while the cycle looks at a point
    scene: PerceivedScene | None = None
    view: WatchView = dataclasses.field(default_factory=WatchView)  # where it watches from
    commanded: tuple[JointTrajectory, ...] = ()  # the motions started, as controllers take them


class HandoverSupervisor(LeafSystem):
    """Steps the handover cycle on the robot's percepts and commands the HSR."""

    def __init__(
        self,
        arm_map: ArmEffectivity,
        ready_state: np.ndarray,
        ready_opening: float,
        intent_params: IntentParams | None = None,
    ):
        super().__init__()
        self._intent_params = IntentParams() if intent_params is None else intent_params
        self._planner = PerceivedPlanner(arm_map)
        self._robot = self._planner.robot
        self._rows = np.array([self._robot.index(joint) for joint in COMMANDED_JOINTS])
        self._ready = np.asarray(ready_state, dtype=float)
        self._ready_opening = float(ready_opening)
        n = len(COMMANDED_JOINTS)
        self._state = self.DeclareVectorInputPort("hsr_state_measured", 2 * n)
        self._opening = self.DeclareVectorInputPort("gripper_opening_measured", 1)
        self._wrench = self.DeclareVectorInputPort("hsr_wrist_wrench_measured", 6)
        self._intent = self.DeclareAbstractInputPort("intent", AbstractValue.Make(IntentState()))
        self._scene = self.DeclareAbstractInputPort(
            "perceived_scene", AbstractValue.Make(PerceivedScene(None))
        )
        self._skeleton = self.DeclareAbstractInputPort(
            "skeleton", AbstractValue.Make(Skeleton.missing("not read"))
        )
        self._detections = self.DeclareAbstractInputPort(
            "detections", AbstractValue.Make(DetectionResult((), "not read"))
        )
        # Optional: the GazeController's move; unconnected, the head holds the ready posture's.
        self._gaze = self.DeclareVectorInputPort("head_command", 4)
        memory = _Memory(
            HandoverCycle(self._planner), correcting=CorrectionWatch(self._intent_params)
        )
        self._memory = self.DeclareAbstractState(AbstractValue.Make(memory))
        # Evaluated at each plant step: streamed at 100 Hz instead (a discrete state), the
        # 10 ms steps in the commanded fingers and arm shook held objects loose.
        self.DeclareVectorOutputPort("hsr_desired_state", 2 * n, self._calc_state)
        self.DeclareVectorOutputPort("gripper_desired_opening", 1, self._calc_opening)
        self.DeclareAbstractOutputPort(
            "cycle", lambda: AbstractValue.Make(CycleRecord()), self._calc_cycle
        )
        self.DeclareAbstractOutputPort(
            "plan_view", lambda: AbstractValue.Make(PlanView()), self._calc_plan_view
        )
        # From the state alone: the perception it gates feeds this system's inputs.
        self.DeclareVectorOutputPort(
            WATCHING, 1, self._calc_watching,
            prerequisites_of_calc={self.abstract_state_ticket(self._memory)},
        )  # fmt: skip
        self.DeclareAbstractOutputPort(
            COMMANDED_TRAJECTORIES, lambda: AbstractValue.Make(()), self._calc_commanded,
            prerequisites_of_calc={self.abstract_state_ticket(self._memory)},
        )  # fmt: skip
        self.DeclarePeriodicUnrestrictedUpdateEvent(TICK_S, 0.0, self._tick)

    def _memory_of(self, context: Context) -> _Memory:
        return context.get_abstract_state(self._memory).get_value()

    def memory(self, context: Context) -> _Memory:
        """What the supervisor carries between ticks in `context`, to read or change (Drake is
        told it may change)."""
        return context.get_mutable_abstract_state(self._memory).get_mutable_value()

    def _tick(self, context: Context, state: State) -> None:
        memory: _Memory = state.get_mutable_abstract_state(self._memory).get_value()
        self._decide(context, memory)
        memory.commanded = self._commanded(memory)

    def _decide(self, context: Context, memory: _Memory) -> None:
        """Look round, weigh where to watch from, and step the cycle on what it perceives."""
        skeleton = self._skeleton.Eval(context)
        if memory.machine.record.phase is Phase.WATCH:
            memory.facing = memory.facing.add(skeleton.torso_forward)
        memory.skeletons = (skeleton, *memory.skeletons)[:STEADY_FRAMES]
        arms = receiving_arms(memory.skeletons, memory.facing.direction())
        memory.arms = arms or memory.arms
        memory.scene = remember(memory.scene, self._scene.Eval(context))
        if context.get_time() >= VIEW_AFTER_S:
            self._raise_view(context, skeleton, memory)
        if context.get_time() < LOOK_ROUND_S:  # it looks round before it acts
            return
        memory.machine.planner = memory.machine.planner.perceiving(memory.scene, memory.arms)
        percepts = self._percepts(context, skeleton, arms, memory)
        memory.machine.step(percepts)
        point = memory.machine.gaze()
        if point is None:
            point = self._target_unseen(memory)
        memory.head = None if point is None else look_at(self._robot, percepts.q, point)

    def _commanded(self, memory: _Memory) -> tuple[JointTrajectory, ...]:
        """`memory.commanded` with the motions started since: the raise to where it watches
        from and the cycle's, in the order they started."""
        raised = memory.view.raised
        started = [] if raised is None else [(raised.start, RAISE, raised.motion)]
        started += [(start, motion.name, motion) for start, motion in memory.machine.started]
        known = {(trajectory.start, trajectory.name) for trajectory in memory.commanded}
        new = sorted((item for item in started if item[:2] not in known), key=lambda item: item[0])
        return memory.commanded + tuple(self._trajectory(*item) for item in new)

    def _trajectory(self, start: float, name: str, motion: Motion) -> JointTrajectory:
        """The motion at the times it was timed at, for the base and the arm (the head is the
        gaze's), in COMMANDED_JOINTS' order."""
        times, positions, velocities = motion.knots()
        columns = self._rows[BODY_ROWS]
        return JointTrajectory(name, start, times, positions[:, columns],
                               velocities[:, columns])  # fmt: skip

    def _target_unseen(self, memory: _Memory) -> np.ndarray | None:
        """Where the object asked for was last seen, while the cycle waits to see it before it
        plans its grasp (`HandoverCycle.seeing`); else None."""
        label = memory.machine.seeing()
        if label is None or memory.scene is None:
            return None
        shapes = [shape.centroid for shape in memory.scene.objects if shape.label == label]
        return shapes[0] if shapes else None

    def _raise_view(self, context: Context, skeleton, memory: _Memory) -> None:
        """Raise the torso if the objects would hide a pointing arm (`WatchView.weigh`), only
        while it watches for a request."""
        requested = memory.machine.record.target is not None
        if requested or not memory.view.settled(context.get_time()):
            return
        objects = memory.scene.objects if memory.scene is not None else ()
        raised = memory.view.weigh(context.get_time(), self._robot, self._measured(context),
                                   skeleton.points, skeleton.confidence, objects,
                                   functools.partial(self._plan_raise, memory))  # fmt: skip
        if raised is not None:
            memory.machine.wait_until(raised.end)  # the grasp plans from the view reached

    def _plan_raise(self, memory: _Memory, q: np.ndarray, posture: np.ndarray) -> Motion | None:
        """The planner's motion to the posture it watches from, None if it finds none."""
        memory.machine.planner = memory.machine.planner.perceiving(memory.scene, memory.arms)
        planned = memory.machine.planner.posture(q, posture)
        return planned.motions[0] if planned.ok else None

    def _measured(self, context: Context) -> np.ndarray:
        """The HSR's measured positions (plant order), also set in the planner's robot."""
        measured = self._state.Eval(context)[: len(COMMANDED_JOINTS)]
        opening = float(self._opening.Eval(context)[0])
        self._robot.set_positions(dict(zip(COMMANDED_JOINTS, measured, strict=True))
                                  | {GRIPPER_KEY: opening})  # fmt: skip
        return self._robot.positions()

    def _percepts(
        self, context: Context, skeleton, arms: tuple[HumanArm, ...], memory: _Memory
    ) -> Percepts:
        time, q = context.get_time(), self._measured(context)
        opening = float(self._opening.Eval(context)[0])
        intent, record = self._intent.Eval(context), memory.machine.record
        wanted = record.target or intent.target  # what it is fetching, once it has begun
        detections = self._detections.Eval(context)
        side = record.receiving or RECEIVING_SIDES[0]
        arm = next((arm for arm in arms if arm.side == side), None)
        palm_pose = self._planner.palm_pose(q)
        palm = pads_centre(palm_pose)
        correction = memory.correcting.update(time, record, intent, skeleton, detections, palm)
        commanded, _, _ = memory.machine.command(time)
        pull = 0.0 if commanded is None else np.linalg.norm(palm - self._planner.palm(commanded))
        wrist_force = palm_pose.rotation() @ self._wrench.Eval(context)[3:]
        return Percepts(time, q, opening, intent.target, detections.seen(wanted),
                        wrist(skeleton, side), palm, person_point(skeleton, arm), float(pull),
                        wrist_force, face_point(skeleton), correction)  # fmt: skip

    def _calc_state(self, context: Context, output: BasicVector) -> None:
        time = context.get_time()
        memory = self._memory_of(context)
        q, v, _ = memory.machine.command(time)
        if q is None:
            command = self._resting(memory, time)
        else:
            command = np.concatenate([q[self._rows], v[self._rows]])
        n = len(COMMANDED_JOINTS)
        if memory.head is not None:
            command[[PAN, TILT, n + PAN, n + TILT]] = [*memory.head, 0.0, 0.0]
        elif time < LOOK_ROUND_S:
            command[[PAN, n + PAN]] = look_round_pan(time, self._ready[PAN]), 0.0
            if self._gaze.HasValue(context):  # the table, whatever its height
                command[[TILT, n + TILT]] = LOOK_ROUND_TILT, 0.0
        elif self._gaze.HasValue(context):
            command[[PAN, TILT, n + PAN, n + TILT]] = self._gaze.Eval(context)
        output.SetFromVector(command)

    def _resting(self, memory: _Memory, time: float) -> np.ndarray:
        """The command while the cycle moves nothing: the ready posture, or the posture it
        watches from (the move to it as planned, base and arm; the head looks round)."""
        command = self._ready.copy()
        if memory.view.raised is not None:
            q, v = memory.view.raised.state(time)
            n, rows = len(COMMANDED_JOINTS), BODY_ROWS  # the head is the watcher's
            command[rows] = q[self._rows[rows]]
            command[[n + row for row in rows]] = v[self._rows[rows]]
        return command

    def _calc_opening(self, context: Context, output: BasicVector) -> None:
        machine = self._memory_of(context).machine
        if machine.record.phase is Phase.WATCH:
            output.SetFromVector([self._ready_opening])
            return
        output.SetFromVector([machine.gripper])

    def _calc_watching(self, context: Context, output: BasicVector) -> None:
        watching = self._memory_of(context).machine.record.phase is Phase.WATCH
        output.SetFromVector([1.0 if watching else 0.0])

    def _calc_cycle(self, context: Context, output: AbstractValue) -> None:
        memory = self._memory_of(context)
        lift = 0.0 if memory.view.raised is None else memory.view.raised.lift
        output.set_value(dataclasses.replace(memory.machine.record, watch_lift=lift))

    def _calc_commanded(self, context: Context, output: AbstractValue) -> None:
        output.set_value(self._memory_of(context).commanded)

    def _calc_plan_view(self, context: Context, output: AbstractValue) -> None:
        output.set_value(self._memory_of(context).machine.view)
