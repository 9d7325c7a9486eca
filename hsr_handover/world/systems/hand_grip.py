"""HandGrip: the person's hand closing on an object, as a stiff spring and damper between the
hand and the object (a soft weld), switched on by the actor's `grip` output.

Drake 1.51's constraints are switched in the plant's context, which no system in the diagram
may change, and a constraint built active would hold every object from the first step in any
context not set up by hand; a force through the plant's `applied_spatial_force` port is
dataflow like the rest of the world.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce, SpatialVelocity
from pydrake.multibody.plant import ExternallyAppliedSpatialForce
from pydrake.multibody.tree import BodyIndex
from pydrake.systems.framework import Context, LeafSystem, State

GRIP_PERIOD = 0.01  # s between checks of the actor's grip
GRIP_FREQUENCY = 40.0
"""rad/s: the natural frequency of the hold, critically damped. The spring and the damper
scale with the object's own mass and inertia, so every object sags the same 6 mm in the hand
(g / GRIP_FREQUENCY^2) and turns back as fast. The force is explicit (the plant sees it one
step late): it stays stable while the frequency times the plant's step is well under 1, which
fixed gains (5 N m/rad, 0.1 N m s/rad) were not for a 0.2 kg cup at a 4 ms step."""


@dataclasses.dataclass(frozen=True)
class GrippedBody:
    """An object the hand may close on: its body index in the plant, mass (kg) and rotational
    inertia about its origin in its own frame (kg m^2, 3 x 3)."""

    index: int
    mass: float
    inertia: np.ndarray


@dataclasses.dataclass(frozen=True)
class _Hold:
    name: str = ""
    hand: int = -1  # the body index of the hand that closed on it
    X_HO: RigidTransform | None = None  # the object in the hand as the hand closed

    def __deepcopy__(self, memo: dict) -> _Hold:
        # Never changed once made (a new hold replaces it): Drake copies the state at each of
        # the 100 checks a second, and a deep copy cost as much as the check.
        return self


class HandGrip(LeafSystem):
    """Inputs `grip` (the object's name or ""), `body_poses` and `body_spatial_velocities`
    (the plant's); output `spatial_forces` for the plant's applied_spatial_force input.
    `hands` are the hands' body indices (the one nearest the object closes on it), `objects`
    what they may hold, by name."""

    def __init__(self, hands: tuple[int, ...], objects: dict[str, GrippedBody]):
        super().__init__()
        if not hands:
            raise ValueError("hands: expected at least one hand's body index")
        self._hands, self._objects = tuple(hands), dict(objects)
        self._grip = self.DeclareAbstractInputPort("grip", AbstractValue.Make(""))
        self._poses = self.DeclareAbstractInputPort(
            "body_poses", AbstractValue.Make([RigidTransform()])
        )
        self._velocities = self.DeclareAbstractInputPort(
            "body_spatial_velocities", AbstractValue.Make([SpatialVelocity()])
        )
        self._hold = self.DeclareAbstractState(AbstractValue.Make(_Hold()))
        self.DeclareAbstractOutputPort(
            "spatial_forces",
            lambda: AbstractValue.Make([ExternallyAppliedSpatialForce()]),
            self._calc_forces,
        )
        self.DeclarePeriodicUnrestrictedUpdateEvent(GRIP_PERIOD, 0.0, self._latch)

    def _latch(self, context: Context, state: State) -> None:
        name = self._grip.Eval(context)
        hold = context.get_abstract_state(self._hold).get_value()
        if name == hold.name:
            return
        if name not in self._objects:
            state.get_mutable_abstract_state(self._hold).set_value(_Hold())
            return
        poses = self._poses.Eval(context)
        X_WO = poses[self._objects[name].index]
        hand = min(self._hands, key=lambda index: np.linalg.norm(
            poses[index].translation() - X_WO.translation()))  # fmt: skip
        X_HO = poses[hand].inverse() @ X_WO
        state.get_mutable_abstract_state(self._hold).set_value(_Hold(name, hand, X_HO))

    def _calc_forces(self, context: Context, output: AbstractValue) -> None:
        hold = context.get_abstract_state(self._hold).get_value()
        if not hold.name:
            output.set_value([])
            return
        held = self._objects[hold.name]
        obj, hand = held.index, hold.hand
        poses, velocities = self._poses.Eval(context), self._velocities.Eval(context)
        X_WH, X_WO = poses[hand], poses[obj]
        X_WT = X_WH @ hold.X_HO  # where the hand holds it
        V_H, V_O = velocities[hand], velocities[obj]
        p_HT = X_WT.translation() - X_WH.translation()
        v_T = V_H.translational() + np.cross(V_H.rotational(), p_HT)
        k, c = GRIP_FREQUENCY**2, 2.0 * GRIP_FREQUENCY  # per unit mass or inertia
        force = held.mass * (
            k * (X_WT.translation() - X_WO.translation()) + c * (v_T - V_O.translational())
        )
        turn = (X_WT.rotation() @ X_WO.rotation().inverse()).ToAngleAxis()
        R_WO = X_WO.rotation().matrix()
        inertia_W = R_WO @ held.inertia @ R_WO.T
        torque = inertia_W @ (
            k * turn.angle() * turn.axis() + c * (V_H.rotational() - V_O.rotational())
        )
        on_object = _applied(obj, SpatialForce(torque, force))
        # Equal and opposite on the hand, at the object's origin.
        p_HO = X_WH.rotation().inverse() @ (X_WO.translation() - X_WH.translation())
        on_hand = _applied(hand, SpatialForce(-torque, -force), p_HO)
        output.set_value([on_object, on_hand])


def _applied(
    body: int, F_W: SpatialForce, p_B: np.ndarray | None = None
) -> ExternallyAppliedSpatialForce:
    applied = ExternallyAppliedSpatialForce()
    applied.body_index = BodyIndex(body)
    applied.p_BoBq_B = np.zeros(3) if p_B is None else p_B
    applied.F_Bq_W = F_W
    return applied
