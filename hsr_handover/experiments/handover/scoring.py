"""A handover trial scored against the world as it truly is, the way HandoverSim counts
(NVlabs/handover-sim's evaluator: contact with the person, object drop, timeout) plus ours
(table contact, an object knocked). Ground truth: a simulator monitor for experiments only,
never read by the robot.

After every plant step it reads the plant's contact results (any contact counts, as in
HandoverSim) and the objects' heights, and a `TrialWatch` applies the rules to them; every
CLEARANCE_EVERY_S it measures the least distance from the robot, and the object it carries, to
the table and to the person.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from pydrake.systems.framework import Context, EventStatus

from hsr_handover.experiments.true_clearance import HAND, PERSON, ROBOT, TABLE, geometry_owners
from hsr_handover.interface import TRUTH_PERSON_GRIP
from hsr_handover.simulation import Simulation
from hsr_handover.systems.contact_pairs import contact_pairs

LIFTED = 0.05  # m above where it stood: the object has been picked up
DROPPED = 0.01
"""m above where it stood: an object picked up and back this low, touching neither the robot
nor the person's closed hand, has dropped (HandoverSim: not held, and touching the table or
below it)."""
SPILL_TILT_DEG = 23.0
"""deg from upright past which a cup carried spills: a 10 cm cup filled to 1.5 cm under its rim
(tan 23° = 1.5 / 3.5, its radius). The robot keeps a cup within 20° (`planning.upright`)."""
CLEARANCE_EVERY_S = 0.05  # s between clearance measurements
NEAR = 0.5  # m: distances beyond this are not measured
PERCEIVED_TABLE = "table"  # the robot's output of the table it perceives (PERCEPTION_OUTPUTS)
NOT_OBJECTS = frozenset({TABLE, PERSON, HAND, ROBOT, ""})  # the owners that are not objects


@dataclasses.dataclass
class TrialScore:
    """What truly happened: when each object was first `lifted` (s), when the target `dropped`,
    when the robot (or the object it carried) first touched the table, the person, and each
    other object (`knocked`; the judge leaves out any that were picked up), when the person
    first touched each object before the robot had lifted it (`person_knocked`: the world's
    doing, not the robot's, as when a pointing hand on the object asked for pushes it over),
    when the person's hand closed on the target (`gripped`), and the least clearance from the
    robot and its load to the table and to the person's body (m; the hands are left out:
    touching one is a contact, and a hand comes close to take the object); and, for every other
    object the robot lifted (and should have put back), how far above where it stood it was last
    seen (`set_down`, m: about 0 when put back standing; a box down on its side reads 3 cm
    below); and the most the robot's perceived table top was off the true one's height
    (`table_height_error`, m; NaN if it never perceived one); and the most the target tilted
    from upright while the robot carried it (`held_tilt`, deg)."""

    lifted: dict[str, float] = dataclasses.field(default_factory=dict)
    dropped: float = math.nan
    table_contact: float = math.nan
    person_contact: float = math.nan
    knocked: dict[str, float] = dataclasses.field(default_factory=dict)
    person_knocked: dict[str, float] = dataclasses.field(default_factory=dict)
    gripped: float = math.nan
    clearance_table: float = math.inf
    clearance_person: float = math.inf
    set_down: dict[str, float] = dataclasses.field(default_factory=dict)
    table_height_error: float = math.nan
    held_tilt: float = 0.0


class TrialWatch:
    """The scoring rules on plain observations, knowing nothing of Drake: after each step,
    `observe` the objects' heights, the pairs of owners in contact (ROBOT, TABLE, PERSON, HAND
    or an object's name), the object the person's hand holds ("" for none) and the target's
    tilt from upright."""

    def __init__(self, target: str):
        self.score = TrialScore()
        self._target = target
        self._start: dict[str, float] = {}
        self._heights_now: dict[str, float] = {}

    def carrying(self) -> bool:
        """Whether the target counts as part of the robot: lifted, not dropped, not taken."""
        score = self.score
        return (
            self._target in score.lifted and math.isnan(score.dropped) and math.isnan(score.gripped)
        )

    def _carried(self, name: str) -> bool:
        """Whether `name` counts as part of the robot: the target `carrying`, or another
        object lifted, each while it is up. An object back at the height it stood at is being
        set down on the table (the target too, put back when the robot was told it had the
        wrong one), and its touching the table is the placing, not a collision."""
        up = self._heights_now.get(name, -math.inf) >= self._start.get(name, math.inf) + DROPPED
        if name == self._target:
            return self.carrying() and up
        return name in self.score.lifted and up

    def observe(
        self,
        time: float,
        heights: dict[str, float],
        contacts: list[tuple[str, str]],
        grip: str,
        tilt: float = 0.0,
    ) -> None:
        """`tilt` is the target's from upright (deg)."""
        if math.isnan(self.score.gripped) and grip == self._target:
            self.score.gripped = time
        held = any(self._target in pair and ROBOT in pair for pair in contacts)
        self._heights(time, heights, held)
        if self.carrying():
            self.score.held_tilt = max(self.score.held_tilt, tilt)
        for a, b in contacts:
            self._contact(time, a, b)

    def _heights(self, time: float, heights: dict[str, float], held: bool) -> None:
        score = self.score
        self._heights_now = heights
        for name, height in heights.items():
            start = self._start.setdefault(name, height)
            if name not in score.lifted and height > start + LIFTED:
                score.lifted[name] = time
            if name in score.lifted and name != self._target:
                score.set_down[name] = height - start
        # HandoverSim's drop: not held, and down on the table (or below it). An object held
        # out low, near the table's edge, is still held.
        low = heights[self._target] < self._start[self._target] + DROPPED
        if self.carrying() and low and not held:
            score.dropped = time

    def _contact(self, time: float, a: str, b: str) -> None:
        score = self.score
        for mine, other in ((a, b), (b, a)):
            if mine in (PERSON, HAND) and other not in NOT_OBJECTS and other not in score.lifted:
                score.person_knocked.setdefault(other, time)
        for mine, other in ((a, b), (b, a)):
            carried = mine not in NOT_OBJECTS and self._carried(mine)
            taken = carried and mine == self._target and other == HAND  # the hand takes it
            if not (mine == ROBOT or carried) or other == ROBOT or taken:
                continue
            if other == TABLE and math.isnan(score.table_contact):
                score.table_contact = time
            elif other in (PERSON, HAND) and math.isnan(score.person_contact):
                score.person_contact = time
            elif other not in (TABLE, PERSON, HAND, self._target, ""):
                score.knocked.setdefault(other, time)


