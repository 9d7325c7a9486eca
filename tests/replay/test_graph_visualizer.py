"""GraphVisualizer: the GNG graph in Meshcat, live (newest snapshot only) and in the replay,
grey while the map rests."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pydrake.common.value import AbstractValue
from pydrake.geometry import Meshcat
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem

from hsr_handover.replay.graph_visualizer import GraphVisualizer, add_graph_visualizer
from hsr_handover.replay.meshcat_replay import make_local_meshcat, start_recording
from hsr_handover.replay.overlays import RESTING_RGBA, SCENE_MAP
from hsr_handover.robot.perception.cloud_map import GraphSnapshot
from tests.meshcat_html import hidden_paths, meshcat_commands, replay_commands, visibility_keys

PATH = SCENE_MAP.path
FPS = 20.0


def random_graph(seed: int, n_nodes: int = 30, n_edges: int = 60) -> GraphSnapshot:
    """A graph that differs from seed to seed, with up to 12 clusters."""
    generator = np.random.default_rng(seed)
    nodes = generator.random((n_nodes, 3))
    edges = generator.integers(0, n_nodes, (n_edges, 2))
    return GraphSnapshot(nodes, edges, generator.integers(0, 12, n_nodes), 0.0)


@pytest.fixture
def meshcat() -> Meshcat:
    return make_local_meshcat()  # a fresh one: a published recording would leak between tests


def publish(
    visualizer: GraphVisualizer,
    context: Context,
    graph: GraphSnapshot,
    time: float,
    watching: bool | None = None,
) -> None:
    """Publish `graph` as if it arrived at `time` (with the robot watching or not, if said)."""
    context.SetTime(time)
    visualizer.GetInputPort("graph").FixValue(context, graph)
    if watching is not None:
        visualizer.GetInputPort("watching").FixValue(context, [float(watching)])
    visualizer.ForcedPublish(context)


def test_publish_draws_nodes_and_edges(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    publish(visualizer, visualizer.CreateDefaultContext(), random_graph(0), 0.0)
    assert visualizer.snapshot_paths == [f"{PATH}/0000"]
    assert meshcat.HasPath(f"{PATH}/0000/nodes")
    assert meshcat.HasPath(f"{PATH}/0000/edges")


def test_nodes_are_coloured_by_cluster(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    graph = GraphSnapshot(np.eye(3), np.array([[0, 1]]), np.array([0, 0, 1]), 0.0)
    publish(visualizer, visualizer.CreateDefaultContext(), graph, 0.0)
    (nodes,) = [
        c for c in meshcat_commands(meshcat.StaticHtml()) if c.get("path") == f"{PATH}/0000/nodes"
    ]
    attributes = nodes["object"]["geometries"][0]["data"]["attributes"]
    colours = np.frombuffer(attributes["color"]["array"][1], dtype="<f4").reshape(-1, 3)
    assert np.array_equal(colours[0], colours[1])  # same cluster
    assert not np.array_equal(colours[0], colours[2])


def test_empty_graph_draws_nothing(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    publish(visualizer, visualizer.CreateDefaultContext(), GraphSnapshot.empty(), 0.0)
    assert visualizer.snapshot_paths == []
    assert not meshcat.HasPath(PATH)


def test_graph_without_edges_draws_nodes_only(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    graph = GraphSnapshot(np.zeros((2, 3)), np.zeros((0, 2), dtype=int), np.zeros(2, int), 0.0)
    publish(visualizer, visualizer.CreateDefaultContext(), graph, 0.0)
    assert meshcat.HasPath(f"{PATH}/0000/nodes")
    assert not meshcat.HasPath(f"{PATH}/0000/edges")


def test_live_scene_shows_only_the_newest_snapshot(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    for k in range(3):
        publish(visualizer, context, random_graph(k), 0.25 * k)
    hidden = hidden_paths(meshcat_commands(meshcat.StaticHtml()))
    assert hidden == {f"{PATH}/0000", f"{PATH}/0001"}


def test_empty_graph_hides_the_previous_one(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    publish(visualizer, context, random_graph(0), 0.0)
    publish(visualizer, context, GraphSnapshot.empty(), 0.25)
    assert visualizer.snapshot_paths == [f"{PATH}/0000"]
    assert hidden_paths(meshcat_commands(meshcat.StaticHtml())) == {f"{PATH}/0000"}


def test_unchanged_graph_adds_no_snapshot(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    publish(visualizer, context, random_graph(0), 0.0)
    publish(visualizer, context, random_graph(0), 0.25)
    assert visualizer.snapshot_paths == [f"{PATH}/0000"]


def test_oldest_snapshots_are_deleted_beyond_the_limit(meshcat):
    visualizer = GraphVisualizer(meshcat, PATH, max_snapshots=2)
    context = visualizer.CreateDefaultContext()
    for k in range(3):
        publish(visualizer, context, random_graph(k), 0.25 * k)
    assert visualizer.snapshot_paths == [f"{PATH}/0001", f"{PATH}/0002"]
    assert not meshcat.HasPath(f"{PATH}/0000")


@pytest.mark.parametrize(
    "option", [{"publish_period": 0.0}, {"max_snapshots": 0}], ids=["period", "limit"]
)
def test_rejects_bad_options(meshcat, option):
    with pytest.raises(ValueError, match=next(iter(option))):
        GraphVisualizer(meshcat, **option)


def test_replay_animates_snapshot_visibility(meshcat, tmp_path: Path):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    start_recording(meshcat, FPS)
    times = [0.0, 0.25, 0.5]
    for k, time in enumerate(times):
        publish(visualizer, context, random_graph(k), time)
    commands = replay_commands(meshcat, tmp_path)
    paths = [f"{PATH}/{k:04d}" for k in range(3)]
    drawn = {c["path"] for c in commands if c["type"] == "set_object"}
    assert {f"{p}/{part}" for p in paths for part in ("nodes", "edges")} <= drawn
    assert hidden_paths(commands) == {paths[0], paths[1]}  # the scene the replay starts from
    keys = visibility_keys(commands)
    assert keys[paths[0]] == [(0.0, True), (0.25, False)]
    assert keys[paths[1]] == [(0.0, False), (0.25, True), (0.5, False)]
    assert keys[paths[2]] == [(0.0, False), (0.5, True)]


def test_replay_starting_late_keeps_keyframes_after_its_start(meshcat, tmp_path: Path):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    start_recording(meshcat, FPS)
    meshcat.get_mutable_recording().set_start_time(1.0)
    publish(visualizer, context, random_graph(0), 0.5)  # before the start: live only
    publish(visualizer, context, random_graph(1), 1.5)
    commands = replay_commands(meshcat, tmp_path)
    keys = visibility_keys(commands)
    assert set(keys) == {f"{PATH}/0000", f"{PATH}/0001"}
    assert keys[f"{PATH}/0001"][-1] == (0.5, True)  # 1.5 s, counted from the start at 1 s


class _GraphEverySecond(LeafSystem):
    """A different graph in each simulated second, as a stand-in for the learner."""

    def __init__(self):
        super().__init__()
        self.DeclareAbstractOutputPort(
            "graph", lambda: AbstractValue.Make(GraphSnapshot.empty()), self._calc_graph
        )

    def _calc_graph(self, context: Context, output: AbstractValue) -> None:
        output.set_value(random_graph(int(context.get_time())))


def test_simulation_publishes_periodically(meshcat, tmp_path: Path):
    builder = DiagramBuilder()
    source = builder.AddSystem(_GraphEverySecond())
    visualizer = add_graph_visualizer(builder, source.get_output_port(), meshcat, path=PATH)
    simulator = Simulator(builder.Build())
    start_recording(meshcat, FPS)
    simulator.AdvanceTo(2.0)
    # Publishes at 0, 0.25, ..., 2.0; the graph changes at 1 s and 2 s.
    assert visualizer.snapshot_paths == [f"{PATH}/{k:04d}" for k in range(3)]
    commands = replay_commands(meshcat, tmp_path)
    assert visibility_keys(commands)[f"{PATH}/0001"] == [(0.0, False), (1.0, True), (2.0, False)]


def test_new_simulation_removes_the_previous_runs_graph(meshcat):
    builder = DiagramBuilder()
    source = builder.AddSystem(_GraphEverySecond())
    visualizer = add_graph_visualizer(builder, source.get_output_port(), meshcat, path=PATH)
    diagram = builder.Build()
    Simulator(diagram).AdvanceTo(1.0)
    Simulator(diagram).AdvanceTo(0.5)
    assert visualizer.snapshot_paths == [f"{PATH}/0002"]  # numbering goes on: paths stay unique
    assert not meshcat.HasPath(f"{PATH}/0000")


def _material_and_colours(commands: list[dict], path: str) -> tuple[int, bool]:
    """A drawn cloud's material colour (0xRRGGBB) and whether it has per-point colours."""
    (nodes,) = [c for c in commands if c.get("path") == path and c["type"] == "set_object"]
    attributes = nodes["object"]["geometries"][0]["data"]["attributes"]
    return nodes["object"]["materials"][0]["color"], "color" in attributes


