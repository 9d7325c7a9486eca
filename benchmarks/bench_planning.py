"""Planning from percepts: grasp plans for the table's objects, and handover
plans into the mutual area from the first grasps (holding the object), in the bundled scenes and
in copies with the table, its objects and the person moved, each target planned twice
in the same run: seeded by the arm's effectivity map (base placement and IK seeds, eq. 11) and
unseeded (the base at a fixed reach, IK from the arm as it is). Per plan: success, the wall time
of each stage (IK, trajectory optimisation, toppra timing), the least clearance along the timed
trajectory checked every 10 ms against the simulation's true geometry (during a handover the true
object rides in the hand as the grasp would hold it, and its distances count), and the duration.

Each scene is perceived by the robot (a short simulation in which it looks round the table,
pans its head left and right, then back: the table fitted to the point clouds, the objects
detected and sized from depth, the person's skeleton lifted); the planner sees only that.

    python benchmarks/bench_planning.py [--targets 200] [--per-scene 10] [--seed 0]
        [--workers 2] [--json planning.json]
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import json
import math
import statistics
import time
from pathlib import Path

import numpy as np

from hsr_handover.experiments.trials import TrialProgress, run_trials
from hsr_handover.experiments.true_clearance import TrueClearance
from hsr_handover.experiments.watch import WATCH_S, watch
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.planning.plan import Plan
from hsr_handover.robot.planning.planner import plan_grasp, plan_handover
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.timing import joint_limits
from hsr_handover.robot.planning.verification import CHECK_STEP
from hsr_handover.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1] / "scenarios"
SCENES = ("demo.yaml", "intent_reference.yaml", "layouts/standing_five.yaml",
          "layouts/moved_base_four.yaml")  # fmt: skip
LOOK_AT_TABLE = -0.1
"""rad of head tilt while perceiving: the robot looks at the table before it plans a grasp.
(standing_five tilts the head up to a standing face, which cuts the table's near edge out of
view: the fitted table is then 9.5 cm short and plans graze the true edge by up to 6 cm.)"""
MOVE = (0.10, 0.15, 0.25)  # m, m, rad: the largest shift of table, objects and person
START = (0.15, 0.3)  # m, rad: the largest offset of the robot's start from where it perceived
START_CLEARANCE, START_DRAWS = 0.05, 20  # m the start keeps from everything; tries to draw one
VARIANTS = ("seeded", "unseeded")
HANDOVERS_PER_SCENE = 3  # handovers planned from the first seeded grasps, holding the object
COLLISION = 0.0  # m: a true clearance below this is a collision
TARGETS = {"success_rate": 0.98, "median_plan_s": 0.5, "min_clearance_m": 0.01}


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """One scene to perceive and plan in: the scenario file, the rigid move of its table, objects
    and person (dx, dy, dyaw about the table's centre), and the plans' seed."""

    scenario: str
    move: tuple[float, float, float]
    targets: int
    seed: int


def moved(scenario, move):
    """The scenario with its table, objects and person turned by dyaw about the table's centre
    and shifted by (dx, dy), and the robot looking at the table."""
    dx, dy, dyaw = move
    pivot = np.array(scenario.table.center, dtype=float)
    c, s = math.cos(dyaw), math.sin(dyaw)

    def place(xy):
        offset = np.asarray(xy[:2], dtype=float) - pivot
        turned = pivot + np.array([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1]])
        return [float(turned[0] + dx), float(turned[1] + dy), *xy[2:]]

    table = dataclasses.replace(scenario.table, center=place(scenario.table.center)[:2],
                                yaw=scenario.table.yaw + dyaw)  # fmt: skip
    objects = [dataclasses.replace(obj, position=place(obj.position), yaw=obj.yaw + dyaw)
               for obj in scenario.objects]  # fmt: skip
    person = dataclasses.replace(scenario.person, position=place(scenario.person.position),
                                 yaw=scenario.person.yaw + dyaw)  # fmt: skip
    joints = {**scenario.robot.joints, "head_tilt_joint": LOOK_AT_TABLE}
    robot = dataclasses.replace(scenario.robot, joints=joints)
    return dataclasses.replace(scenario, table=table, objects=objects, person=person, robot=robot)


def plan_scene(spec: SceneSpec) -> list[dict]:
    """Every target of one scene, planned seeded and unseeded; one record per plan."""
    scenario = moved(load_scenario(ROOT / spec.scenario), spec.move)
    watched = watch(scenario, WATCH_S, look_around=True)
    perceived, measured = watched.percept("perceived_scene"), watched.measured_positions()
    station = watched.simulation.station
    station_context = watched.simulation.station_context(watched.root)
    planning = PlanningScene(perceived)
    limits = joint_limits(planning.plant)
    truth = TrueClearance(station, station_context, list(limits.names))
    by_color = {obj.color: obj.name for obj in scenario.objects}
    labels = [shape.label for shape in perceived.objects if shape.label in by_color]
    arm_map, _ = load_or_build()
    rng = np.random.default_rng(spec.seed)
    records, holds = [], []
    for index in range(spec.targets):
        label = labels[index % len(labels)] if labels else ""
        q_now = _clear_start(planning, truth, measured, rng)
        for variant in VARIANTS:
            seed_map = arm_map if variant == "seeded" else None
            plan = plan_grasp(planning, seed_map, label, q_now, limits)
            records.append(_record(spec, "grasp", variant, plan, truth, by_color))
            if plan.ok and variant == "seeded":
                holds.append(plan)
    if not labels:
        records.append({**_record(spec, "grasp", "seeded", None, truth, by_color),
                        "reason": "no object perceived"})  # fmt: skip
    arm = watched.person_arm()
    person = None if arm is None else PersonEffectivity(arm)
    for grasp in holds[:HANDOVERS_PER_SCENE]:
        for variant in VARIANTS:
            if person is None:
                records.append({**_record(spec, "handover", variant, None, truth, by_color),
                                "reason": "no person perceived"})  # fmt: skip
                continue
            seed_map = arm_map if variant == "seeded" else None
            plan = plan_handover(planning, seed_map, person, grasp.goal, limits, grasp.held)
            with truth.holding(by_color[grasp.held.label], grasp.held.q_grasp):
                records.append(_record(spec, "handover", variant, plan, truth, by_color))
    return records


def _clear_start(planning, truth, measured: dict, rng: np.random.Generator) -> np.ndarray:
    """A start near where the robot perceived from, at least START_CLEARANCE from everything
    (a robot does not start inside the table); where it perceived from if none is drawn."""
    planning.set_positions(measured)
    perceived_from = planning.positions()
    for _ in range(START_DRAWS):
        start = dict(measured)
        start["base_x_joint"] += rng.uniform(-START[0], START[0])
        start["base_y_joint"] += rng.uniform(-START[0], START[0])
        start["base_yaw_joint"] += rng.uniform(-START[1], START[1])
        planning.set_positions(start)
        if truth(planning.positions())[0] >= START_CLEARANCE:
            return planning.positions()
    return perceived_from


def _record(spec: SceneSpec, kind: str, variant: str, plan: Plan | None, truth, by_color) -> dict:
    """One plan's line: what, where, whether, how long, and how close to the true world."""
    base = {"scene": spec.scenario, "moved": spec.move != (0.0, 0.0, 0.0), "kind": kind,
            "variant": variant}  # fmt: skip
    if plan is None:
        return {**base, "ok": False, "reason": ""}
    stages = {f"{stage}_s": value for stage, value in plan.seconds.items()}
    clearance, nearest = _true_clearance(plan, truth, by_color)
    return {**base, "target": plan.target, "ok": plan.ok, "reason": plan.reason,
            "ik_solves": plan.ik_solves, **stages, "plan_s": plan.plan_seconds,
            "duration_s": plan.duration if plan.ok else None, "min_clearance_m": clearance,
            "nearest": nearest}  # fmt: skip


def _true_clearance(plan: Plan, truth: TrueClearance, by_color: dict) -> tuple:
    if not plan.ok:
        return None, ""
    best, nearest = math.inf, ""
    for motion in plan.motions:
        ignore = tuple(by_color.get(label, label) for label in motion.ignore)
        _, positions = motion.sample(CHECK_STEP)
        for q in positions:
            distance, name = truth(q, ignore)
            if distance < best:
                best, nearest = distance, name
    return best, nearest


def summarise(records: list[dict], variant: str) -> dict:
    """The JSON's figures for one variant, over all plans and by kind (grasp, handover)."""
    mine = [r for r in records if r["variant"] == variant]
    return {
        **_figures(mine),
        "by_kind": {
            kind: _figures([r for r in mine if r["kind"] == kind]) for kind in ("grasp", "handover")
        },
    }


def _figures(mine: list[dict]) -> dict:
    done = [r for r in mine if r["ok"]]
    plan_s = [r["plan_s"] for r in done]
    clearances = [r["min_clearance_m"] for r in done]
    failures = collections.Counter(r["reason"].split(":")[0] for r in mine if not r["ok"])
    return {
        "plans": len(mine),
        "success_rate": len(done) / len(mine) if mine else 0.0,
        "median_plan_s": statistics.median(plan_s) if plan_s else None,
        "p95_plan_s": float(np.percentile(plan_s, 95)) if plan_s else None,
        "stage_median_s": {
            stage: statistics.median(r[f"{stage}_s"] for r in done)
            for stage in ("ik", "optimisation", "timing")
        }
        if done
        else {},
        "min_clearance_m": min(clearances) if clearances else None,
        "median_clearance_m": statistics.median(clearances) if clearances else None,
        "collisions": sum(c < COLLISION for c in clearances),
        "below_1cm": sum(c < 0.01 for c in clearances),
        "median_duration_s": statistics.median(r["duration_s"] for r in done) if done else None,
        "failures": dict(failures),
    }


def scene_specs(targets: int, per_scene: int, seed: int) -> list[SceneSpec]:
    """Each bundled scene as it is, then moved copies, until `targets` are planned."""
    rng = np.random.default_rng(seed)
    specs, planned = [], 0
    while planned < targets:
        name = SCENES[len(specs) % len(SCENES)]
        move = (0.0, 0.0, 0.0) if len(specs) < len(SCENES) else tuple(
            float(rng.uniform(-m, m)) for m in MOVE)  # fmt: skip
        count = min(per_scene, targets - planned)
        specs.append(SceneSpec(name, move, count, int(rng.integers(2**31))))
        planned += count
    return specs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=200)
    parser.add_argument("--per-scene", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    load_or_build()  # built once here, not in every worker
    start = time.perf_counter()
    specs = scene_specs(args.targets, args.per_scene, args.seed)
    outcomes = run_trials(plan_scene, specs, args.workers, progress=TrialProgress())
    records = [r for outcome in outcomes if outcome.ok for r in outcome.result]
    failed_scenes = [(spec.scenario, o.error) for spec, o in zip(specs, outcomes, strict=True)
                     if not o.ok]  # fmt: skip
    report = {variant: summarise(records, variant) for variant in VARIANTS}
    summary = {**report["seeded"], "unseeded": report["unseeded"], "targets": TARGETS,
               "scenes": len(specs), "failed_scenes": failed_scenes,
               "wall_s": time.perf_counter() - start}  # fmt: skip
    _print(summary)
    if args.json:
        args.json.write_text(json.dumps({**summary, "plans_detail": records}, indent=1))


def _print(summary: dict) -> None:
    print(f"{summary['scenes']} scenes, {summary['plans']} plans per variant, "
          f"wall {summary['wall_s']:.0f} s")  # fmt: skip
    for name, figures in (("seeded", summary), ("unseeded", summary["unseeded"])):
        for kind, part in (("all", figures), *figures["by_kind"].items()):
            print(f"{name:9s} {kind:9s} {_line(part)}")
        print(f"{'':9s} failures {figures['failures']}")
    seeded, unseeded = summary, summary["unseeded"]
    if unseeded["success_rate"] > 0 and unseeded["median_plan_s"]:
        print(f"the map's worth: success x{seeded['success_rate'] / unseeded['success_rate']:.2f}, "
              f"median plan time x{seeded['median_plan_s'] / unseeded['median_plan_s']:.2f} "
              "(seeded / unseeded, the baseline, same targets)")  # fmt: skip


def _line(figures: dict) -> str:
    if not figures["plans"]:
        return "no plans"
    stages = " ".join(f"{k} {v * 1e3:.0f}" for k, v in figures["stage_median_s"].items())
    clearance = figures["min_clearance_m"]
    return (f"{figures['plans']:4d} plans, success {figures['success_rate']:6.1%}, plan median "
            f"{_ms(figures['median_plan_s'])} p95 {_ms(figures['p95_plan_s'])} (ms: {stages}), "
            f"least true clearance {'n/a' if clearance is None else f'{clearance * 100:.1f} cm'}, "
            f"collisions {figures['collisions']}")  # fmt: skip


def _ms(seconds: float | None) -> str:
    return "n/a" if seconds is None else f"{seconds * 1e3:.0f} ms"


if __name__ == "__main__":
    main()
