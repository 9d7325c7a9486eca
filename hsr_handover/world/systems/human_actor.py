"""HumanActor: the scripted person as a Drake system, who may also take what the robot offers."""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import GeometryId
from pydrake.math import RigidTransform
from pydrake.multibody.plant import ContactResults
from pydrake.systems.framework import BasicVector, Context, LeafSystem, State

from hsr_handover.systems.contact_pairs import contact_pairs
from hsr_handover.world.person.behavior import PostureTimeline
from hsr_handover.world.person.body import PERSON_JOINTS
from hsr_handover.world.person.correcting import Corrector
from hsr_handover.world.person.receiving import Receiver, Receiving
from hsr_handover.world.person.repeating import Repeater

RECEIVING_PERIOD = 0.05  # s between the person's looks at the world while waiting to take


@dataclasses.dataclass(frozen=True)
class WorldBodies:
    """Where the receiving person looks in the plant's body poses: its hands by arm ("right",
    "left"; the hand's middle `hand_middle` m below the hand body's origin, the wrist), the
    objects by name, the person
    frame's pose `X_WP`, and the robot's `gripper` (capsules: body, two ends in it, radius);
    and in its contact results, the hands' geometries and each object's (`touch`: geometry
    id to "" for a hand, or the object's name)."""

    hands: dict[str, int]
    hand_middle: float
    objects: dict[str, int]
    X_WP: RigidTransform
    gripper: tuple[tuple[int, np.ndarray, np.ndarray, float], ...] = ()
    touch: dict[GeometryId, str] = dataclasses.field(default_factory=dict)

    def touching(self, results: ContactResults) -> frozenset[str]:
        """The objects a hand touches in `results`."""
        touched = set()
        for a, b in contact_pairs(results):
            owners = {self.touch.get(a), self.touch.get(b)}
            if "" in owners:
                touched |= owners - {"", None}
        return frozenset(touched)


@dataclasses.dataclass
class PersonActing:
    """What the person is doing: the posture timeline and the parts of their behaviour that
    react to the robot (taking what it holds out, correcting it, asking again)."""

    timeline: PostureTimeline
    receiver: Receiver | None
    corrector: Corrector | None = None
    repeater: Repeater | None = None

    def __deepcopy__(self, memo: dict) -> PersonActing:
        """Drake copies the state at every update: the timeline is never changed once made
        (`interrupted` makes a new one), so the copies share it."""
        return PersonActing(
            self.timeline,
            copy.deepcopy(self.receiver, memo),
            copy.deepcopy(self.corrector, memo),
            copy.deepcopy(self.repeater, memo),
        )


