"""The attention experiment (paper §4.1, figs. 9-12): the robot's focus moves from the person's
face to the hand to an object; the scene GNG follows. Measured: node count and mean node error
over time (fig. 11), node density per region at the end of each focus phase (fig. 12), the
density ratio of the attended human region to the rest, and how long the node count takes to
settle after each shift.

Node density here is nodes per square metre of observed surface: the camera's cloud is
organised (one point per pixel), so each pixel's footprint is the cross product of its steps to
the neighbouring pixels (distance and incidence included). The density ratio of a region is its
density over the rest's, within the workspace the map learns from. The attention gain of a
region is its ratio in the phase that attends to it over its ratio in the phase with no focus:
what attention itself adds.

Regions for scoring come from the simulator's ground truth; the robot attended to regions it
found in its own percepts.
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
from pydrake.systems.framework import Context, EventStatus

from hsr_handover.robot.perception.attention import (
    FACE_RADIUS,
    HAND_RADIUS,
    OBJECT_RADIUS,
    AttentionRegion,
)
from hsr_handover.robot.perception.cloud_map import GraphSnapshot, Workspace
from hsr_handover.scenario import Scenario
from hsr_handover.simulation import ProgressCallback, RunReport, Simulation, run_scenario
from hsr_handover.world.station import Station

SETTLE_BAND = 0.05  # a change smaller than 5% of the level is no step to settle
SETTLED_TAIL_S = 1.0  # the settled count is the mean over the phase's last second
RISE_FRACTION = 0.9  # settled once 90% of the step from the old level to the new is covered
SMOOTHING_S = 0.3  # the count is averaged over this window first: frame noise is not adaptation
DEPTH_JUMP = 0.05  # m: a step to a neighbouring pixel longer than this crosses an edge
HUMAN_FOCI = ("face", "hand")


@dataclasses.dataclass
class PhaseResult:
    """One focus phase: its focus, time span, node-count settle time (s after the shift; NaN
    when it never settled), per-region node density ratios over its settled end, node count, the
    attention gain of the attended region (NaN without a focus or a no-focus baseline), and
    how long the number of nodes inside the attended region took to settle (how fast the map
    follows attention)."""

    focus: str
    target: str
    start: float
    end: float
    settle_time_s: float
    density_ratios: dict[str, float]
    node_count: int
    attention_gain: float = float("nan")
    region_settle_time_s: float = float("nan")

    @property
    def attended_ratio(self) -> float:
        """The density ratio of the region attended in this phase (NaN for no focus)."""
        return self.density_ratios.get(self.target or self.focus, float("nan"))


@dataclasses.dataclass
class AttentionResult:
    times: np.ndarray
    node_count: np.ndarray
    mean_node_error: np.ndarray
    quantisation_error: np.ndarray
    phases: list[PhaseResult]
    region_nodes: np.ndarray  # nodes inside the attended (true) region, per sample; 0 unfocused

    @property
    def density_ratio(self) -> float:
        """The attended human region's density ratio: the lowest over face and hand phases."""
        ratios = [p.attended_ratio for p in self.phases if p.focus in HUMAN_FOCI]
        return min(ratios) if ratios else float("nan")

    @property
    def settle_time_s(self) -> float:
        """The slowest node-count settle after a shift of focus (NaN if one never settled)."""
        times = [p.settle_time_s for p in self.phases[1:]]
        return max(times) if times else float("nan")

    @property
    def region_settle_time_s(self) -> float:
        """The slowest settle of the attended region's node count after a shift to a focus."""
        times = [p.region_settle_time_s for p in self.phases[1:] if p.focus != "none"]
        return max(times) if times else float("nan")

    def summary(self) -> dict:
        """A JSON-ready summary (NaN still to be mapped to null by the writer)."""
        return {
            "density_ratio": self.density_ratio,
            "settle_time_s": self.settle_time_s,
            "region_settle_time_s": self.region_settle_time_s,
            "phases": [
                {**dataclasses.asdict(phase), "attended_ratio": phase.attended_ratio}
                for phase in self.phases
            ],
        }


def truth_regions(station: Station, context: Context) -> dict[str, AttentionRegion]:
    """Face, active hand and objects from the simulator's ground truth, for scoring."""
    plant = station.plant
    plant_context = plant.GetMyContextFromRoot(context)

    def frame(name: str) -> np.ndarray:
        pose = plant.GetFrameByName(f"coco_{name}", station.person).CalcPoseInWorld(plant_context)
        return pose.translation()

    face = np.mean([frame(name) for name in ("nose", "r_eye", "l_eye")], axis=0)
    # The active hand is on the more extended arm; its centre is half a hand past the wrist.
    arms = [(frame(f"{side}_shoulder"), frame(f"{side}_elbow"), frame(f"{side}_wrist"))
            for side in "rl"]  # fmt: skip
    shoulder, elbow, wrist = max(arms, key=lambda arm: np.linalg.norm(arm[2] - arm[0]))
    forearm = (wrist - elbow) / np.linalg.norm(wrist - elbow)
    hand = wrist + 0.5 * station.body.hand * forearm
    regions = {
        "face": AttentionRegion("face", face, FACE_RADIUS),
        "hand": AttentionRegion("hand", hand, HAND_RADIUS),
    }
    for obj in station.scenario.objects:
        center = plant.GetBodyByName(obj.name).EvalPoseInWorld(plant_context).translation()
        regions[obj.name] = AttentionRegion(f"object:{obj.name}", center, OBJECT_RADIUS)
    return regions


