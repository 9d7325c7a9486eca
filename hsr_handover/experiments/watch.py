"""Let the robot watch a scenario for a while with perception on, then read its percepts: the
start of every experiment that plans from what the robot perceives."""

from __future__ import annotations

import dataclasses

from pydrake.geometry import Meshcat
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context

from hsr_handover.hsr import COMMANDED_JOINTS, HEAD_JOINTS
from hsr_handover.robot.effectivity.person_map import HumanArm, receiving_arms
from hsr_handover.robot.handover.look_round import LOOK_AROUND_PANS, LOOK_DWELL_S, LOOK_ROUND_TILT
from hsr_handover.robot.handover.scene_memory import remember
from hsr_handover.robot.perception.facing import steady_facing
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.robot.planning.perceived_scene import PerceivedScene
from hsr_handover.scenario import Scenario
from hsr_handover.simulation import Simulation, prepare_simulation, start_replay

WATCH_S = 3.5  # s of watching before planning: the look round (2.7 s), then a steady view
RECENT_S, RECENT_STEP_S = 0.6, 0.1  # the skeletons kept of the watch's end, and how often
SCENE_STEP_S = 0.1  # s between the perceived scenes remembered (the supervisor's tick)


@dataclasses.dataclass
class Watched:
    """The simulation after watching, its `simulator` (keeps the contexts alive) and `root`
    context, the skeletons perceived at each stop of the look round (`glimpses`, oldest
    first) and every RECENT_STEP_S over the watch's last RECENT_S (`recent`, oldest first),
    and the Meshcat recording the replay (None without one); `scene`, the perceived scene
    with what the camera turned away from remembered, every SCENE_STEP_S, as the supervisor
    keeps it (`scene_memory.remember`): what to plan in, for the last frame alone lacks what
    the look round saw and the view back does not (an object at the table's end);
    `percept(name)` evaluates one of the robot's perception outputs now."""

    simulation: Simulation
    simulator: Simulator
    root: Context
    scene: PerceivedScene
    glimpses: tuple[Skeleton, ...] = ()
    meshcat: Meshcat | None = None
    recent: tuple[Skeleton, ...] = ()

    def percept(self, name: str):
        return _percept(self.simulation, self.simulator, name)

    def measured_positions(self) -> dict[str, float]:
        return self.simulation.measured_positions(self.root)

    def person_arm(self) -> HumanArm | None:
        """The receiving arm as last seen: now, or else in the latest view that showed both
        shoulders (of the watch's end, then of the look round: a person beside a moved table
        can be out of view ahead), its shoulder steady over that view and the ones before it
        (`person_map.STEADY_FRAMES`: the watch's end, then the look round's stops); its frame
        faces the chest's facing voted over those views, its size the median over them
        (`receiving_arms`)."""
        skeletons = (self.percept("skeleton"), *reversed(self.recent), *reversed(self.glimpses))
        forward = steady_facing(skeleton.torso_forward for skeleton in skeletons)
        arms = receiving_arms(skeletons, forward)
        return arms[0] if arms else None


def watch(
    scenario: Scenario, seconds: float, look_around: bool = False, replay: bool = False
) -> Watched:
    """Simulate `scenario` for `seconds` with perception on and the handover off, whatever
    the file says. With `look_around`, the head first pans to each of LOOK_AROUND_PANS for
    LOOK_DWELL_S (so the table's ends come into view), then back, before the remaining time.
    With `replay`, the run is recorded in a Meshcat (`Watched.meshcat`; `replay.write_replay`
    writes it)."""
    # The look round below commands the head itself.
    perception = dataclasses.replace(
        scenario.perception,
        enabled=True,
        active_gaze=scenario.perception.active_gaze and not look_around,
    )
    handover = dataclasses.replace(scenario.handover, enabled=False)  # it watches, no more
    scenario = dataclasses.replace(scenario, perception=perception, handover=handover)
    simulation, meshcat = prepare_simulation(scenario, with_meshcat=replay)
    simulator = Simulator(simulation.diagram)
    if meshcat is not None:
        start_replay(meshcat, scenario)
    memory = _SceneMemory(simulation, simulator)
    glimpses = _look_around(simulation, simulator, memory) if look_around else ()
    end = max(seconds, simulator.get_context().get_time())
    recent = []
    for k in range(round(RECENT_S / RECENT_STEP_S)):
        time = end - RECENT_S + k * RECENT_STEP_S
        if time > simulator.get_context().get_time():
            memory.advance_to(time)
            recent.append(_percept(simulation, simulator, "skeleton"))
    memory.advance_to(end)
    return Watched(simulation, simulator, simulator.get_context(), memory.scene, glimpses,
                   meshcat, tuple(recent))  # fmt: skip


def _percept(simulation: Simulation, simulator: Simulator, name: str):
    robot_context = simulation.robot_context(simulator.get_context())
    return simulation.robot.diagram.GetOutputPort(name).Eval(robot_context)


class _SceneMemory:
    """Advances the simulator, remembering the perceived scene every SCENE_STEP_S on the way."""

    def __init__(self, simulation: Simulation, simulator: Simulator):
        self._simulation, self._simulator = simulation, simulator
        self.scene: PerceivedScene | None = None

    def advance_to(self, time: float) -> None:
        """Advance to `time` (at least initialising the simulator), remembering on the way."""
        while True:
            step_end = self._simulator.get_context().get_time() + SCENE_STEP_S
            last = step_end >= time - 1e-9  # not a sliver of a step for the sums' rounding
            self._simulator.AdvanceTo(time if last else step_end)
            seen = _percept(self._simulation, self._simulator, "perceived_scene")
            self.scene = remember(self.scene, seen)
            if last:
                return


def _look_around(
    simulation: Simulation, simulator: Simulator, memory: _SceneMemory
) -> tuple[Skeleton, ...]:
    """A stand-in for the supervisor's look round: the ready posture's head pan
    stepped through LOOK_AROUND_PANS with the head tilted to LOOK_ROUND_TILT, then back to
    where it was (advanced by `memory`); the skeleton perceived at the end of each stop."""
    posture = simulation.robot.diagram.GetSubsystemByName("ready_posture")
    context = posture.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    command = posture.get_mutable_source_value(context)
    pan, tilt = (COMMANDED_JOINTS.index(joint) for joint in HEAD_JOINTS)
    start = tuple(command.get_value()[[pan, tilt]])
    stops = [(angle, LOOK_ROUND_TILT) for angle in LOOK_AROUND_PANS]
    glimpses = []
    for head in (*stops, start):
        value = command.get_value().copy()
        value[[pan, tilt]] = head
        command.set_value(value)
        memory.advance_to(simulator.get_context().get_time() + LOOK_DWELL_S)
        glimpses.append(_percept(simulation, simulator, "skeleton"))
    return tuple(glimpses)
