"""Feeling the object taken while presenting it (paper 3.3: the robot lets go when the person
holds the object). From the wrist's force sensor, the palm pulled off its command, the
gripper's opening, the hand seen at the object and, once the fingers close on nothing, where
the camera sees the object: whether the person has hold of it (a tug toward them, the palm
drawn in), has taken it (drawn out of the fingers or through them), knocked it, or whether it
was dropped. Plain numpy: `cycle.HandoverCycle` acts on what it says."""

from __future__ import annotations

import dataclasses
import enum
import math

import numpy as np

from hsr_handover.robot.handover.cycle_params import CycleParams
from hsr_handover.robot.handover.cycle_types import Percepts


@dataclasses.dataclass(frozen=True)
class Felt:
    """What one decision feels: the person has `held` of the object (the palm pulled off its
    command, a tug toward them at this decision and the last, or a load pulled across for
    `held_across_s`), or has `taken` it (drawn out
    of the fingers soon after a hand was at it or held it, or drawn through them)."""

    held: bool
    taken: bool


class Emptied(enum.Enum):
    """Fingers closed on nothing while presenting: what became of the object."""

    JUST_NOW = "just now"  # the first decision with the fingers empty: stand still and look
    LOOKING = "looking"  # not yet `empty_s` since: the object may still be falling
    TAKEN = "taken"  # the camera sees it up, in the person's hand
    DROPPED = "dropped"  # the camera sees it down, where it stood or lower
    UNSEEN = "unseen"  # not seen at all: the robot's own hand may hide it in the person's


class TakeDetector:
    """Judges, decision by decision while presenting, whether the person has taken the object.

    Its memory: the load on the wrist as presenting began (`carried_force`, N, world; None
    without the sensor), the width the fingers closed on (`held_width`, m), whether the last
    decision felt a tug, when a hand was last at the object or felt holding it, and when the
    fingers closed on nothing."""

    def __init__(self, carried_force: np.ndarray | None, held_width: float, params: CycleParams):
        self._params = params
        self._carried_force = carried_force
        self._held_width = held_width
        self._tugged = False  # whether the last decision felt a tug
        self._hand_at_object = -math.inf  # when a hand was last seen at, or held, the object
        self._emptied_at: float | None = None  # when the fingers closed on nothing
        self._across_since: float | None = None  # since when a load is pulled across, held

    def feel(self, p: Percepts, person: np.ndarray | None) -> Felt:
        """This decision's verdict on `p`, with `person` the point on the person last seen
        (m, world): the way the object is pulled toward them."""
        params = self._params
        if p.opening >= params.held_opening:
            self._emptied_at = None  # holding (again: a glitch of the opening's sensor)
        if p.hand is not None and p.palm is not None:
            if float(np.linalg.norm(p.hand - p.palm)) <= params.reach:
                self._hand_at_object = p.time
        felt = self.tug(p, person) > params.tug
        tugged, self._tugged = felt and self._tugged, felt  # felt now and at the last decision
        across = p.opening >= params.held_opening and self.pulled_across(p, person)
        if tugged or across:
            self._hand_at_object = p.time
        if not across or self._across_since is None:
            self._across_since = p.time if across else None
        spread = p.opening > self._held_width + params.spread  # a knock forces the fingers apart
        held_across = across and not spread and p.time - self._across_since >= params.held_across_s
        drawn_out = (
            p.opening < params.held_opening and p.time - self._hand_at_object <= params.taken_s
        )
        forced_open = spread and not self.knocked(p, person)
        return Felt(p.pull > params.pull or tugged or held_across, drawn_out or forced_open)

    def tug(self, p: Percepts, person: np.ndarray | None) -> float:
        """N by which the load on the wrist pulls harder toward the `person` than it did as the
        robot began presenting (0 without the sensor or a person seen, or when the change
        points more than `tug_cone_deg` away from the person)."""
        felt = self._load_change(p, person)
        if felt is None:
            return 0.0
        change, toward = felt
        # The force on the wrist points where the load is pulled: toward the person.
        return float(change @ toward) if self._toward(change, toward) else 0.0

    def pulled_across(self, p: Percepts, person: np.ndarray | None) -> bool:
        """Whether the load on the wrist has changed by over `tug` in the horizontal since the
        robot began presenting: something other than gravity has hold of the object."""
        felt = self._load_change(p, person)
        return felt is not None and float(np.linalg.norm(felt[0][:2])) > self._params.tug

    def knocked(self, p: Percepts, person: np.ndarray | None) -> bool:
        """Whether the wrist feels the object knocked rather than drawn: a change of load over
        `tug` that points more than `tug_cone_deg` off the `person` (a hand striking it on its
        way in forces the fingers open too: 18 N sideways)."""
        felt = self._load_change(p, person)
        if felt is None:
            return False
        change, toward = felt
        return float(np.linalg.norm(change)) > self._params.tug and not self._toward(change, toward)

    def emptied(self, p: Percepts, object_start: np.ndarray | None) -> Emptied:
        """Fingers closed on nothing with no hand seen at the object nor tug felt: dropped, or
        taken by a hand out of the camera's sight. The robot holds still for `empty_s`, then
        the camera tells: an object seen up (`seen_up`) is in the person's hand, one seen
        lower has dropped, and one not seen at all may be hidden by the robot's own hand."""
        params = self._params
        just_now = self._emptied_at is None
        if just_now:
            self._emptied_at = p.time
        if p.time - self._emptied_at < params.empty_s:
            return Emptied.JUST_NOW if just_now else Emptied.LOOKING
        if p.object_seen is None:
            return Emptied.UNSEEN
        return Emptied.TAKEN if self.seen_up(p, object_start) else Emptied.DROPPED

    def seen_up(self, p: Percepts, object_start: np.ndarray | None) -> bool:
        """Whether the camera sees the object `still_up` above where it stood (`object_start`,
        m, world; False when that is not known)."""
        seen = p.object_seen
        if seen is None or object_start is None:
            return False
        return bool(seen[2] > object_start[2] + self._params.still_up)

    def _load_change(
        self, p: Percepts, person: np.ndarray | None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The change of the load on the wrist (N) since the robot began presenting, and the
        unit direction from the palm to the person; None without the sensor or a person seen."""
        known = (p.wrist_force, self._carried_force, person, p.palm)
        if any(value is None for value in known):
            return None
        toward = person - p.palm
        distance = float(np.linalg.norm(toward))
        if distance == 0.0:
            return None
        return p.wrist_force - self._carried_force, toward / distance

    def _toward(self, change: np.ndarray, toward: np.ndarray) -> bool:
        """Whether the force `change` points within `tug_cone_deg` of the unit direction
        `toward`."""
        along = float(change @ toward)
        cone = math.cos(math.radians(self._params.tug_cone_deg))
        return along >= cone * float(np.linalg.norm(change))
