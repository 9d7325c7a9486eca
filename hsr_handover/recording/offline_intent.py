"""The robot's perception and intent estimator run offline on a recording: a session folder
(`rgbd_session`) or a ROS bag (`ros_bag_session`). No world, no simulator of one; the robot's
own diagram fed by a SessionPlayer on the ports the station's sensors feed live, so the same
recording gives the same recognition offline as it did online.

The robot perceives with the settings the recording was made with (a folder's `session.yaml`,
a bag's settings topic, read as a scenario file: `simulation.seed`, `camera.rate_hz`,
`perception`, `intent`), else the defaults at the frame rate of its stamps; the camera's
intrinsics come from the recording's camera info.
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
from pathlib import Path

import numpy as np
import yaml
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.recording.recorded_session import RecordedSession
from hsr_handover.recording.rgbd_session import SESSION, SessionError
from hsr_handover.recording.session_player import SessionPlayer
from hsr_handover.robot.builder import build_robot
from hsr_handover.robot.intent import IntentState
from hsr_handover.scenario import Scenario, ScenarioError, load_scenario
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


def _settings_scenario(session: RecordedSession) -> Scenario:
    """The session's settings read as a scenario file is, with its checks (SessionError naming
    where the settings came from)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / SESSION
        path.write_text(yaml.safe_dump(session.settings, sort_keys=False))
        try:
            return load_scenario(path)
        except ScenarioError as error:
            raise SessionError(
                f"{session.settings_source}: {error.key_path}: {error.expected}"
            ) from None


def _robot_scenario(session: RecordedSession) -> Scenario:
    """The scenario the robot is built from: the session's settings, its camera's intrinsics."""
    scenario = _settings_scenario(session) if session.settings else Scenario()
    if not session.settings and len(session.stamps) > 1:
        scenario.camera.rate_hz = float(1.0 / np.median(np.diff(session.stamps)))
    camera = session.camera
    scenario.camera.width, scenario.camera.height = camera.width, camera.height
    scenario.camera.intrinsics = [camera.fx, camera.fy, camera.cx, camera.cy]
    scenario.perception.enabled, scenario.handover.enabled = True, False
    scenario.perception.attention, scenario.perception.skeleton_recording = [], None
    scenario.perception.active_gaze = False  # a recording's head moved as it was recorded
    return scenario


def perceive(session: RecordedSession) -> OfflineIntent:
    """Run the robot's perception and intent estimator over a recording read (a session folder
    or a bag); what it recognised. Raises SessionError naming the file at fault."""
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
