"""A strict YAML reader for scenario files: PyYAML's safe loader, plus errors with key paths.

PyYAML alone lets the last of two equal keys win silently, recurses once per nesting level (a
file nested a thousand deep ends in a RecursionError), and fails on a 5,000-digit integer with
Python's own "Exceeds the limit" message. This loader records each node's key path while
composing, so it can refuse all three with a SchemaMismatch naming where.

It also reads YAML 1.2 floats without a dot or exponent sign (`1e-3`, `2.5e8`), which YAML 1.1
would read as strings; Drake's loader turns those strings into the same numbers.

Events come from libyaml when PyYAML has it (a 100,000-item list takes 1 s instead of 10 s);
the nodes are composed here in Python, since libyaml's own composer recurses in C without limit
and crashes the interpreter on deep nesting.
"""

from __future__ import annotations

import re
from collections.abc import Hashable
from typing import Any

import yaml
from yaml.composer import Composer
from yaml.constructor import SafeConstructor
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.resolver import Resolver

from hsr_handover.scenario.typed_yaml import SchemaMismatch, child, where

MAX_ITEMS = 1000
"""The most entries a list or mapping may have; no scenario needs nearly as many, and refusing
more keeps every later step fast, even when YAML aliases repeat one list many times."""

MAX_DEPTH = 12
"""Deepest nesting of lists and mappings; the schema's deepest value sits at depth 5."""

MAX_NUMBER_CHARS = 100
"""Longest integer literal; any longer is out of every range, and Python refuses to convert
integers of more than 4,300 digits."""

_MERGE_TAG = "tag:yaml.org,2002:merge"
_FLOAT_TAG = "tag:yaml.org,2002:float"
_INT_TAG = "tag:yaml.org,2002:int"
_YAML12_FLOAT = re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)[eE][-+]?[0-9]+$")


if yaml.__with_libyaml__:
    from yaml.cyaml import CParser as _EventParser
else:  # pragma: no cover - PyYAML built without libyaml

    class _EventParser(yaml.reader.Reader, yaml.scanner.Scanner, yaml.parser.Parser):
        def __init__(self, stream: str) -> None:
            yaml.reader.Reader.__init__(self, stream)
            yaml.scanner.Scanner.__init__(self)
            yaml.parser.Parser.__init__(self)


class StrictLoader(Composer, _EventParser, SafeConstructor, Resolver):
    """A safe loader that refuses duplicate keys, deep nesting and overlong integers.

    Composer comes before the event parser so that its Python composing, not libyaml's, runs.
    """

    def __init__(self, stream: str) -> None:
        _EventParser.__init__(self, stream)
        Composer.__init__(self)
        SafeConstructor.__init__(self)
        Resolver.__init__(self)
        self._path: list[str] = []  # the key path of the node being composed, part by part
        self._key_paths: dict[int, str] = {}  # id(node) -> its key path

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        if _entries_before(parent, index) >= MAX_ITEMS:
            # Refused before the rest is read: a 100,000-item list costs no parsing time.
            raise SchemaMismatch(self._where(), f"expected at most {MAX_ITEMS} entries")
        self._path.append(_path_part(parent, index))
        try:
            if len(self._path) > MAX_DEPTH:
                raise SchemaMismatch(self._where(), f"expected at most {MAX_DEPTH} nested levels")
            node = super().compose_node(parent, index)
            # An alias keeps the key path of its anchor.
            self._key_paths.setdefault(id(node), "".join(self._path).removeprefix("."))
            return node
        finally:
            self._path.pop()

    def construct_object(self, node: Node, deep: bool = False) -> Any:
        try:
            return super().construct_object(node, deep=deep)
        except SchemaMismatch:
            raise
        except (ValueError, TypeError, AttributeError, ArithmeticError, LookupError):
            # A tag PyYAML cannot construct, such as `!!int abc` or `!!timestamp 13`.
            raise SchemaMismatch(
                where(self._node_path(node)), f"expected a valid {node.tag.split(':')[-1]}"
            ) from None

    def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict:
        seen = set()
        # `<<: *defaults` may be overridden, not a repeat; PyYAML itself reports non-mappings
        # tagged !!map and keys that are lists or mappings.
        pairs = node.value if isinstance(node, MappingNode) else []
        for key_node, _ in pairs:
            if key_node.tag == _MERGE_TAG:
                continue
            key = self.construct_object(key_node, deep=deep)
            if not isinstance(key, Hashable):
                continue
            if key in seen:
                raise SchemaMismatch(
                    child(self._node_path(node), key), "expected each key once; this one repeats"
                )
            seen.add(key)
        return super().construct_mapping(node, deep=deep)

    def construct_yaml_int(self, node: ScalarNode) -> int:
        if len(node.value) > MAX_NUMBER_CHARS:
            raise SchemaMismatch(
                where(self._node_path(node)),
                f"expected a number of at most {MAX_NUMBER_CHARS} digits, got {len(node.value)}",
            )
        return super().construct_yaml_int(node)

    def _where(self) -> str:
        return where("".join(self._path).removeprefix("."))

    def _node_path(self, node: Node) -> str:
        return self._key_paths.get(id(node), "")


def _entries_before(parent: Node | None, index: Any) -> int:
    """How many entries `parent` holds before the one being composed at `index`."""
    if isinstance(parent, SequenceNode):
        return index
    if isinstance(parent, MappingNode) and index is None:  # a key starts a new entry
        return len(parent.value)
    return 0


def _path_part(parent: Node | None, index: Any) -> str:
    """The key path step from `parent` to the child composed at `index` (PyYAML passes the key
    node for a mapping value, None for a mapping key, and the position in a sequence)."""
    if isinstance(parent, SequenceNode):
        return f"[{index}]"
    if isinstance(parent, MappingNode):
        return f".{index.value}" if isinstance(index, ScalarNode) else ".(a key)"
    return ""


StrictLoader.add_constructor(_INT_TAG, StrictLoader.construct_yaml_int)
StrictLoader.add_implicit_resolver(_FLOAT_TAG, _YAML12_FLOAT, list("-+0123456789."))


def load_yaml(text: str) -> Any:
    """Parse one YAML document. Raises yaml.YAMLError for broken YAML and SchemaMismatch, naming
    the key path, for a repeated key, nesting deeper than MAX_DEPTH or an overlong integer."""
    loader = StrictLoader(text)
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()
