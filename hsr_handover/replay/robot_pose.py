"""A second, static HSR drawn in Meshcat at a configuration: where a plan puts the robot, beside
the recorded robot that stays where it stood."""

from __future__ import annotations

import numpy as np
from pydrake.geometry import Meshcat, Rgba, Role
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.systems.framework import DiagramBuilder

from hsr_handover.hsr import add_hsr


def draw_robot(meshcat: Meshcat, path: str, q: np.ndarray, rgba: Rgba) -> list[str]:
    """The HSR's illustration geometry at positions `q` (the order of a plant holding only the
    HSR, as the planning scene's), drawn under `path` in one colour and placed live (no
    recorded keyframes: it stands there throughout a replay). Returns the paths drawn."""
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, 0.0)
    add_hsr(plant, Parser(plant))
    plant.Finalize()
    q = np.asarray(q, dtype=float)
    if q.shape != (plant.num_positions(),):
        raise ValueError(f"q: expected {plant.num_positions()} HSR positions, got {q.shape}")
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant.SetPositions(plant.GetMyMutableContextFromRoot(context), q)
    query = scene_graph.get_query_output_port().Eval(scene_graph.GetMyContextFromRoot(context))
    inspector = query.inspector()
    paths = []
    for geometry in inspector.GetAllGeometryIds(Role.kIllustration):
        name = inspector.GetName(geometry).split("::")[-1]
        paths.append(f"{path}/{name}_{len(paths)}")
        meshcat.SetObject(paths[-1], inspector.GetShape(geometry), rgba)
        meshcat.SetTransform(paths[-1], query.GetPoseInWorld(geometry))
    return paths
