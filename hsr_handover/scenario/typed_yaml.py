"""Check raw YAML data against a dataclass schema and name the key path of the first mismatch.

Drake's `yaml_load_typed` is the loader; its errors name a field but not where it sits ("The
fields ['bogus'] were unknown"). A researcher with a 60-line scenario wants `objects[2].size`.
This walker runs first and reports unknown keys and wrong types with their full path.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from typing import Any

MAX_ECHO = 32
"""The most characters of a value an error message repeats."""

YAML_KEY = "yaml_key"
"""Field metadata: `field(metadata={YAML_KEY: False})` keeps a dataclass field out of YAML."""


class SchemaMismatch(ValueError):
    """Raw data does not fit the schema at `key_path`; the message says what was expected."""

    def __init__(self, key_path: str, expected: str):
        super().__init__(f"{key_path}: {expected}")
        self.key_path = key_path
        self.expected = expected


def shorten(text: str, limit: int) -> str:
    """`text`, cut to at most `limit` characters with a marker where it was cut."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def describe(value: Any) -> str:
    """A short description of a value for an error message: short values as written, long
    ones by their size, so no message echoes a 100,000-item list or a page-long string."""
    if isinstance(value, list | tuple | dict):
        # Only short flat containers are written out: YAML aliases can nest one list in itself
        # many times over, and repr() would then take exponential time.
        items = value.values() if isinstance(value, dict) else value
        flat = len(value) <= 4 and all(isinstance(item, int | float | str) for item in items)
        if not (flat and len(repr(value)) <= MAX_ECHO):
            return _count(value)
    if isinstance(value, str) and len(value) > MAX_ECHO:
        return f"{shorten(repr(value), MAX_ECHO)} ({len(value)} characters)"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**MAX_ECHO:
        return f"an integer of {len(str(abs(value)))} digits"
    return repr(value)


def check_against_schema(data: Any, schema: type, path: str = "") -> None:
    """Raise SchemaMismatch at the first place `data` does not fit `schema`."""
    origin = typing.get_origin(schema)
    if origin in (typing.Union, types.UnionType):
        _check_optional(data, schema, path)
    elif dataclasses.is_dataclass(schema):
        _check_dataclass(data, schema, path)
    elif origin is list:
        _check_list(data, typing.get_args(schema)[0], path)
    elif origin is dict:
        _check_dict(data, *typing.get_args(schema), path)
    else:
        _check_scalar(data, schema, path)


def where(path: str) -> str:
    """The key path as error messages show it ("(top level)" for the document itself)."""
    return path or "(top level)"


def child(path: str, key: Any) -> str:
    """The key path of `key` inside the mapping at `path`."""
    return f"{path}.{key}" if path else str(key)


def _check_optional(data: Any, schema: type, path: str) -> None:
    inner = [arg for arg in typing.get_args(schema) if arg is not type(None)]
    if data is not None:
        check_against_schema(data, inner[0], path)


def _check_dataclass(data: Any, schema: type, path: str) -> None:
    if not isinstance(data, dict):
        expected = f"expected a mapping of {schema.__name__} fields, got {_kind(data)}"
        raise SchemaMismatch(where(path), expected)
    hints = _yaml_fields(schema)
    for key, value in data.items():
        key_path = child(path, key)
        if key not in hints:
            known = ", ".join(hints)
            raise SchemaMismatch(key_path, f"unknown key; expected one of: {known}")
        check_against_schema(value, hints[key], key_path)


def _yaml_fields(schema: type) -> dict[str, type]:
    """The fields a YAML mapping may set, by name, with their types."""
    hints = typing.get_type_hints(schema)
    fields = dataclasses.fields(schema)
    return {f.name: hints[f.name] for f in fields if f.metadata.get(YAML_KEY, True)}


def _check_list(data: Any, item_type: type, path: str) -> None:
    if not isinstance(data, list):
        raise SchemaMismatch(where(path), f"expected a list, got {_kind(data)}")
    for index, item in enumerate(data):
        check_against_schema(item, item_type, f"{path}[{index}]")


def _check_dict(data: Any, key_type: type, value_type: type, path: str) -> None:
    if not isinstance(data, dict):
        raise SchemaMismatch(where(path), f"expected a mapping, got {_kind(data)}")
    for key, value in data.items():
        key_path = child(path, key)
        if not isinstance(key, key_type):
            raise SchemaMismatch(key_path, f"expected a {key_type.__name__} key, got {_kind(key)}")
        check_against_schema(value, value_type, key_path)


def _check_scalar(data: Any, schema: type, path: str) -> None:
    if schema is float:
        ok = isinstance(data, int | float) and not isinstance(data, bool)
    elif schema is int:
        ok = isinstance(data, int) and not isinstance(data, bool)
    else:
        ok = isinstance(data, schema)
    if not ok:
        raise SchemaMismatch(where(path), f"expected {schema.__name__}, got {_kind(data)}")


def _kind(data: Any) -> str:
    """What a value is, for a type mismatch: the type, and the value when it is short."""
    if data is None:
        return "null"
    if isinstance(data, list | dict):
        return _count(data)
    return f"{type(data).__name__} {describe(data)}"


def _count(container: list | tuple | dict) -> str:
    noun = ("key", "keys") if isinstance(container, dict) else ("item", "items")
    kind = "a mapping" if isinstance(container, dict) else "a list"
    return f"{kind} of {len(container)} {noun[len(container) != 1]}"
