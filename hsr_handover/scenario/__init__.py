"""Scenarios: the typed schema, loading a file, and the checks that give one-line errors.

`schema` holds the dataclasses, `typed_yaml` the key-path schema walk, `checks` the checks on a
loaded scenario's numbers, `loading` the file reader that runs them in order.
"""

from hsr_handover.scenario.checks import (
    object_center,
    resolve_model_path,
    resolve_recording_path,
)
from hsr_handover.scenario.loading import load_scenario
from hsr_handover.scenario.robot_start import robot_start_positions
from hsr_handover.scenario.schema import (
    ActionConfig,
    CameraConfig,
    FocusConfig,
    GngConfig,
    ImprecisionConfig,
    IntentConfig,
    ObjectConfig,
    PerceptionConfig,
    PersonConfig,
    RobotConfig,
    Scenario,
    ScenarioError,
    SimulationConfig,
    SkeletonRecordingConfig,
    TableConfig,
    VariationConfig,
)

__all__ = [
    "ActionConfig", "CameraConfig", "FocusConfig", "GngConfig", "ImprecisionConfig",
    "IntentConfig", "ObjectConfig", "VariationConfig",
    "PerceptionConfig", "PersonConfig", "RobotConfig", "Scenario", "ScenarioError",
    "SimulationConfig", "SkeletonRecordingConfig", "TableConfig", "load_scenario", "object_center",
    "resolve_model_path", "resolve_recording_path", "robot_start_positions",
]  # fmt: skip
