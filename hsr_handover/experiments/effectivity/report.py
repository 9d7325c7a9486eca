"""Write the effectivity figures: the paper's fig. 8 (the arm's map) and fig. 14 (the scene,
the person's range and the mutual area in red), and the JSON summary."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display on a robot's or CI's machine
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from hsr_handover.experiments.effectivity.figures import EffectivityResult  # noqa: E402
from hsr_handover.experiments.reporting import save_figure  # noqa: E402
from hsr_handover.experiments.reporting import write_json as write_summary  # noqa: E402

PAPER_ARM_NODES = 108
THIN_AXIS_M = 0.4  # m: an axis shorter than this, drawn at equal scale, takes two ticks


def summary_lines(result: EffectivityResult) -> list[str]:
    summary = result.summary()
    errors = summary["palm_error_median_m"]
    arm = summary["person_arm"]
    lines = [
        f"arm map: {summary['arm_nodes']} nodes (paper: {PAPER_ARM_NODES}); eq. 11 palm error "
        f"median {errors['nodes'] * 100:.1f} cm at the nodes, "
        f"{errors['random_targets'] * 100:.1f} cm at random targets",
        f"scene map: {summary['scene_nodes']} nodes",
    ]
    if arm is not None:
        lines.append(
            f"person's {arm['side']} arm (perceived): upper {arm['upper_m']:.2f} m, forearm "
            f"{arm['forearm_m']:.2f} m, hand {arm['hand_m']:.2f} m; {arm['nodes']} nodes"
        )
    point, mutual = summary["handover_point"], summary["mutual_nodes"]
    lines.append(
        f"mutual area: {'n/a' if mutual is None else mutual} robot nodes; handover point "
        + ("n/a" if point is None else "(" + ", ".join(f"{v:.2f}" for v in point) + ") m")
        + f"; {result.status}"
    )
    return lines


def write_json(result: EffectivityResult, path: Path) -> None:
    write_summary(result.summary(), path)


def _edges(axes, nodes: np.ndarray, edges: np.ndarray, color: str) -> None:
    for a, b in edges:
        axes.plot(*nodes[[a, b]].T, color=color, linewidth=0.4, alpha=0.5)


def plot(result: EffectivityResult, path: Path) -> None:
    """Left, fig. 8: the arm's map with its edges, in the robot's base frame. Right, fig. 14, in
    the world frame: the perceived scene's map (grey), the person's range (blue), the robot's
    map at its handover base (green), the mutual area (red), the rule's ideal point (x) and the
    handover point (star)."""
    figure = plt.figure(figsize=(13, 6.2))
    arm = figure.add_subplot(1, 2, 1, projection="3d")
    _edges(arm, result.arm_nodes, result.arm_edges, "tab:green")
    arm.scatter(*result.arm_nodes.T, s=6, color="tab:green")
    arm.set_title(f"fig. 8: the arm's effectivity, {len(result.arm_nodes)} nodes (paper "
                  f"{PAPER_ARM_NODES})\neq. 11 palm error median "
                  f"{result.palm_error_nodes_m * 100:.1f} cm at nodes, "
                  f"{result.palm_error_random_m * 100:.1f} cm at random targets",
                  fontsize="medium")  # fmt: skip
    scene = figure.add_subplot(1, 2, 2, projection="3d")
    _scene(scene, result)
    for axes, frame in ((arm, "robot base frame"), (scene, "world frame")):
        _axes_in_metres(axes, frame)
    figure.subplots_adjust(left=0.02, right=0.95, wspace=0.15)
    save_figure(figure, path)


def _scene(scene, result: EffectivityResult) -> None:
    if len(result.scene_nodes):
        scene.scatter(*result.scene_nodes.T, s=2, color="0.55", label="scene map (GNG)")
    if result.person is not None:
        scene.scatter(*result.person.nodes.T, s=6, color="tab:blue", alpha=0.45,
                      label="person's range")  # fmt: skip
    handover = result.handover
    if handover is not None and handover.robot_nodes is not None:
        outside = handover.robot_nodes[~handover.mutual]
        scene.scatter(*outside.T, s=8, color="tab:green", alpha=0.6, label="robot's range")
        scene.scatter(*handover.robot_nodes[handover.mutual].T, s=14, color="red",
                      label="mutual area")  # fmt: skip
    if handover is not None:
        scene.scatter(*handover.ideal, marker="x", s=60, color="black", label="ideal point")
        if handover.point is not None:
            scene.scatter(*handover.point, marker="*", s=160, color="gold", edgecolor="black",
                          label="handover point")  # fmt: skip
    ok = handover is not None and handover.point is not None
    title = "fig. 14: scene, person's range and mutual area"
    scene.set_title(title if ok else f"{title}\nno handover point: {result.status}",
                    fontsize="medium")  # fmt: skip
    scene.legend(loc="upper left", fontsize="small", markerscale=1.5)


def _axes_in_metres(axes, frame: str) -> None:
    """Equal scales, at most four ticks an axis and two on a thin one (their labels would run
    together), each axis labelled with its unit and the frame named."""
    axes.set_aspect("equal")
    for axis, limits in zip(
        (axes.xaxis, axes.yaxis, axes.zaxis),
        (axes.get_xlim(), axes.get_ylim(), axes.get_zlim()),
        strict=True,
    ):
        thin = limits[1] - limits[0] < THIN_AXIS_M
        axis.set_major_locator(MaxNLocator(2 if thin else 4))
    axes.set_xlabel("x (m)", labelpad=8)
    axes.set_ylabel("y (m)", labelpad=8)
    axes.set_zlabel("z (m)", labelpad=8)
    axes.text2D(0.02, 0.02, frame, transform=axes.transAxes, fontsize="small")
