"""GraphVisualizer: the robot's topological map (a GNG graph) drawn in Meshcat, live and in replays.

Each publish of a changed graph draws it as a new snapshot (`meshcat_recording.Snapshots`):
snapshot k is hidden from the recording's start, shown from its publish time and hidden again
when snapshot k + 1 appears. Live browsers see only the newest. While the map rests (the
robot's `watching` output is 0: it learns only while the robot watches for a request), it is
drawn grey, so the replay does not pass its last picture off as the scene now.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import Meshcat, Rgba
from pydrake.perception import BaseField, Fields, PointCloud
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, OutputPort

from hsr_handover.replay.meshcat_recording import Snapshots
from hsr_handover.replay.overlays import CLUSTER_PALETTE, RESTING_RGBA, SCENE_MAP
from hsr_handover.robot.perception.cloud_map import GraphSnapshot
from hsr_handover.robot.systems.watching import WATCHING, declare_watching_input, is_watching

EDGE_RGBA = Rgba(0.25, 0.25, 0.25, 1.0)  # dark grey: visible on the white table and floor
RESTING_EDGE_RGBA = Rgba(0.78, 0.78, 0.78, 1.0)  # light grey: the map at rest

# Per-point colours multiply the material colour in three.js, so the material must be white.
_VERTEX_COLOURED = Rgba(1.0, 1.0, 1.0, 1.0)


class GraphVisualizer(LeafSystem):
    """Inputs `graph` (GraphSnapshot) and optionally `watching` (1 while the map learns;
    unconnected, always); draws the graph in Meshcat every `publish_period` s and on
    ForcedPublish: nodes as points coloured by cluster, edges as line segments, all grey
    while the map rests.

    Each publish of a changed graph adds one snapshot (about 31 kB of replay HTML for 300 nodes
    and 600 edges); an unchanged graph adds nothing and an empty one hides the previous graph.
    Only the newest `max_snapshots` snapshots are kept: older ones are deleted, so a replay
    longer than `max_snapshots * publish_period` shows no graph at its start.

    Like Drake's MeshcatVisualizer, the bookkeeping of what has been drawn lives in the system,
    not in the Context: publish events cannot change the Context, and Meshcat is outside it.
    """

    def __init__(
        self,
        meshcat: Meshcat,
        path: str = SCENE_MAP.path,
        publish_period: float = 0.25,
        point_size: float = 0.015,
        line_width: float = 2.0,
        edge_rgba: Rgba = EDGE_RGBA,
        max_snapshots: int = 240,
    ):
        super().__init__()
        if publish_period <= 0:
            raise ValueError(f"publish_period: expected a positive period, got {publish_period}")
        if max_snapshots < 1:
            raise ValueError(f"max_snapshots: expected at least 1, got {max_snapshots}")
        self._meshcat = meshcat
        self._point_size, self._line_width, self._edge_rgba = point_size, line_width, edge_rgba
        self._snapshots = Snapshots(meshcat, path, max_snapshots)
        self._graph = self.DeclareAbstractInputPort(
            "graph", AbstractValue.Make(GraphSnapshot.empty())
        )
        self._watching = declare_watching_input(self)
        self.DeclareInitializationPublishEvent(self._clear)
        self.DeclarePeriodicPublishEvent(publish_period, 0.0, self._publish)
        self.DeclareForcedPublishEvent(self._publish)
        self._drawn: GraphSnapshot | None = None
        self._resting = False  # whether the snapshot shown is the resting map's

    @property
    def snapshot_paths(self) -> list[str]:
        """The Meshcat paths of the snapshots kept, oldest first."""
        return list(self._snapshots.paths)

    def _clear(self, context: Context) -> None:
        """Remove what an earlier simulation on this Meshcat drew."""
        self._snapshots.clear()
        self._drawn, self._resting = None, False

    def _publish(self, context: Context) -> None:
        graph: GraphSnapshot = self._graph.Eval(context)
        resting = not is_watching(self._watching, context)
        drawn = self._drawn
        if drawn is not None and resting == self._resting and _same_graph(graph, drawn):
            return  # the snapshot shown is still right; another copy would only grow the replay
        time = context.get_time()
        if len(graph.nodes):
            self._snapshots.show(lambda path: self._draw(path, graph, resting), time)
        else:
            self._snapshots.hide(time)
        self._drawn, self._resting = graph, resting

    def _draw(self, path: str, graph: GraphSnapshot, resting: bool) -> None:
        cloud = _node_cloud(graph, coloured=not resting)
        rgba = RESTING_RGBA if resting else _VERTEX_COLOURED
        self._meshcat.SetObject(f"{path}/nodes", cloud, self._point_size, rgba)
        if len(graph.edges):
            ends = graph.nodes[np.asarray(graph.edges, dtype=int)]  # (M, 2, 3)
            self._meshcat.SetLineSegments(
                f"{path}/edges",
                np.asfortranarray(ends[:, 0].T, dtype=float),
                np.asfortranarray(ends[:, 1].T, dtype=float),
                self._line_width,
                RESTING_EDGE_RGBA if resting else self._edge_rgba,
            )


def add_graph_visualizer(
    builder: DiagramBuilder,
    graph_output_port: OutputPort,
    meshcat: Meshcat,
    watching: OutputPort | None = None,
    **options: Any,
) -> GraphVisualizer:
    """Add a GraphVisualizer (named "graph_visualizer") fed by `graph_output_port` and, if
    given, `watching` (the robot's output of that name); `options` are GraphVisualizer's
    keyword arguments."""
    visualizer = builder.AddNamedSystem("graph_visualizer", GraphVisualizer(meshcat, **options))
    builder.Connect(graph_output_port, visualizer.GetInputPort("graph"))
    if watching is not None:
        builder.Connect(watching, visualizer.GetInputPort(WATCHING))
    return visualizer


def _node_cloud(graph: GraphSnapshot, coloured: bool = True) -> PointCloud:
    """The nodes as a cloud, each its cluster's colour (or, not `coloured`, the material's)."""
    fields = BaseField.kXYZs | BaseField.kRGBs if coloured else BaseField.kXYZs
    cloud = PointCloud(len(graph.nodes), Fields(fields))
    cloud.mutable_xyzs()[:] = graph.nodes.T
    if coloured:
        labels = np.asarray(graph.clusters, dtype=int)
        cloud.mutable_rgbs()[:] = CLUSTER_PALETTE[labels % len(CLUSTER_PALETTE)].T
    return cloud


def _same_graph(a: GraphSnapshot, b: GraphSnapshot) -> bool:
    return (
        np.array_equal(a.nodes, b.nodes)
        and np.array_equal(a.edges, b.edges)
        and np.array_equal(a.clusters, b.clusters)
    )
