"""GraphVisualizer: the robot's topological map (a GNG graph) drawn in Meshcat, live and in replays.

Each publish of a changed graph draws it as a new snapshot (`meshcat_recording.Snapshots`):
snapshot k is hidden from the recording's start, shown from its publish time and hidden again
when snapshot k + 1 appears. Live browsers see only the newest.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import Meshcat, Rgba
from pydrake.perception import BaseField, Fields, PointCloud
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, OutputPort

from hsr_handover.replay.meshcat_recording import Snapshots
from hsr_handover.robot.perception.cloud_map import GraphSnapshot

# Cluster colours (matplotlib's tab10), cycled over cluster labels.
CLUSTER_PALETTE = np.array(
    [
        [31, 119, 180], [255, 127, 14], [44, 160, 44], [214, 39, 40], [148, 103, 189],
        [140, 86, 75], [227, 119, 194], [127, 127, 127], [188, 189, 34], [23, 190, 207],
    ],
    dtype=np.uint8,
)  # fmt: skip

EDGE_RGBA = Rgba(0.25, 0.25, 0.25, 1.0)  # dark grey: visible on the white table and floor

# Per-point colours multiply the material colour in three.js, so the material must be white.
_VERTEX_COLOURED = Rgba(1.0, 1.0, 1.0, 1.0)


class GraphVisualizer(LeafSystem):
    """Input `graph` (GraphSnapshot); draws it in Meshcat every `publish_period` s and on
    ForcedPublish: nodes as points coloured by cluster, edges as line segments.

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
        path: str = "/perception/gng",
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
        self.DeclareInitializationPublishEvent(self._clear)
        self.DeclarePeriodicPublishEvent(publish_period, 0.0, self._publish)
        self.DeclareForcedPublishEvent(self._publish)
        self._drawn: GraphSnapshot | None = None

    @property
    def snapshot_paths(self) -> list[str]:
        """The Meshcat paths of the snapshots kept, oldest first."""
        return list(self._snapshots.paths)

    def _clear(self, context: Context) -> None:
        """Remove what an earlier simulation on this Meshcat drew."""
        self._snapshots.clear()
        self._drawn = None

    def _publish(self, context: Context) -> None:
        graph: GraphSnapshot = self._graph.Eval(context)
        if self._drawn is not None and _same_graph(graph, self._drawn):
            return  # the snapshot shown is still right; another copy would only grow the replay
        time = context.get_time()
        if len(graph.nodes):
            self._snapshots.show(lambda path: self._draw(path, graph), time)
        else:
            self._snapshots.hide(time)
        self._drawn = graph

    def _draw(self, path: str, graph: GraphSnapshot) -> None:
        self._meshcat.SetObject(
            f"{path}/nodes", _node_cloud(graph), self._point_size, _VERTEX_COLOURED
        )
        if len(graph.edges):
            ends = graph.nodes[np.asarray(graph.edges, dtype=int)]  # (M, 2, 3)
            self._meshcat.SetLineSegments(
                f"{path}/edges",
                np.asfortranarray(ends[:, 0].T, dtype=float),
                np.asfortranarray(ends[:, 1].T, dtype=float),
                self._line_width,
                self._edge_rgba,
            )


def add_graph_visualizer(
    builder: DiagramBuilder,
    graph_output_port: OutputPort,
    meshcat: Meshcat,
    **options: Any,
) -> GraphVisualizer:
    """Add a GraphVisualizer (named "graph_visualizer") fed by `graph_output_port`; `options`
    are GraphVisualizer's keyword arguments."""
    visualizer = builder.AddNamedSystem("graph_visualizer", GraphVisualizer(meshcat, **options))
    builder.Connect(graph_output_port, visualizer.get_input_port())
    return visualizer


def _node_cloud(graph: GraphSnapshot) -> PointCloud:
    cloud = PointCloud(len(graph.nodes), Fields(BaseField.kXYZs | BaseField.kRGBs))
    cloud.mutable_xyzs()[:] = graph.nodes.T
    labels = np.asarray(graph.clusters, dtype=int)
    cloud.mutable_rgbs()[:] = CLUSTER_PALETTE[labels % len(CLUSTER_PALETTE)].T
    return cloud


def _same_graph(a: GraphSnapshot, b: GraphSnapshot) -> bool:
    return (
        np.array_equal(a.nodes, b.nodes)
        and np.array_equal(a.edges, b.edges)
        and np.array_equal(a.clusters, b.clusters)
    )