class HandoverScorer:
    """A simulator monitor scoring one trial in which the person asks for `target` (by name):
    it reads the plant after each step and hands what it reads to a `TrialWatch`. Given the
    true `table_height` (m), it also compares the robot's perceived table top with it (the
    percepts the planner's scene is built from: a top perceived 9 cm high can send a carry into
    the table)."""

    def __init__(self, simulation: Simulation, target: str, table_height: float = math.nan):
        station = simulation.station
        self._plant = station.plant
        self._watch = TrialWatch(target)
        self._target = target
        self._owner = geometry_owners(station)
        self._target_geometries = {g for g, owner in self._owner.items() if owner == target}
        self._bodies = {name: self._body(instance) for name, instance in station.objects.items()}
        self._station = station.diagram
        self._grip = station.diagram.GetOutputPort(TRUTH_PERSON_GRIP)
        self._next_clearance = 0.0
        robot = self._robot = simulation.robot.diagram
        perceives = robot.HasOutputPort(PERCEIVED_TABLE)
        self._table = robot.GetOutputPort(PERCEIVED_TABLE) if perceives else None
        self._table_height = table_height

    @property
    def score(self) -> TrialScore:
        return self._watch.score

    def _body(self, instance):
        return self._plant.get_body(self._plant.GetBodyIndices(instance)[0])

    def __call__(self, root: Context) -> EventStatus:
        time = root.get_time()
        plant_context = self._plant.GetMyContextFromRoot(root)
        grip = self._grip_now(root) if math.isnan(self.score.gripped) else ""
        poses = {name: body.EvalPoseInWorld(plant_context) for name, body in self._bodies.items()}
        heights = {name: pose.translation()[2] for name, pose in poses.items()}
        up = float(np.clip(poses[self._target].rotation().matrix()[2, 2], -1.0, 1.0))
        tilt = math.degrees(math.acos(up))  # each object stands on its frame's z axis
        self._watch.observe(time, heights, self._contacts(plant_context), grip, tilt)
        if time >= self._next_clearance:
            self._next_clearance = time + CLEARANCE_EVERY_S
            self._clearance(plant_context)
            self._perceived_table(root)
        return EventStatus.Succeeded()

    def _perceived_table(self, root: Context) -> None:
        """Keep the most the robot's perceived table top is off the true height so far."""
        if self._table is None or math.isnan(self._table_height):
            return
        estimate = self._table.Eval(self._robot.GetMyContextFromRoot(root)).estimate
        if estimate is not None:
            error = abs(estimate.height - self._table_height)
            self.score.table_height_error = float(np.fmax(self.score.table_height_error, error))

    def _grip_now(self, root: Context) -> str:
        return self._grip.Eval(self._station.GetMyContextFromRoot(root))

    def _contacts(self, plant_context) -> list[tuple[str, str]]:
        """The owners of each pair of geometries in contact now."""
        results = self._plant.get_contact_results_output_port().Eval(plant_context)
        return [(self._owner.get(a, ""), self._owner.get(b, "")) for a, b in contact_pairs(results)]

    def _clearance(self, plant_context) -> None:
        query = self._plant.get_geometry_query_input_port().Eval(plant_context)
        carried = self._target_geometries if self._watch.carrying() else set()
        score = self.score
        for pair in query.ComputeSignedDistancePairwiseClosestPoints(NEAR):
            for mine, other in ((pair.id_A, pair.id_B), (pair.id_B, pair.id_A)):
                if self._owner.get(mine) != ROBOT and mine not in carried:
                    continue
                owner = self._owner.get(other, "")
                if owner == TABLE:
                    score.clearance_table = min(score.clearance_table, pair.distance)
                elif owner == PERSON:
                    score.clearance_person = min(score.clearance_person, pair.distance)
