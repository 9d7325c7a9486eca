"""Fuzzing the scenario loader: mutated copies of the bundled scenarios get a clean answer.

`hsr-handover validate` either accepts the file (exit 0; then a short run succeeds too) or
rejects it with exit 2 and exactly one short stderr line `error: FILE: KEY: expected ...`:
never a traceback, a Drake message, exit 1 or a hang. Derandomised, so CI sees the same cases.
"""

from __future__ import annotations

import copy
import re
import signal
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from hsr_handover.cli import main
from hsr_handover.scenario import ScenarioError, load_scenario
from tests.paths import bundled_scenarios

MAX_EXAMPLES = 200
MAX_RUNS = 3  # accepted examples that also simulate; building the world takes ~1-2 s each
EXAMPLE_TIME_LIMIT_S = 60
MAX_ERROR_LINE = 300

MARKER = "MUTATION_MARKER"
KEY_PATH = re.compile(r"\(file\)|\(top level\)|line \d+|[^\s:][^:]*")  # a key path or a place

# Raw YAML put in place of a leaf. Each is one line, so it fits block and flow style alike.
OUT_OF_RANGE = [".nan", ".inf", "-.inf", "1.0e+308", "-1.0e+308", "1e308", "9" * 5000]
OTHER_VALUES = [
    "-1", "0", "0.0", "1e-300", "2", "-0.5", "3.5", "'text'", "true", "null", "[]", "{}",
    "[" + ", ".join(["1.5"] * 2000) + "]", "[" * 1000 + "]" * 1000, "'" + "x" * 10_000 + "'",
    "!!int abc", "{a: 1, a: 2}",
]  # fmt: skip

RANDOM_VALUES = st.one_of(
    st.floats(), st.integers(), st.booleans(), st.none(), st.text(max_size=30),
    st.lists(st.floats(allow_nan=False), max_size=4),
)  # fmt: skip

# Pieces of YAML syntax, tags and control characters that arbitrary scenario text is made of.
YAML_PIECES = st.sampled_from(
    [*"[]{}:,-?!&*|>'\"#%@` \n\tab01.e+_<=~\x00", "!!int ", "!!float ", "!!timestamp ",
     "!!binary ", "!!set ", "!!omap ", "!!map ", "!!seq ", "!!str ", "<<: ", "&a ", "*a", "---\n",
     "? ", "simulation: ", "duration: "]
)  # fmt: skip

FUZZ_SETTINGS = settings(
    max_examples=MAX_EXAMPLES,
    deadline=None,
    derandomize=True,  # the same examples on every run, so CI is repeatable
    database=None,
    # tmp_path and capsys are shared by the examples of one test; each example rewrites the file
    # and reads its captured output.
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)

SCENARIO_DATA = {path.name: yaml.safe_load(path.read_text()) for path in bundled_scenarios()}