class HumanActor(LeafSystem):
    """Turns the person's behaviour timeline into desired joint states for the plant's PD.

    Output `person_desired_state`: [q; v] of the person's actuated joints, ordered as
    `joint_order` (the plant's actuator order for the person). With a `receiver` (and the
    `world` bodies it watches), input `body_poses` (the plant's) lets the person react: the
    receiver's postures interrupt the script, and output `grip` names the object the hand
    holds ("" for none). Input `contact_results` (the plant's; optional) tells what the hand
    touches: the hand closes on what it reaches for when it strikes it. With a `corrector`
    (which needs the receiver's inputs too) the person asks again when the robot lifts an
    object other than the one asked for; with a `repeater` (the same), when the robot's
    hand (the first of the `world`'s gripper capsules) stays still after the request.
    """

    def __init__(
        self,
        timeline: PostureTimeline,
        joint_order: Sequence[str],
        receiver: Receiver | None = None,
        world: WorldBodies | None = None,
        corrector: Corrector | None = None,
        repeater: Repeater | None = None,
    ):
        super().__init__()
        unknown = [name for name in joint_order if name not in PERSON_JOINTS]
        if unknown:
            raise ValueError(f"joint_order: expected names from PERSON_JOINTS, got {unknown}")
        if (receiver is None) != (world is None):
            raise ValueError("receiver and world: expected both or neither")
        for name, watcher in (("corrector", corrector), ("repeater", repeater)):
            if watcher is not None and receiver is None:
                raise ValueError(f"{name}: expected a receiver and world beside it")
        if repeater is not None and not world.gripper:
            raise ValueError("repeater: expected the world's gripper capsules to watch")
        self._order = np.array([PERSON_JOINTS.index(name) for name in joint_order])
        self._world = world
        self._acting = self.DeclareAbstractState(
            AbstractValue.Make(PersonActing(timeline, receiver, corrector, repeater))
        )
        self.DeclareVectorOutputPort(
            "person_desired_state", 2 * len(self._order), self._calc_desired_state
        )
        self.DeclareAbstractOutputPort("grip", lambda: AbstractValue.Make(""), self._calc_grip)
        self.DeclareVectorOutputPort("repeated_at", 1, self._calc_repeated_at)
        if receiver is not None:
            self._poses = self.DeclareAbstractInputPort(
                "body_poses", AbstractValue.Make([RigidTransform()])
            )
            self._contacts = self.DeclareAbstractInputPort(
                "contact_results", AbstractValue.Make(ContactResults())
            )
            self.DeclarePeriodicUnrestrictedUpdateEvent(RECEIVING_PERIOD, 0.0, self._react)

    def _react(self, context: Context, state: State) -> None:
        acting: PersonActing = state.get_mutable_abstract_state(self._acting).get_value()
        world, poses = self._world, self._poses.Eval(context)
        X_PW = world.X_WP.inverse()
        objects = {name: X_PW @ poses[index].translation()
                   for name, index in world.objects.items()}  # fmt: skip
        hand_body = poses[world.hands[acting.receiver.arm]]
        hand = X_PW @ (hand_body @ np.array([0.0, 0.0, -world.hand_middle]))
        gripper = [(X_PW @ (poses[body] @ start), X_PW @ (poses[body] @ end), radius)
                   for body, start, end, radius in world.gripper]  # fmt: skip
        time = context.get_time()
        posture = acting.timeline.evaluate(time)[0]
        touching = (
            self._touching(context) if acting.receiver.state is Receiving.REACHING else frozenset()
        )
        changes = acting.receiver.update(time, objects, hand, gripper, posture, touching)
        if acting.corrector is not None:
            changes = changes + acting.corrector.update(time, objects)
        if acting.repeater is not None:
            changes = changes + acting.repeater.update(time, gripper[0][0])
        for start, goal in sorted(changes, key=_start):
            acting.timeline = acting.timeline.interrupted(start, goal)

    def _touching(self, context: Context) -> frozenset[str]:
        if not self._contacts.HasValue(context):
            return frozenset()
        return self._world.touching(self._contacts.Eval(context))

    def _calc_desired_state(self, context: Context, output: BasicVector) -> None:
        timeline = context.get_abstract_state(self._acting).get_value().timeline
        q, v = timeline.evaluate(context.get_time())
        output.SetFromVector(np.concatenate([q[self._order], v[self._order]]))

    def acting(self, context: Context) -> PersonActing:
        """The person's behaviour in `context` (for scoring and tests; the robot reads only
        the station's sensor ports)."""
        return context.get_abstract_state(self._acting).get_value()

    def _calc_repeated_at(self, context: Context, output: BasicVector) -> None:
        repeater = context.get_abstract_state(self._acting).get_value().repeater
        at = None if repeater is None else repeater.repeated_at
        output.SetAtIndex(0, math.nan if at is None else at)

    def _calc_grip(self, context: Context, output: AbstractValue) -> None:
        receiver = context.get_abstract_state(self._acting).get_value().receiver
        output.set_value("" if receiver is None else receiver.grip)


def _start(change: tuple[float, np.ndarray]) -> float:
    return change[0]
