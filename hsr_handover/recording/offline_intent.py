"""The robot's perception and intent estimator run offline on a recorded RGB-D session
(`perception.rgbd_session`): no world, no simulator of one; the robot's own diagram fed by a
SessionPlayer on the ports the station's sensors feed live, so the same session gives the same
recognition offline as it did online.

The robot perceives with the settings the session was recorded with (its `session.yaml`, read
as a scenario file: `simulation.seed`, `camera.rate_hz`, `perception`, `intent`), else the
defaults at the frame rate of its stamps; the camera's intrinsics come from its
`camera_info.yaml`.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.recording.rgbd_session import SESSION, RgbdSession, read_session
from hsr_handover.recording.session_player import SessionPlayer
from hsr_handover.robot.builder import build_robot
from hsr_handover.robot.intent import IntentState
from hsr_handover.scenario import Scenario, load_scenario
from hsr_handover.systems.port_types import check_abstract_connections


@dataclasses.dataclass(frozen=True)
class OfflineIntent:
    """What the robot recognised in a session: the `target` (the detector's label, a colour;
    None if nothing), its `confidence`, when (`recognised_time`, s on the session's stamps;
    NaN if never) and in which `frame` (-1 if never), over `frames` frames at `rate_hz`."""

    target: str | None
    confidence: float
    recognised_time: float
    frame: int
    frames: int
    rate_hz: float

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _robot_scenario(session: RgbdSession) -> Scenario:
    """The scenario the robot is built from: the session's settings, its camera's intrinsics."""
    settings = session.directory / SESSION
    scenario = load_scenario(settings) if settings.is_file() else Scenario()
    if not settings.is_file() and len(session.stamps) > 1:
        scenario.camera.rate_hz = float(1.0 / np.median(np.diff(session.stamps)))
    camera = session.camera
    scenario.camera.width, scenario.camera.height = camera.width, camera.height
    scenario.camera.intrinsics = [camera.fx, camera.fy, camera.cx, camera.cy]
    scenario.perception.enabled, scenario.handover.enabled = True, False
    scenario.perception.attention, scenario.perception.skeleton_recording = [], None
    scenario.perception.active_gaze = False  # a recording's head moved as it was recorded
    return scenario


def perceive_session(directory: Path) -> OfflineIntent:
    """Run the robot's perception and intent estimator over a recorded session; what it
    recognised. Raises SessionError or ScenarioError (ValueErrors) naming the file at fault."""
    session = read_session(Path(directory))
    scenario = _robot_scenario(session)
    robot = build_robot(scenario).diagram
    start = session.stamps[0]
    builder = DiagramBuilder()
    player = builder.AddNamedSystem("session_player", SessionPlayer(session, start))
    builder.AddSystem(robot)
    for index in range(robot.num_input_ports()):
        port = robot.get_input_port(index)
        builder.Connect(player.GetOutputPort(port.get_name()), port)
    diagram = builder.Build()
    check_abstract_connections(diagram)
    simulator = Simulator(diagram)
    period = 1.0 / scenario.camera.rate_hz
    simulator.AdvanceTo(session.stamps[-1] - start + period)
    intent: IntentState = robot.GetOutputPort("intent").Eval(
        robot.GetMyContextFromRoot(simulator.get_context())
    )
    time = intent.recognised_time + start
    frame = -1 if math.isnan(time) else int(np.argmin(np.abs(np.array(session.stamps) - time)))
    return OfflineIntent(intent.target, float(intent.confidence), time, frame,
                         len(session.stamps), scenario.camera.rate_hz)  # fmt: skip
