"""Loading a scenario file: YAML, then the schema walk, then Drake's typed loader, then checks."""

from pathlib import Path

import yaml
from pydrake.common.yaml import yaml_load_typed

from hsr_handover.scenario.checks import check_scenario
from hsr_handover.scenario.schema import Scenario, ScenarioError
from hsr_handover.scenario.strict_yaml import load_yaml
from hsr_handover.scenario.typed_yaml import SchemaMismatch, check_against_schema

MAX_FILE_BYTES = 1_000_000
"""Largest scenario file read; the bundled ones are under 3 kB."""


def load_scenario(filename: str | Path) -> Scenario:
    """Load and check a scenario file. Raises ScenarioError naming the file, key and expectation.

    An empty (or comment-only) file is an error, not an all-defaults scenario: a scenario
    without objects or a script shows nothing, so an empty file is more likely a mistake.

    Checks here need only the file; checks that need the built scene (the person or the robot
    intersecting the table) run when the station is built.
    """
    name = str(filename)
    text = _read_text(Path(filename), name)
    try:
        raw = load_yaml(text)
        if raw is None:
            raise SchemaMismatch("(file)", "expected a mapping of scenario sections, got none")
        check_against_schema(raw, Scenario)
        # Drake parses the same text again; the walk above has ruled out everything it would
        # read differently, but its scanner is stricter (a tab after a key's colon).
        scenario = yaml_load_typed(schema=Scenario, data=text, defaults=Scenario())
    except yaml.YAMLError as error:
        raise _yaml_error(name, text, error) from None
    except SchemaMismatch as error:
        raise ScenarioError(name, error.key_path, error.expected) from None
    scenario.source = name
    check_scenario(scenario)
    return scenario


def _yaml_error(name: str, text: str, error: yaml.YAMLError) -> ScenarioError:
    """The line, the column and the problem PyYAML found (a ReaderError has a position instead
    of a mark)."""
    mark = getattr(error, "problem_mark", None)
    position = getattr(error, "position", None)
    if mark is not None:
        where = f"line {mark.line + 1}, column {mark.column + 1}"
    elif position is not None:
        line_start = text.rfind("\n", 0, position) + 1
        where = f"line {text.count(chr(10), 0, position) + 1}, column {position - line_start + 1}"
    else:
        where = "(file)"
    problem = getattr(error, "problem", None) or getattr(error, "reason", None)
    context, begun = getattr(error, "context", None), getattr(error, "context_mark", None)
    elsewhere = begun is not None and (mark is None or begun.index != mark.index)
    if problem and context and elsewhere:  # an unclosed quote, say: where it was opened
        problem += f", {context} begun at line {begun.line + 1}, column {begun.column + 1}"
    return ScenarioError(
        name, where, f"expected valid YAML ({problem})" if problem else "expected valid YAML"
    )


def _read_text(path: Path, name: str) -> str:
    if not path.is_file():
        raise ScenarioError(name, "(file)", "expected an existing scenario YAML file")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise ScenarioError(name, "(file)", f"expected a file under {MAX_FILE_BYTES:,} bytes")
    data = path.read_bytes()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        raise ScenarioError(name, "(file)", f"expected UTF-8 text; line {line} is not") from None
