"""What the world holds: the table, the objects and the person from a scenario's numbers, and the
robot's and the person's start configurations."""

from __future__ import annotations

import math

import numpy as np
from pydrake.geometry import (
    Box,
    CollisionFilterDeclaration,
    GeometryId,
    GeometrySet,
    LightParameter,
    RenderEngineVtkParams,
)
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import CoulombFriction, MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex

from hsr_handover.hsr import GRIPPER_JOINT, GRIPPER_MIMIC_JOINT, TORSO_JOINT
from hsr_handover.scenario import ActionConfig, Scenario, ScenarioError, object_center
from hsr_handover.world.person.behavior import REACHES, Action, rest_posture
from hsr_handover.world.person.body import BodyDimensions, arm_joint_indices
from hsr_handover.world.person.imprecision import (
    draw_head_fraction,
    draw_pointing_error,
    perturb_direction,
)
from hsr_handover.world.person.pointing_clearance import (
    POINT_CLEAR,
    Upright,
    clear_aim,
    lowering_clearance,
)
from hsr_handover.world.scene.object_models import object_height, object_sdf
from hsr_handover.world.scene.person_model import person_sdf
from hsr_handover.world.scene.table_model import table_sdf

FLOOR_FRICTION = CoulombFriction(0.6, 0.5)
FLOOR_SIZE = (40.0, 40.0, 0.1)  # m: the room's floor, its top at z = 0
PERSON_STREAM = 0x9E4
"""Keys the person's random draws apart from the other users of the run's seed."""
CORRECTION_STREAM = 0x9E5
"""Keys the draws of the person's request made again when the robot lifts another object
(`request_again`): its own, so a script's draws are the same whether or not the person ever
corrects the robot."""
REPEAT_STREAM = 0x9E6
"""Keys the draws of the request repeated when the robot does not respond (`request_again`)."""


def person_pose(scenario: Scenario) -> RigidTransform:
    """Pose of the person frame (floor below the hips, facing +x) in the world."""
    x, y = scenario.person.position
    return RigidTransform(RollPitchYaw(0, 0, scenario.person.yaw), [x, y, 0.0])


def couple_default_positions(
    plant: MultibodyPlant, robot: ModelInstanceIndex, start: dict[str, float]
) -> None:
    """Start coupled joints consistent, or the mimic constraints snap them on the first step."""
    lift = start.get("arm_lift_joint", 0.0)
    plant.GetJointByName(TORSO_JOINT, robot).set_default_positions([0.5 * lift])
    finger = start.get(GRIPPER_JOINT, 0.0)
    plant.GetJointByName(GRIPPER_MIMIC_JOINT, robot).set_default_positions([finger])


def person_actions(scenario: Scenario, body: BodyDimensions) -> list[Action]:
    """The scenario's behaviour script with object names resolved to points in the person frame,
    made as imprecise as `person.imprecision` says: each pointing arm turned off the
    shoulder-to-target ray by its own drawn error (the eyes stay on the target) and raised, if
    need be, until its hand clears the objects (`clear_aim`); such a hand, or one that would
    sweep through an object as the arm lowers (`lowering_clearance`), is withdrawn before the
    arm lowers. Every head turn is short by this person's drawn fraction. The draws come
    from the run's seed.

    The actor is part of the simulated world, so it may know where the objects really are.
    """
    rng = np.random.default_rng([scenario.simulation.seed, PERSON_STREAM])
    head_fraction = draw_head_fraction(rng, scenario.person.imprecision.model())
    return _resolved(scenario, body, scenario.person.behavior, rng, head_fraction)


def last_request(scenario: Scenario) -> ActionConfig | None:
    """The script's last pointing (None when it never points)."""
    requests = [item for item in scenario.person.behavior if item.action == "point_at"]
    return requests[-1] if requests else None


def wanted_object(scenario: Scenario) -> str:
    """The object the script's last pointing asks for ("" when it points at nothing)."""
    point = last_request(scenario)
    return point.target if point is not None else ""


def request_again(scenario: Scenario, body: BodyDimensions, stream: int) -> list[Action]:
    """The script's last request made again, from time 0 (the person asking once more when the
    robot lifts another object, or does not respond): the look at the object, then the
    pointing as long after it and for as long as in the script, with a pointing error of its
    own (drawn from `stream` of the run's seed: CORRECTION_STREAM or REPEAT_STREAM) and this
    person's head fraction. Empty when nothing is asked."""
    point = last_request(scenario)
    if point is None:
        return []
    looks = [item for item in scenario.person.behavior
             if item.action == "look_at" and item.target == point.target
             and item.start <= point.start]  # fmt: skip
    lead = point.start - looks[-1].start if looks else 0.0
    items = [
        ActionConfig("look_at", 0.0, target=point.target),
        ActionConfig("point_at", lead, point.duration, target=point.target, arm=point.arm),
    ]
    person = np.random.default_rng([scenario.simulation.seed, PERSON_STREAM])
    head_fraction = draw_head_fraction(person, scenario.person.imprecision.model())
    rng = np.random.default_rng([scenario.simulation.seed, stream])
    return _resolved(scenario, body, items, rng, head_fraction)


