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


class SchemaMismatch(ValueError):
    """Raw data does not fit the schema at `key_path`; the message says what was expected."""

    def __init__(self, key_path: str, expected: str):
        super().__init__(f"{key_path}: {expected}")
        self.key_path = key_path
        self.expected = expected


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
        _check_dict(data, typing.get_args(schema)[1], path)
    else:
        _check_scalar(data, schema, path)


def _where(path: str) -> str:
    return path or "(top level)"


def _check_optional(data: Any, schema: type, path: str) -> None:
    inner = [arg for arg in typing.get_args(schema) if arg is not type(None)]
    if data is not None:
        check_against_schema(data, inner[0], path)


def _check_dataclass(data: Any, schema: type, path: str) -> None:
    if not isinstance(data, dict):
        raise SchemaMismatch(_where(path), f"expected a mapping of {schema.__name__} fields")
    hints = typing.get_type_hints(schema)
    for key, value in data.items():
        key_path = f"{path}.{key}" if path else str(key)
        if key not in hints:
            known = ", ".join(hints)
            raise SchemaMismatch(key_path, f"unknown key; expected one of: {known}")
        check_against_schema(value, hints[key], key_path)


def _check_list(data: Any, item_type: type, path: str) -> None:
    if not isinstance(data, list):
        raise SchemaMismatch(_where(path), f"expected a list, got {_describe(data)}")
    for index, item in enumerate(data):
        check_against_schema(item, item_type, f"{path}[{index}]")


def _check_dict(data: Any, value_type: type, path: str) -> None:
    if not isinstance(data, dict):
        raise SchemaMismatch(_where(path), f"expected a mapping, got {_describe(data)}")
    for key, value in data.items():
        check_against_schema(value, value_type, f"{path}.{key}")


def _check_scalar(data: Any, schema: type, path: str) -> None:
    if schema is float:
        ok = isinstance(data, int | float) and not isinstance(data, bool)
    elif schema is int:
        ok = isinstance(data, int) and not isinstance(data, bool)
    else:
        ok = isinstance(data, schema)
    if not ok:
        raise SchemaMismatch(_where(path), f"expected {schema.__name__}, got {_describe(data)}")


def _describe(data: Any) -> str:
    if isinstance(data, dict | list):
        return type(data).__name__
    return f"{type(data).__name__} {data!r}"
