"""Loading a scenario file: YAML, then the schema walk, then Drake's typed loader, then checks."""

from pathlib import Path

import yaml
from pydrake.common.yaml import yaml_load_typed

from hsr_handover.scenario.checks import check_scenario
from hsr_handover.scenario.schema import Scenario, ScenarioError
from hsr_handover.scenario.typed_yaml import SchemaMismatch, check_against_schema


def load_scenario(filename: str | Path) -> Scenario:
    """Load and check a scenario file. Raises ScenarioError naming the file, key and expectation.

    Checks here need only the file; checks that need the built scene (the person or the robot
    intersecting the table) run in `station.check_initial_clearance`.
    """
    path = Path(filename)
    name = str(filename)
    if not path.is_file():
        raise ScenarioError(name, "(file)", "expected an existing scenario YAML file")
    try:
        raw = yaml.safe_load(path.read_text())
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark else "(file)"
        raise ScenarioError(name, where, "expected valid YAML") from None
    try:
        check_against_schema(raw if raw is not None else {}, Scenario)
    except SchemaMismatch as error:
        raise ScenarioError(name, error.key_path, error.expected) from None
    if raw is not None and "source" in raw:
        raise ScenarioError(name, "source", "unknown key; it is set by the loader")
    scenario = yaml_load_typed(schema=Scenario, filename=str(path), defaults=Scenario())
    scenario.source = name
    check_scenario(scenario)
    return scenario
