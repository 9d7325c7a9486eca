"""Planning from percepts, every plan kind the handover cycle makes: grasps (move, approach,
lift) of the table's objects; from the first grasps, the carry to the handover point holding the
object, and from each carry the follow (ruckig, to a hand moved from the handover point), the
put back (from part way along the carry, the way it came), the retreat (after a handover, and
holding the object nobody took) and the back off (from the object put back); and from each start
the posture (the watching raise). In the bundled scenes, in copies with the table, its objects
and the person moved, and (`--layouts generated` or `both`) in layouts drawn by the experiments'
generator. The kinds the arm's effectivity map seeds (grasp, carry) are planned twice in the
same run: seeded (base placement and IK seeds, eq. 11) and unseeded (the base at a fixed reach,
IK from the arm as it is), the baseline. Per plan: success, the wall time of each stage (IK,
trajectory optimisation, toppra timing, retries), the least clearance along the timed trajectory
checked every 10 ms against the simulation's true geometry (with the object held the true object
rides in the hand as the grasp would hold it, and its distances count), the most the object held
tilts from upright ("tilt cup/box": a cup keeps within 20 degrees, a box may lie on its side),
and the duration. Each failure is judged by a slower exhaustive search (`exhaustive`: more IK
seeds and base placements, random via points, 1000 SNOPT iterations): "missed" when it finds a
plan, "unreachable" when it does not; the success rate over reachable targets counts only the
missed.

Each scene is perceived by the robot (a short simulation in which it looks round the table,
pans its head left and right, then back: the table fitted to the point clouds, the objects
detected and sized from depth, the person's skeleton lifted); the planner sees only that.

    python benchmarks/bench_planning.py [--targets 200] [--per-scene 10] [--seed 0]
        [--layouts bundled|generated|both] [--workers 2] [--json planning.json]
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import dataclasses
import functools
import json
import math
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from hsr_handover.experiments.layouts import generate_layout
from hsr_handover.experiments.trials import TrialProgress, run_trials
from hsr_handover.experiments.true_clearance import TrueClearance
from hsr_handover.experiments.watch import WATCH_S, watch
from hsr_handover.robot.effectivity.arm_map import load_or_build
from hsr_handover.robot.effectivity.person_map import PersonEffectivity
from hsr_handover.robot.handover.watch_view import FLEX, LIFT
from hsr_handover.robot.perception.object_shapes import BOX, CYLINDER
from hsr_handover.robot.planning import (
    follow,
    grasp_configurations,
    handover_pose,
    inverse_kinematics,
    paths,
    planner,
    solving,
)
from hsr_handover.robot.planning.follow import plan_follow
from hsr_handover.robot.planning.inverse_kinematics import PalmGoal, palm_goal
from hsr_handover.robot.planning.plan import Plan
from hsr_handover.robot.planning.planner import (
    LOWER,
    plan_back_off,
    plan_grasp,
    plan_handover,
    plan_posture,
    plan_put_back,
    plan_retreat,
)
from hsr_handover.robot.planning.planning_scene import PlanningScene
from hsr_handover.robot.planning.timing import joint_limits
from hsr_handover.robot.planning.trajectory import COLLISION_BOUND, CONTROL_POINTS
from hsr_handover.robot.planning.upright import tilt_from, upright_for
from hsr_handover.robot.planning.verification import CHECK_STEP
from hsr_handover.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1] / "scenarios"
SCENES = ("demo.yaml", "intent_reference.yaml", "layouts/standing_five.yaml",
          "layouts/moved_base_four.yaml")  # fmt: skip
GENERATED_FROM = "intent_reference.yaml"  # the generated layouts' base (its `layouts` ranges)
LAYOUTS = ("bundled", "generated", "both")
LOOK_AT_TABLE = -0.1
"""rad of head tilt while perceiving: the robot looks at the table before it plans a grasp.
(standing_five tilts the head up to a standing face, which cuts the table's near edge out of
view: the fitted table is then 9.5 cm short and plans graze the true edge by up to 6 cm.)"""
MOVE = (0.10, 0.15, 0.25)  # m, m, rad: the largest shift of table, objects and person
START = (0.15, 0.3)  # m, rad: the largest offset of the robot's start from where it perceived
START_CLEARANCE, START_DRAWS = 0.05, 20  # m the start keeps from everything; tries to draw one
VARIANTS = ("seeded", "unseeded")
KINDS = ("grasp", "carry", "follow", "put back", "retreat", "back off", "posture")
MAPPED = ("grasp", "carry")  # the kinds the arm's map seeds: planned unseeded too (the baseline)
HANDOVERS_PER_SCENE = 3  # carries planned from the first seeded grasps, holding the object
HAND_MOVED = (0.08, 0.08, 0.05)  # m: the largest move of the hand a follow re-targets to
PUT_BACK_FROM = (0.3, 1.0)  # share of the carry played when the put back is asked for
RISE = (0.03, 0.15)  # m the watching raise lifts the camera (the lift twice as far)
COLLISION = 0.0  # m: a true clearance below this is a collision
TARGETS = {"success_rate": 0.99, "median_plan_s": 0.25, "p95_plan_s": 0.6, "min_clearance_m": 0.01}
EXHAUSTIVE = {"iterations": 1000, "ik_seeds": 8, "vias": 6, "placements": 12}
"""The reachability judge's effort: SNOPT's major iterations, random IK seeds after a failed
solve, random via points as first guesses for a path, base placements per grasp or aim."""


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """One scene to perceive and plan in: the scenario file, the rigid move of its table, objects
    and person (dx, dy, dyaw about the table's centre), or (`generated`) a layout drawn from it
    with the plans' seed; the number of grasp targets and the plans' seed."""

    scenario: str
    move: tuple[float, float, float]
    targets: int
    seed: int
    generated: bool = False

    @property
    def name(self) -> str:
        return f"generated from {self.scenario}" if self.generated else self.scenario


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


def scene_scenario(spec: SceneSpec):
    """The scenario a spec perceives: the bundled one moved, or a layout generated from it."""
    scenario = load_scenario(ROOT / spec.scenario)
    if spec.generated:
        scenario, _ = generate_layout(scenario, np.random.default_rng(spec.seed))
    return moved(scenario, spec.move)


@dataclasses.dataclass
class Bench:
    """One perceived scene and what plans in it are scored against."""

    spec: SceneSpec
    planning: PlanningScene
    limits: object
    truth: TrueClearance
    by_color: dict
    rng: np.random.Generator
    records: list = dataclasses.field(default_factory=list)

    def plan(self, kind: str, variant: str, planning: Callable[[], Plan],
             holding: tuple[str, np.ndarray] | None = None) -> Plan:  # fmt: skip
        """Plan with `planning`, record it (scored with the true object `holding` in the hand,
        if given; a failure judged by the exhaustive search), and return the plan."""
        plan = planning()
        with self._holding(holding):
            record = _record(self.spec, kind, variant, plan, self.truth, self.by_color)
        if plan.ok and holding is not None and any(m.name == LOWER for m in plan.motions):
            # Lowered, the object stands on the table again: scored as let go of.
            lowered = dataclasses.replace(plan, motions=plan.motions[-1:])
            clearance, nearest = _true_clearance(lowered, self.truth, self.by_color)
            with self._holding(holding):
                carried = dataclasses.replace(plan, motions=plan.motions[:-1])
                scores = [(clearance, nearest),
                          _true_clearance(carried, self.truth, self.by_color)]  # fmt: skip
            scored = [score for score in scores if score[0] is not None]
            record["min_clearance_m"], record["nearest"] = min(scored, default=(None, ""))
        if plan.ok and holding is not None:
            shape = self.planning.scene.object_named(holding[0])
            if shape is not None:
                record["held"] = shape.kind
                record["held_tilt_deg"] = _held_tilt(self.planning, plan, shape, holding[1])
        if not plan.ok:  # its own draws: a failure leaves the later targets as they were
            with exhaustive(np.random.default_rng(len(self.records))):
                record["judged"] = "missed" if planning().ok else "unreachable"
        self.records.append(record)
        return plan

    def _holding(self, holding):
        if holding is None:
            return contextlib.nullcontext()
        return self.truth.holding(self.by_color[holding[0]], holding[1])


def plan_scene(spec: SceneSpec) -> list[dict]:
    """Every target of one scene, every kind, planned seeded and (where the map seeds it)
    unseeded; one record per plan."""
    scenario = scene_scenario(spec)
    watched = watch(scenario, WATCH_S, look_around=True)
    perceived, measured = watched.scene, watched.measured_positions()
    station = watched.simulation.station
    station_context = watched.simulation.station_context(watched.root)
    planning = PlanningScene(perceived)
    limits = joint_limits(planning.plant)
    truth = TrueClearance(station, station_context, list(limits.names))
    by_color = {obj.color: obj.name for obj in scenario.objects}
    labels = [shape.label for shape in perceived.objects if shape.label in by_color]
    arm_map, _ = load_or_build()
    bench = Bench(spec, planning, limits, truth, by_color, np.random.default_rng(spec.seed))
    holds = []
    for index in range(spec.targets):
        label = labels[index % len(labels)] if labels else ""
        q_now = _clear_start(planning, truth, measured, bench.rng)
        for variant in VARIANTS:
            seed_map = arm_map if variant == "seeded" else None
            plan = bench.plan("grasp", variant,
                              functools.partial(plan_grasp, planning, seed_map, label, q_now,
                                                limits))  # fmt: skip
            if plan.ok and variant == "seeded":
                holds.append(plan)
        _posture(bench, q_now)
    if not labels:
        bench.records.append({**_record(spec, "grasp", "seeded", None, truth, by_color),
                              "reason": "no object perceived"})  # fmt: skip
    arm = watched.person_arm()
    person = None if arm is None else PersonEffectivity(arm)
    for grasp in holds[:HANDOVERS_PER_SCENE]:
        _carry_and_after(bench, arm_map, person, grasp)
    return bench.records


def _carry_and_after(bench: Bench, arm_map, person, grasp: Plan) -> None:
    """The carry from a grasp, seeded and unseeded, and from the seeded carry the follow, the
    put back, the retreats and the back off."""
    held, planning, limits = grasp.held, bench.planning, bench.limits
    holding = (held.label, held.q_grasp)
    carry = None
    for variant in VARIANTS:
        if person is None:
            bench.records.append(
                {
                    **_record(bench.spec, "carry", variant, None, bench.truth, bench.by_color),
                    "reason": "no person perceived",
                }
            )
            continue
        seed_map = arm_map if variant == "seeded" else None
        plan = bench.plan("carry", variant,
                          functools.partial(plan_handover, planning, seed_map, person, grasp.goal,
                                            limits, held), holding)  # fmt: skip
        if variant == "seeded" and plan.ok:
            carry = plan
    if carry is None:
        return
    at_hand = carry.goal
    bench.plan("follow", "seeded", functools.partial(
        plan_follow, planning, _follow_goal(bench, at_hand), at_hand, np.zeros_like(at_hand), held,
        limits, arm_map), holding)  # fmt: skip
    motion = carry.motions[-1]
    played = bench.rng.uniform(*PUT_BACK_FROM) * motion.duration
    came = [motion.state(t)[0] for t in np.linspace(0.0, played, 16)]
    bench.plan("put back", "seeded", functools.partial(
        plan_put_back, planning, came[-1], held, grasp.goal, limits, came), holding)  # fmt: skip
    bench.plan("retreat", "seeded", functools.partial(
        plan_retreat, planning, at_hand, limits, None, held.label))  # fmt: skip
    bench.plan("retreat", "seeded", functools.partial(
        plan_retreat, planning, at_hand, limits, held), holding)  # fmt: skip
    # Put back and let go of: the fingers open round the object where they closed on it.
    q_open = grasp.motions[1].state(grasp.motions[1].duration)[0]
    bench.plan("back off", "seeded", functools.partial(
        plan_back_off, planning, q_open, limits, held.label))  # fmt: skip


def _follow_goal(bench: Bench, q: np.ndarray) -> PalmGoal:
    """The hand kept turned as at `q`, its pads moved by up to HAND_MOVED (the person's hand
    moved from the handover point), as the cycle's follow asks."""
    goal = palm_goal(bench.planning, q)
    moved = bench.rng.uniform(-1.0, 1.0, 3) * np.array(HAND_MOVED)
    return dataclasses.replace(goal, point=goal.point + moved)


def _posture(bench: Bench, q_now: np.ndarray) -> None:
    """The watching raise from `q_now`: the lift up by twice a drawn rise, the torso half as
    far, the arm flexed down to its limit (`watch_view.watch_posture`'s posture)."""
    planning = bench.planning
    lift, torso, flex = (planning.index(joint) for joint in (LIFT, "torso_lift_joint", FLEX))
    lower = planning.plant.GetPositionLowerLimits()
    upper = planning.plant.GetPositionUpperLimits()
    raised = q_now.copy()
    raised[lift] = min(upper[lift], q_now[lift] + 2.0 * bench.rng.uniform(*RISE))
    raised[torso] = 0.5 * raised[lift]
    raised[flex] = lower[flex]
    bench.plan("posture", "seeded",
               functools.partial(plan_posture, planning, q_now, raised, bench.limits))  # fmt: skip


@contextlib.contextmanager
def exhaustive(rng: np.random.Generator):
    """Within the block the planner searches as far as the benchmark can wait (EXHAUSTIVE):
    every IK solve that fails is tried again from random seeds, every grasp and aim takes more
    base placements, every path gets random via points as further first guesses, and SNOPT
    runs up to 1000 major iterations. What this finds exists; the planner should have found
    it."""
    solve_ik = inverse_kinematics.solve_palm_ik
    place = grasp_configurations.place_base
    longer = {name: dataclasses.replace(getattr(solving, name), iterations=EXHAUSTIVE["iterations"])
              for name in ("IK_EFFORT", "PATH_EFFORT")}  # fmt: skip
    patches = [*((solving, name, effort) for name, effort in longer.items()),
               (paths, "_guesses", _with_vias(paths._guesses, rng))]  # fmt: skip
    for module in (grasp_configurations, handover_pose, follow, planner):
        if hasattr(module, "solve_palm_ik"):
            patches.append((module, "solve_palm_ik", _reseeded(solve_ik, rng)))
    for module in (grasp_configurations, handover_pose):
        patches.append((module, "place_base", _more_placements(place)))
    saved = [(module, name, getattr(module, name)) for module, name, _ in patches]
    try:
        for module, name, value in patches:
            setattr(module, name, value)
        yield
    finally:
        for module, name, value in saved:
            setattr(module, name, value)


def _reseeded(solve_ik, rng: np.random.Generator):
    """`solve_ik` tried again from EXHAUSTIVE["ik_seeds"] seeds with the arm drawn within its
    limits while it fails."""
    arm_joints = ("arm_lift_joint", "arm_flex_joint", "arm_roll_joint", "wrist_flex_joint",
                  "wrist_roll_joint")  # fmt: skip

    def solve(scene, goal, seed, *args, **kwargs):
        found = solve_ik(scene, goal, seed, *args, **kwargs)
        arm = [scene.index(joint) for joint in arm_joints]
        lower = scene.plant.GetPositionLowerLimits()[arm]
        upper = scene.plant.GetPositionUpperLimits()[arm]
        for _ in range(EXHAUSTIVE["ik_seeds"]):
            if found.ok:
                return found
            drawn = np.asarray(seed, dtype=float).copy()
            drawn[arm] = rng.uniform(lower, upper)
            found = solve_ik(scene, goal, drawn, *args, **kwargs)
        return found

    return solve


def _more_placements(place):
    def placements(*args, **kwargs):
        kwargs.pop("most", None)
        if len(args) > 7:
            args = args[:7] + (EXHAUSTIVE["placements"],) + args[8:]
            return place(*args, **kwargs)
        return place(*args, most=EXHAUSTIVE["placements"], **kwargs)

    return placements


def _with_vias(guesses, rng: np.random.Generator):
    def with_vias(scene, q_from, q_to, *args, **kwargs):
        tried = list(guesses(scene, q_from, q_to, *args, **kwargs))
        lower = np.maximum(scene.plant.GetPositionLowerLimits(), -20.0)
        upper = np.minimum(scene.plant.GetPositionUpperLimits(), 20.0)
        for k in range(EXHAUSTIVE["vias"]):
            via = (q_from + q_to) / 2 + rng.normal(0.0, 0.3, len(q_from))
            via = np.clip(via, lower, upper)
            half = CONTROL_POINTS // 2
            points = np.hstack(
                [
                    np.linspace(q_from, via, half).T,
                    np.linspace(via, q_to, CONTROL_POINTS - half + 1).T[:, 1:],
                ]
            )
            tried.append((f"via {k}", points))  # fmt: skip
        return tried

    return with_vias


def _clear_start(planning, truth, measured: dict, rng: np.random.Generator) -> np.ndarray:
    """A start near where the robot perceived from, at least START_CLEARANCE from everything
    (a robot does not start inside the table) and COLLISION_BOUND from what it perceives (the
    cycle's robot stands where clear paths of its percepts brought it: drawn only clear of the
    truth, a hand stowed under a table's top started inside the perceived table's block, which
    runs to the floor); where it perceived from if none is drawn."""
    planning.set_positions(measured)
    perceived_from = planning.positions()
    for _ in range(START_DRAWS):
        start = dict(measured)
        start["base_x_joint"] += rng.uniform(-START[0], START[0])
        start["base_y_joint"] += rng.uniform(-START[0], START[0])
        start["base_yaw_joint"] += rng.uniform(-START[1], START[1])
        planning.set_positions(start)
        clear = planning.clearance(within=COLLISION_BOUND)[0] >= COLLISION_BOUND
        if clear and truth(planning.positions())[0] >= START_CLEARANCE:
            return planning.positions()
    return perceived_from


def _record(spec: SceneSpec, kind: str, variant: str, plan: Plan | None, truth, by_color) -> dict:
    """One plan's line: what, where, whether, how long, and how close to the true world."""
    base = {"scene": spec.name, "moved": spec.move != (0.0, 0.0, 0.0),
            "generated": spec.generated, "kind": kind, "variant": variant}  # fmt: skip
    if plan is None:
        return {**base, "ok": False, "reason": ""}
    stages = {f"{stage}_s": value for stage, value in plan.seconds.items()}
    clearance, nearest = _true_clearance(plan, truth, by_color)
    return {**base, "target": plan.target, "ok": plan.ok, "reason": plan.reason,
            "retried": list(getattr(plan, "retried", ())), "ik_solves": plan.ik_solves,
            **stages, "plan_s": plan.plan_seconds,
            "duration_s": plan.duration if plan.ok else None, "min_clearance_m": clearance,
            "nearest": nearest}  # fmt: skip


def _held_tilt(planning: PlanningScene, plan: Plan, shape, q_grasp: np.ndarray) -> float:
    """The most (deg) the object held (`shape`), upright where the hand closed on it at
    `q_grasp`, tilts along the plan's motions checked every CHECK_STEP s (the last leg of a put
    back included: it stands again at its end)."""
    up = upright_for(shape, planning.hand_pose(q_grasp).rotation().matrix()).up_in_hand
    return max((math.degrees(tilt_from(planning.hand_pose(q).rotation().matrix(), up))
                for motion in plan.motions for q in motion.sample(CHECK_STEP)[1]),
               default=0.0)  # fmt: skip


def _true_clearance(plan: Plan, truth: TrueClearance, by_color: dict) -> tuple:
    if not plan.ok or not plan.motions:
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
    """The JSON's figures for one variant, over all plans and by kind."""
    mine = [r for r in records if r["variant"] == variant]
    kinds = KINDS if variant == "seeded" else MAPPED
    return {
        **_figures(mine),
        "by_kind": {kind: _figures([r for r in mine if r["kind"] == kind]) for kind in kinds},
    }


def _figures(records: list[dict]) -> dict:
    mine = [r for r in records if "plan_s" in r]  # not "no person perceived": nothing to plan
    done = [r for r in mine if r["ok"]]
    plan_s = [r["plan_s"] for r in done]
    clearances = [r["min_clearance_m"] for r in done if r["min_clearance_m"] is not None]
    tilts = {kind: [r["held_tilt_deg"] for r in done if r.get("held") == kind]
             for kind in (CYLINDER, BOX)}  # fmt: skip
    failures = collections.Counter(r["reason"].split(":")[0] for r in mine if not r["ok"])
    judged = collections.Counter(r.get("judged", "") for r in mine if not r["ok"])
    reachable = len(mine) - judged["unreachable"]
    return {
        "plans": len(mine),
        "not_planned": len(records) - len(mine),
        "succeeded": len(done),
        "success_rate": len(done) / len(mine) if mine else 0.0,
        "missed": judged["missed"],
        "unreachable": judged["unreachable"],
        "reachable_success_rate": len(done) / reachable if reachable else None,
        "retried": sum(bool(r.get("retried")) for r in done),
        "median_plan_s": statistics.median(plan_s) if plan_s else None,
        "p95_plan_s": float(np.percentile(plan_s, 95)) if plan_s else None,
        "stage_median_s": {
            stage: statistics.median(r.get(f"{stage}_s", 0.0) for r in done)
            for stage in ("ik", "optimisation", "timing", "retry")
        }
        if done
        else {},
        "min_clearance_m": min(clearances) if clearances else None,
        "median_clearance_m": statistics.median(clearances) if clearances else None,
        "collisions": sum(c < COLLISION for c in clearances),
        "below_1cm": sum(c < 0.01 for c in clearances),
        "median_duration_s": statistics.median(r["duration_s"] for r in done) if done else None,
        "max_cup_tilt_deg": max(tilts[CYLINDER], default=None),
        "max_box_tilt_deg": max(tilts[BOX], default=None),
        "failures": dict(failures),
    }


def scene_specs(
    targets: int, per_scene: int, seed: int, layouts: str = "bundled"
) -> list[SceneSpec]:
    """Each bundled scene as it is, then moved copies (`layouts` "bundled"), or layouts drawn
    by the experiments' generator ("generated"), or both alternately, until `targets` grasp
    targets are planned."""
    if layouts not in LAYOUTS:
        raise ValueError(f"layouts: expected one of {LAYOUTS}, got {layouts!r}")
    rng = np.random.default_rng(seed)
    specs, planned, bundled = [], 0, 0
    while planned < targets:
        count = min(per_scene, targets - planned)
        generate = layouts == "generated" or (layouts == "both" and len(specs) % 2 == 1)
        if generate:
            specs.append(SceneSpec(GENERATED_FROM, (0.0, 0.0, 0.0), count,
                                   int(rng.integers(2**31)), generated=True))  # fmt: skip
        else:
            name = SCENES[bundled % len(SCENES)]
            move = (0.0, 0.0, 0.0) if bundled < len(SCENES) else tuple(
                float(rng.uniform(-m, m)) for m in MOVE)  # fmt: skip
            specs.append(SceneSpec(name, move, count, int(rng.integers(2**31))))
            bundled += 1
        planned += count
    return specs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=200)
    parser.add_argument("--per-scene", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--layouts", choices=LAYOUTS, default="bundled")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    load_or_build()  # built once here, not in every worker
    start = time.perf_counter()
    specs = scene_specs(args.targets, args.per_scene, args.seed, args.layouts)
    outcomes = run_trials(plan_scene, specs, args.workers, progress=TrialProgress())
    records = [r for outcome in outcomes if outcome.ok for r in outcome.result]
    failed_scenes = [(spec.name, o.error) for spec, o in zip(specs, outcomes, strict=True)
                     if not o.ok]  # fmt: skip
    report = {variant: summarise(records, variant) for variant in VARIANTS}
    summary = {**report["seeded"], "unseeded": report["unseeded"], "targets": TARGETS,
               "scenes": len(specs), "failed_scenes": failed_scenes,
               "wall_s": time.perf_counter() - start}  # fmt: skip
    _print(summary)
    if args.json:
        args.json.write_text(json.dumps({**summary, "plans_detail": records}, indent=1))


def _print(summary: dict) -> None:
    print(f"{summary['scenes']} scenes, {summary['plans']} seeded plans, "
          f"wall {summary['wall_s']:.0f} s")  # fmt: skip
    baseline = summary["unseeded"]["by_kind"]
    print(f"{'kind':9s} {'plans':>5s} {'success':>8s} {'of reachable':>12s} {'missed':>6s} "
          f"{'unreach':>7s} {'retried':>7s} {'median':>8s} {'p95':>8s} {'least clear':>11s} "
          f"{'tilt cup/box':>9s}   "
          "baseline (unseeded): success median p95")  # fmt: skip
    for kind, part in (*summary["by_kind"].items(), ("all", summary)):
        base = baseline.get(kind, summary["unseeded"] if kind == "all" else None)
        print(f"{kind:9s} {_line(part)}   {_baseline(base)}")
    print(f"failures: {summary['failures']}; unseeded failures: {summary['unseeded']['failures']}")
    seeded, unseeded = summary, summary["unseeded"]
    if unseeded["success_rate"] > 0 and unseeded["median_plan_s"]:
        print(f"the map's worth (grasps and carries): success x"
              f"{_mapped(seeded, 'succeeded') / max(_mapped(unseeded, 'succeeded'), 1):.2f} "
              "(seeded / unseeded, the baseline, same targets)")  # fmt: skip


def _mapped(figures: dict, key: str) -> int:
    return sum(figures["by_kind"][kind][key] for kind in MAPPED)


def _line(figures: dict) -> str:
    if not figures["plans"]:
        return f"{0:5d} {'no plans':>8s}"
    clearance = figures["min_clearance_m"]
    tilts = "/".join("-" if figures[key] is None else f"{figures[key]:.0f}°"
                     for key in ("max_cup_tilt_deg", "max_box_tilt_deg"))  # fmt: skip
    reachable = figures["reachable_success_rate"]
    return (f"{figures['plans']:5d} {figures['success_rate']:8.1%} "
            f"{'n/a' if reachable is None else f'{reachable:.1%}':>12s} {figures['missed']:6d} "
            f"{figures['unreachable']:7d} {figures['retried']:7d} "
            f"{_ms(figures['median_plan_s']):>8s} {_ms(figures['p95_plan_s']):>8s} "
            f"{'n/a' if clearance is None else f'{clearance * 100:.1f} cm':>11s} "
            f"{tilts:>9s}")  # fmt: skip


def _baseline(figures: dict | None) -> str:
    if figures is None:
        return "n/a (no map to seed)"
    if not figures["plans"]:
        return "no plans"
    return (f"{figures['success_rate']:.1%} {_ms(figures['median_plan_s'])} "
            f"{_ms(figures['p95_plan_s'])}")  # fmt: skip


def _ms(seconds: float | None) -> str:
    return "n/a" if seconds is None else f"{seconds * 1e3:.0f} ms"


if __name__ == "__main__":
    main()
