"""Abstract ports carrying Python objects are type-checked when the diagram is built."""

from __future__ import annotations

import pytest
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Diagram, DiagramBuilder, LeafSystem

from hsr_handover.robot.perception.object_detection import DetectionResult
from hsr_handover.robot.perception.skeleton import Skeleton
from hsr_handover.systems.port_types import check_abstract_connections


class _Base:
    pass


class _Special(_Base):
    pass


class _Source(LeafSystem):
    def __init__(self, model: object):
        super().__init__()
        self.DeclareAbstractOutputPort(
            "out", lambda: AbstractValue.Make(model), lambda context, output: None
        )


class _Sink(LeafSystem):
    def __init__(self, model: object):
        super().__init__()
        self.DeclareAbstractInputPort("in", AbstractValue.Make(model))


def _joined(given: object, taken: object) -> Diagram:
    builder = DiagramBuilder()
    source = builder.AddNamedSystem("source", _Source(given))
    sink = builder.AddNamedSystem("sink", _Sink(taken))
    builder.Connect(source.get_output_port(), sink.get_input_port())
    return builder.Build()


def test_a_port_joined_to_another_type_is_refused_naming_both_ends():
    diagram = _joined(DetectionResult((), "none"), Skeleton.missing("none"))
    with pytest.raises(TypeError, match="'in' of 'sink' takes Skeleton .* 'out' of 'source'"):
        check_abstract_connections(diagram)


def test_the_same_type_or_a_subclass_is_taken():
    check_abstract_connections(_joined(Skeleton.missing("a"), Skeleton.missing("b")))
    check_abstract_connections(_joined(_Special(), _Base()))


def test_an_untyped_input_is_refused():
    with pytest.raises(TypeError, match="'in' of 'sink' is declared untyped"):
        check_abstract_connections(_joined(Skeleton.missing("a"), object()))


def test_a_diagram_inside_the_diagram_is_checked():
    builder = DiagramBuilder()
    builder.AddSystem(_joined(_Base(), _Special()))
    with pytest.raises(TypeError, match="takes _Special .* gives _Base"):
        check_abstract_connections(builder.Build())