def test_the_map_at_rest_is_drawn_grey_from_when_it_rests(meshcat, tmp_path: Path):
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    start_recording(meshcat, FPS)
    graph = random_graph(0)
    publish(visualizer, context, graph, 0.0, watching=True)
    publish(visualizer, context, graph, 0.5, watching=False)
    publish(visualizer, context, graph, 1.0, watching=False)  # still resting: nothing new
    assert visualizer.snapshot_paths == [f"{PATH}/0000", f"{PATH}/0001"]
    commands = replay_commands(meshcat, tmp_path)
    keys = visibility_keys(commands)
    assert keys[f"{PATH}/0000"] == [(0.0, True), (0.5, False)]
    assert keys[f"{PATH}/0001"] == [(0.0, False), (0.5, True)]
    grey = int(round(RESTING_RGBA.r() * 255)) * 0x010101
    assert _material_and_colours(commands, f"{PATH}/0000/nodes") == (0xFFFFFF, True)
    assert _material_and_colours(commands, f"{PATH}/0001/nodes") == (grey, False)


def test_the_map_is_never_animated_on_its_overlay_path(meshcat, tmp_path: Path):
    """The user's tick on the overlay's own path holds: only its snapshots are animated."""
    visualizer = GraphVisualizer(meshcat, PATH)
    context = visualizer.CreateDefaultContext()
    start_recording(meshcat, FPS)
    for k, watching in enumerate((True, True, False)):
        publish(visualizer, context, random_graph(k), 0.25 * k, watching=watching)
    commands = replay_commands(meshcat, tmp_path)
    assert all(path.startswith(f"{PATH}/") for path in visibility_keys(commands))
    assert PATH not in hidden_paths(commands)