def pixel_areas(cloud: np.ndarray, width: int, height: int) -> np.ndarray:
    """Surface area (m^2) each point of an organised cloud (height * width, 3) stands for: the
    cross product of its steps to the next pixel along the row and along the column. A step
    across a depth jump is replaced by the step back to the previous pixel, so an object's
    silhouette keeps its area; a point with no continuous neighbour along an axis gets 0."""
    grid = cloud.reshape(height, width, 3)
    along_row = _continuous_step(grid, axis=1)
    along_column = _continuous_step(grid, axis=0)
    areas = np.linalg.norm(np.cross(along_row, along_column), axis=2)
    areas[~np.isfinite(areas)] = 0.0
    return areas.ravel()


def _continuous_step(grid: np.ndarray, axis: int) -> np.ndarray:
    """Per pixel, the difference to the next pixel along `axis`, or to the previous one where
    the next is missing or across a depth jump; NaN where neither is continuous."""
    difference = np.diff(grid, axis=axis)
    forward = np.full_like(grid, np.nan)
    backward = np.full_like(grid, np.nan)
    if axis == 1:
        forward[:, :-1], backward[:, 1:] = difference, difference
    else:
        forward[:-1], backward[1:] = difference, difference
    with np.errstate(invalid="ignore"):
        forward_ok = np.linalg.norm(forward, axis=2) <= DEPTH_JUMP
        backward_ok = np.linalg.norm(backward, axis=2) <= DEPTH_JUMP
    step = np.where(forward_ok[..., None], forward, backward)
    step[~(forward_ok | backward_ok)] = np.nan
    return step


def density_ratio(
    graph: GraphSnapshot, points: np.ndarray, areas: np.ndarray, region: AttentionRegion
) -> float:
    """(nodes per m^2 inside the region) / (nodes per m^2 outside), over the observed surface
    `points` with their `areas`; NaN when either side has no surface or no nodes outside."""
    nodes_in = region.contains(graph.nodes)
    points_in = region.contains(points)
    area_in, area_out = areas[points_in].sum(), areas[~points_in].sum()
    if area_in <= 0 or area_out <= 0 or nodes_in.all():
        return float("nan")
    return float((nodes_in.sum() / area_in) / ((~nodes_in).sum() / area_out))


def settle_time(times: np.ndarray, counts: np.ndarray, start: float, end: float) -> float:
    """The 90% rise time of a count after a shift at `start`: seconds until the count, averaged
    over SMOOTHING_S within the phase, has covered 90% of the way from its level just before the
    shift to its settled level (the mean of the phase's last second, or last half if shorter).
    0 when the change is within the noise (SETTLE_BAND of the level or two standard deviations
    of the settled tail); NaN when the phase is empty or the count never gets there."""
    in_phase = (times >= start) & (times < end)
    before = counts[(times >= start - SMOOTHING_S) & (times < start)]
    if not in_phase.any():
        return float("nan")
    phase_times, phase_counts = times[in_phase], _smooth(times, counts[in_phase])
    tail = phase_counts[phase_times >= end - min(SETTLED_TAIL_S, (end - start) / 2)]
    if not len(tail):  # the run ended before the phase's settled end: no level to settle to
        return float("nan")
    settled = tail.mean()
    initial = before.mean() if len(before) else phase_counts[0]
    noise = max(SETTLE_BAND * max(abs(settled), 1.0), 2.0 * tail.std())
    if abs(settled - initial) <= noise:
        return 0.0
    progress = (phase_counts - initial) / (settled - initial)
    reached = np.flatnonzero(progress >= RISE_FRACTION)
    return float(phase_times[reached[0]] - start) if len(reached) else float("nan")


