"""Type-checking the connections of abstract ports that carry Python objects.

Drake checks a connection by the C++ type of the value it carries, and to C++ every Python
object is one type (`Value[object]`), so a skeleton's port joined to a detections' port builds
and fails only when the value is used. Each abstract input port is declared with a model value
of the type it takes; `check_abstract_connections` compares that type with what the output port
it is connected to allocates, in the diagram and every diagram inside it.
"""

from __future__ import annotations

from pydrake.systems.framework import Diagram, InputPort, OutputPort, PortDataType


def _model_type(port: InputPort | OutputPort) -> type:
    return type(port.Allocate().get_value())


def _describe(port: InputPort | OutputPort) -> str:
    return f"'{port.get_name()}' of '{port.get_system().get_name()}'"


def check_abstract_connections(diagram: Diagram) -> None:
    """Raise TypeError naming both ports if a connection's input takes another Python type than
    its output gives (a subclass is taken), or if an input's model value is a bare `object`."""
    for (system_in, index_in), (system_out, index_out) in diagram.connection_map().items():
        port_in = system_in.get_input_port(index_in)
        if port_in.get_data_type() != PortDataType.kAbstractValued:
            continue
        port_out = system_out.get_output_port(index_out)
        taken, given = _model_type(port_in), _model_type(port_out)
        if taken is object:
            raise TypeError(
                f"input {_describe(port_in)} is declared untyped: declare it with a model value "
                "of the type it takes"
            )
        if not issubclass(given, taken):
            raise TypeError(
                f"input {_describe(port_in)} takes {taken.__name__} but is connected to output "
                f"{_describe(port_out)}, which gives {given.__name__}"
            )
    for system in diagram.GetSystems():
        if isinstance(system, Diagram):
            check_abstract_connections(system)