def _leaves(node: Any, path: tuple = ()) -> Iterator[tuple]:
    """Paths (tuples of keys and indices) of every scalar in the data."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _leaves(value, (*path, key))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            yield from _leaves(value, (*path, index))
    else:
        yield path


def _key_path(path: tuple) -> str:
    """A path as the loader names it: `objects[1].size[0]`."""
    text = "".join(f"[{part}]" if isinstance(part, int) else f".{part}" for part in path)
    return text.removeprefix(".")


def _parent(data: Any, path: tuple) -> Any:
    for part in path[:-1]:
        data = data[part]
    return data


@st.composite
def mutated_scenarios(draw) -> tuple[bytes, str | None]:
    """A mutated bundled scenario as file bytes, and the key path of a value every scenario
    rejects (non-finite, huge, a repeated key), whose error must name it or a parent; else
    None."""
    data = copy.deepcopy(SCENARIO_DATA[draw(st.sampled_from(sorted(SCENARIO_DATA)))])
    leaves = list(_leaves(data))
    path = draw(st.sampled_from(leaves))
    parent, last = _parent(data, path), path[-1]
    kinds = ["out of range", "value", "random value", "delete", "unknown", "bytes", "tab"]
    kinds.append("duplicate key" if isinstance(parent, dict) else "copy item")
    if isinstance(parent[last], int | float) and not isinstance(parent[last], bool):
        kinds += ["scale"] * 3  # small changes: the most likely to be accepted, then simulated
    kind = draw(st.sampled_from(kinds))
    raw, named = MARKER, None
    if kind == "out of range":
        parent[last], raw, named = MARKER, draw(st.sampled_from(OUT_OF_RANGE)), _key_path(path)
    elif kind == "scale":
        factor = draw(st.sampled_from([0.5, 0.9, 1.1, 2.0, -1.0]))
        parent[last] = type(parent[last])(parent[last] * factor)
    elif kind == "random value":
        parent[last] = draw(RANDOM_VALUES)
    elif kind == "value":
        parent[last], raw = MARKER, draw(st.sampled_from(OTHER_VALUES))
    elif kind == "delete":
        del parent[last]
    elif kind == "duplicate key":
        parent[MARKER] = 0
        raw = f"{last}: {draw(st.sampled_from(['0.5', '1', repr(parent[last])]))}"
        named = _key_path(path)
    elif kind == "unknown":
        container = _parent(data, path[:-1]) if len(path) > 1 else data
        target = container if isinstance(container, dict) else parent
        target[draw(st.sampled_from(["colour", "k" * 5000, "source", "1"]))] = 1
    elif kind == "copy item":
        parent.append(copy.deepcopy(parent[last]))
    text = yaml.safe_dump(data, sort_keys=False, default_flow_style=draw(st.booleans()))
    text = text.replace(f"{MARKER}: 0", raw).replace(MARKER, raw)
    encoded = text.encode()
    if kind == "bytes":  # the file cut short, and a stray byte, tab or quote from there on
        at = draw(st.integers(0, len(encoded)))
        stray = draw(st.sampled_from([b"\xff", b"\x00", b"", b"\n  ]{", b"\t", b'"', b"'"]))
        encoded = encoded[:at] + stray + draw(st.sampled_from([b"", encoded[at:]]))
    elif kind == "tab":  # an editor's slip: a tab after one key's colon, or before a key
        spots = [i for i in range(len(encoded)) if encoded[i : i + 2] in (b": ", b"\n ")]
        if spots:
            at = draw(st.sampled_from(spots))
            encoded = encoded[: at + 1] + b"\t" + encoded[at + 2 :]
    return encoded, named


@contextmanager
def _time_limit(seconds: int) -> Iterator[None]:
    """Fail instead of hanging: an alarm raises in the main thread after `seconds`."""

    def expire(signum, frame):
        raise TimeoutError(f"no answer within {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _assert_clean_error(err: str, path: Path, named: str | None) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err[:2000]
    line = lines[0]
    assert line.startswith(f"error: {path}: "), line[:500]
    assert len(line) < MAX_ERROR_LINE, line
    key = line.removeprefix(f"error: {path}: ").split(": ", 1)[0]
    assert KEY_PATH.fullmatch(key), line
    if named is not None:  # the error names the broken value's key or one of its parents
        assert named == key or named.startswith((key + ".", key + "[")), (named, line)


class _RUNS:
    """How many accepted examples have simulated so far in this session."""

    count = 0


@FUZZ_SETTINGS
@given(case=mutated_scenarios())
def test_mutated_scenario_is_accepted_and_runs_or_gets_one_clean_error(case, tmp_path, capsys):
    text, named = case
    path = tmp_path / "mutated.yaml"
    path.write_bytes(text)
    capsys.readouterr()
    with _time_limit(EXAMPLE_TIME_LIMIT_S):
        status = main(["validate", str(path)])
    out, err = capsys.readouterr()
    assert status in (0, 2), err[:2000]
    event(f"validate exit {status}")  # pytest --hypothesis-show-statistics counts these
    if status == 2:
        assert out == ""
        _assert_clean_error(err, path, named)
        return
    assert out.startswith(f"ok: {path}")
    if _RUNS.count >= MAX_RUNS:
        return
    _RUNS.count += 1
    replay = tmp_path / "mutated.html"
    with _time_limit(EXAMPLE_TIME_LIMIT_S):
        status = main(["run", str(path), "--duration", "0.05", "--html", str(replay)])
    assert status == 0, capsys.readouterr().err[-2000:]
    assert replay.is_file()
    event("simulated")


@FUZZ_SETTINGS
@given(text=st.lists(YAML_PIECES, max_size=40).map("".join))
def test_arbitrary_text_is_a_scenario_or_one_scenario_error(text, tmp_path):
    """Cheaper than the above (no world is built), so it tries odder syntax."""
    path = tmp_path / "arbitrary.yaml"
    path.write_text(text)
    try:
        load_scenario(path)
    except ScenarioError as error:
        assert "\n" not in str(error) and len(str(error)) < MAX_ERROR_LINE, str(error)