def _smooth(times: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Centred moving average over SMOOTHING_S, so it does not lag; the ends average over what
    exists, and nothing from a neighbouring phase leaks in."""
    step = float(np.median(np.diff(times))) if len(times) > 1 else 1.0
    # No longer than the values: "same" returns the longer of the two (a short run's phase).
    kernel = np.ones(min(max(int(round(SMOOTHING_S / step)), 1), max(len(values), 1)))
    weights = np.convolve(np.ones_like(values), kernel, "same")
    return np.convolve(values, kernel, "same") / weights


class AttentionRecorder:
    """A simulator monitor: samples the map's stats at the camera's rate and, over the settled
    end of each focus phase (its last second, or last half if shorter), the density ratio of
    every region, averaged at the end. A region holds only a few nodes (a hand, about five), so
    one frame's ratio moves by a fifth with a single node; thirty frames steady it."""

    def __init__(self, simulation: Simulation):
        scenario = simulation.station.scenario
        self.station, self.period = simulation.station, 1.0 / scenario.camera.rate_hz
        self.robot = simulation.robot.diagram
        self.schedule = list(scenario.perception.attention)
        self.starts = [change.start for change in self.schedule]
        self.ends = [*self.starts[1:], scenario.simulation.duration]
        self.next_sample = 0.0
        self.rows: list[tuple[float, ...]] = []
        self.ratios: list[list[dict[str, float]]] = [[] for _ in self.schedule]
        self.cloud_size = tuple(scenario.perception.cloud_size)
        box = scenario.perception.workspace
        self.workspace = Workspace(tuple(box[:3]), tuple(box[3:]))

    def __call__(self, context: Context) -> EventStatus:
        time = context.get_time()
        if time + 1e-9 < self.next_sample:
            return EventStatus.Succeeded()
        self.next_sample += self.period
        phase = int(np.searchsorted(self.starts, time + 1e-9, side="right")) - 1
        regions = truth_regions(self.station, context)
        robot_context = self.robot.GetMyContextFromRoot(context)
        graph = self.robot.GetOutputPort("gng_graph").Eval(robot_context)
        stats = self.robot.GetOutputPort("gng_stats").Eval(robot_context)
        attended = 0
        if phase >= 0 and self.schedule[phase].focus != "none":
            change = self.schedule[phase]
            attended = int(regions[change.target or change.focus].contains(graph.nodes).sum())
        self.rows.append((time, *stats[:3], attended))
        if phase >= 0 and self._in_settled_tail(phase, time):
            self.ratios[phase].append(self._density_ratios(context, graph, regions))
        return EventStatus.Succeeded()

    def _in_settled_tail(self, phase: int, time: float) -> bool:
        start, end = self.starts[phase], self.ends[phase]
        return time >= end - min(SETTLED_TAIL_S, (end - start) / 2)

    def _density_ratios(self, context: Context, graph: GraphSnapshot, regions: dict) -> dict:
        robot_context = self.robot.GetMyContextFromRoot(context)
        cloud = self.robot.GetOutputPort("point_cloud").Eval(robot_context).xyzs().T
        cloud = cloud.astype(float)
        areas = pixel_areas(cloud, *self.cloud_size)
        inside = self.workspace.contains(cloud)
        return {
            name: density_ratio(graph, cloud[inside], areas[inside], region)
            for name, region in regions.items()
        }

    def result(self) -> AttentionResult:
        series = np.array(self.rows, dtype=float).reshape(-1, 5)
        times, counts, region_nodes = series[:, 0], series[:, 1], series[:, 4]
        phases = []
        for index, change in enumerate(self.schedule):
            start, end = self.starts[index], self.ends[index]
            samples = self.ratios[index]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN regions stay NaN
                ratios = {name: float(np.nanmean([r[name] for r in samples]))
                          for name in (samples[0] if samples else {})}  # fmt: skip
            tail = (times >= start) & (times < end) & (times >= end - SETTLED_TAIL_S)
            phase = PhaseResult(
                change.focus, change.target, start, end,
                settle_time(times, counts, start, end), ratios,
                int(np.median(counts[tail])) if tail.any() else 0,
                region_settle_time_s=settle_time(times, region_nodes, start, end),
            )  # fmt: skip
            phases.append(phase)
        return AttentionResult(
            times, counts, series[:, 2], series[:, 3], _with_gains(phases), region_nodes
        )


def _with_gains(phases: list[PhaseResult]) -> list[PhaseResult]:
    """Each focused phase's attention gain: its attended ratio over the same region's ratio in
    the (last) phase without focus."""
    unfocused = [p for p in phases if p.focus == "none"]
    if not unfocused:
        return phases
    baseline = unfocused[-1].density_ratios
    gained = []
    for phase in phases:
        if phase.focus != "none":
            before = baseline.get(phase.target or phase.focus, float("nan"))
            phase = dataclasses.replace(phase, attention_gain=phase.attended_ratio / before)
        gained.append(phase)
    return gained


def run_attention(
    scenario: Scenario, replay: Path | None = None, progress: ProgressCallback | None = None
) -> tuple[AttentionResult, RunReport]:
    """Simulate the scenario with perception on and measure its attention phases."""
    scenario.perception.enabled = True
    scenario.handover.enabled = False  # the robot watches; it does not act
    recorders: list[AttentionRecorder] = []

    def make_recorder(simulation: Simulation) -> AttentionRecorder:
        recorders.append(AttentionRecorder(simulation))
        return recorders[-1]

    report = run_scenario(scenario, replay, progress, monitor_factory=make_recorder)
    return recorders[0].result(), report