def _resolved(scenario, body, items, rng, head_fraction: float) -> list[Action]:
    """`items` (ActionConfig) as Actions in the person frame, pointing errors drawn from
    `rng` (see `person_actions`)."""
    to_person = person_pose(scenario).inverse()
    centers = {obj.name: object_center(scenario, obj) for obj in scenario.objects}
    uprights = object_uprights(scenario)
    imprecision = scenario.person.imprecision.model()
    actions = []
    for item in items:
        world_point = centers.get(item.target) if item.target else None
        if item.action in REACHES:
            world_point = np.asarray(item.point, dtype=float)
        point = None if world_point is None else to_person @ world_point
        arm_point, withdraw = None, False
        if item.action == "point_at":
            shoulder = body.shoulder(item.arm)
            error = draw_pointing_error(rng, imprecision.pointing_error_deg)
            aimed = shoulder + perturb_direction(point - shoulder, error)
            arm_point = clear_aim(body, item.arm, aimed, uprights)
            rest = rest_posture(body, scenario.table.height)[arm_joint_indices(item.arm)]
            raised = not np.array_equal(arm_point, aimed)  # held over an object
            sweeps = lowering_clearance(body, item.arm, arm_point, rest, uprights) < POINT_CLEAR
            withdraw = raised or sweeps
        end = None if item.duration is None else item.start + item.duration
        actions.append(Action(item.action, item.start, end, point, item.arm, head_fraction,
                              arm_point, withdraw))  # fmt: skip
    return actions


def object_uprights(scenario: Scenario) -> list[Upright]:
    """Each object standing on the table as the cylinder round it, in the person frame (what
    the pointing person keeps the hand clear of)."""
    to_person = person_pose(scenario).inverse()
    uprights = []
    for obj in scenario.objects:
        if obj.shape == "cup":
            radius = obj.size[0] / 2
        else:
            radius = math.hypot(obj.size[0], obj.size[1]) / 2
        bottom = scenario.table.height
        top = bottom + object_height(obj.shape, obj.size)
        xy = (to_person @ object_center(scenario, obj))[:2]
        uprights.append(Upright(xy, radius, bottom, top))
    return uprights


def add_floor(plant: MultibodyPlant) -> GeometryId:
    """The floor, for what falls (collision only: the camera's view is unchanged, and the
    robot and the person are kept off it by `floor_filter`)."""
    # A slab, not a HalfSpace: Drake warns on every build that rigid half spaces do not
    # support deformable contact.
    return plant.RegisterCollisionGeometry(
        plant.world_body(), RigidTransform([0, 0, -FLOOR_SIZE[2] / 2]), Box(*FLOOR_SIZE),
        "floor", FLOOR_FRICTION,
    )  # fmt: skip


def floor_filter(plant: MultibodyPlant, floor: GeometryId, instances) -> CollisionFilterDeclaration:
    """The HSR's base and the person's feet stand on joints, not on the floor: no contact with
    it for the bodies of `instances`."""
    ids = [gid for instance in instances for index in plant.GetBodyIndices(instance)
           for gid in plant.GetCollisionGeometriesForBody(plant.get_body(index))]  # fmt: skip
    return CollisionFilterDeclaration().ExcludeBetween(GeometrySet(floor), GeometrySet(ids))


def add_world(
    plant: MultibodyPlant, parser: Parser, scenario: Scenario, body: BodyDimensions
) -> tuple[ModelInstanceIndex, ModelInstanceIndex, dict[str, ModelInstanceIndex]]:
    """Add the table, the person and the objects; returns their model instances."""
    table = scenario.table
    table_instance = parser.AddModelsFromString(
        table_sdf(*table.size, table.height, table.thickness), "sdf"
    )[0]
    X_WT = RigidTransform(RollPitchYaw(0, 0, table.yaw), [*table.center, 0.0])
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("table", table_instance), X_WT)

    person = parser.AddModelsFromString(person_sdf(body), "sdf")[0]
    plant.WeldFrames(
        plant.world_frame(), plant.GetFrameByName("pelvis", person), person_pose(scenario)
    )
    # The person's muscles hold the limbs wherever the actor puts them; modelling the fight
    # against gravity would only add tracking lag nobody measures.
    plant.set_gravity_enabled(person, False)

    objects = {}
    for obj in scenario.objects:
        instance = parser.AddModelsFromString(
            object_sdf(obj.name, obj.shape, obj.size, obj.color, obj.mass), "sdf"
        )[0]
        pose = RigidTransform(RollPitchYaw(0, 0, obj.yaw), object_center(scenario, obj))
        plant.SetDefaultFloatingBaseBodyPose(plant.GetBodyByName(obj.name, instance), pose)
        objects[obj.name] = instance
    return table_instance, person, objects


def set_default_positions(
    plant: MultibodyPlant,
    instance: ModelInstanceIndex,
    positions: dict[str, float],
    key: str,
    source: str,
) -> None:
    for name, value in positions.items():
        if not plant.HasJointNamed(name, instance):
            raise ScenarioError(source, f"{key}.{name}", "expected a joint name of the model")
        joint = plant.GetJointByName(name, instance)
        lower, upper = joint.position_lower_limits()[0], joint.position_upper_limits()[0]
        if not lower - 1e-9 <= value <= upper + 1e-9:
            raise ScenarioError(
                source, f"{key}.{name}", f"expected a value in [{lower:g}, {upper:g}], got {value}"
            )
        joint.set_default_positions([value])


def render_params() -> RenderEngineVtkParams:
    """Room lighting: a ceiling light plus a dim headlight. With the headlight alone, surfaces
    seen at grazing angles (the table top, the tops of objects) render nearly black."""
    ceiling = LightParameter(
        type="directional", frame="world", direction=[0.2, 0.1, -1.0], intensity=0.9
    )
    headlight = LightParameter(
        type="directional", frame="camera", direction=[0, 0, 1], intensity=0.45
    )
    return RenderEngineVtkParams(lights=[ceiling, headlight])
