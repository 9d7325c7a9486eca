"""The planning scene: a MultibodyPlant of its own holding the HSR and, as fixed collision
geometry, what the robot perceives (docs/design.md §3.4). Never the simulation's plant: that is
truth.

The table is a solid block from the floor to its fitted top (the camera cannot see under it,
so no plan goes there); each object a cylinder or box; the person a capsule per bone. Table and
objects are widened by TABLE_MARGIN and OBJECT_MARGIN, the person's capsules by their own
margin. The HSR's own links do not collide with one another here: the arm's joint limits keep
it off its body.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Hashable, Iterable, Iterator, Mapping, Sequence

import numpy as np
from pydrake.geometry import (
    Box,
    CollisionFilterDeclaration,
    Cylinder,
    GeometryId,
    GeometryInstance,
    GeometrySet,
    ProximityProperties,
    QueryObject,
    Shape,
)
from pydrake.geometry import Capsule as CapsuleShape
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, CoulombFriction, MultibodyPlant
from pydrake.multibody.tree import Body
from pydrake.systems.framework import Context, DiagramBuilder

from hsr_handover.hsr import (
    GRIPPER_JOINT,
    GRIPPER_MIMIC_JOINT,
    PALM_FRAME,
    TORSO_JOINT,
    TORSO_PER_LIFT,
    add_hsr,
    hsr_set_positions,
)
from hsr_handover.robot.perception.object_detection import label_colour
from hsr_handover.robot.perception.object_shapes import CYLINDER, ObjectShape
from hsr_handover.robot.perception.table_fit import TableEstimate
from hsr_handover.robot.planning.perceived_scene import Capsule, PerceivedScene
from hsr_handover.robot.planning.upright import Upright, upright_for

PLANNING_TIME_STEP = 0.01  # s: the HSR's mimic couplings need a discrete plant; never stepped
TABLE, PERSON, HELD = "table", "person", "held"
NEAR = 0.5  # m: distances beyond this are not computed
TABLE_MARGIN = 0.01
"""m added round the table's sides and top: the fit is good to about a centimetre."""
OBJECT_MARGIN = 0.02
"""m added round each object's sides and top: an object is sized from the side the camera
sees, and its back, hidden, can be 2 cm deeper than seen (a hand on its way to a cup's
pre-grasp came within 0.5 cm of it with 1 cm here)."""
HELD_MARGIN = 0.02
"""m added round a held object's sides and top beyond OBJECT_MARGIN, and the two of them under
it: the grip can turn, shift and tilt it in the fingers, and the shape perceived at the grasp,
from the camera's side, is the smaller (a box can sag 1.4 cm and tilt 13 degrees in the fingers
as a carry sets off). The held object's second detection (`seen_in_hand`) and a start allowance
only for the parts and obstacles the start touches (`trajectory.StartContact`) keep a carried
box off its neighbours."""
HELD_SPREAD = OBJECT_MARGIN + HELD_MARGIN  # m the held solid reaches past the object's sides


def _table_block(table: TableEstimate) -> tuple[Shape, RigidTransform]:
    height = table.height + TABLE_MARGIN
    pose = RigidTransform(RotationMatrix.MakeZRotation(table.yaw), [*table.center, height / 2])
    return Box(*(table.size + 2 * TABLE_MARGIN), height), pose


def _object_solid(
    shape: ObjectShape, margin: float = OBJECT_MARGIN, below: float = 0.0
) -> tuple[Shape, RigidTransform]:
    """The object widened by `margin` round its sides and top and by `below` under it."""
    height = shape.height + margin + below
    center = [*shape.center, shape.bottom - below + height / 2]
    pose = RigidTransform(RotationMatrix.MakeZRotation(shape.yaw), center)
    if shape.kind == CYLINDER:
        return Cylinder(shape.radius + margin, height), pose
    return Box(*(shape.size + 2 * margin), height), pose


def _capsule_solid(capsule: Capsule) -> tuple[Shape, RigidTransform]:
    axis = capsule.end - capsule.start
    rotation = RotationMatrix.MakeFromOneVector(axis if capsule.length > 1e-9 else [0, 0, 1], 2)
    pose = RigidTransform(rotation, (capsule.start + capsule.end) / 2)
    return CapsuleShape(capsule.radius, capsule.length), pose


class PlanningScene:
    """The HSR and the perceived scene in a plant built for planning queries.

    `plant`, `scene_graph`, `diagram` and a `context` (with `plant_context`) to query; the
    HSR's model instance is `robot`. `geometry` maps each obstacle's name (TABLE, an object's
    label, or PERSON) to its geometry ids.
    """

    def __init__(self, scene: PerceivedScene):
        builder = DiagramBuilder()
        plant, scene_graph = AddMultibodyPlantSceneGraph(builder, PLANNING_TIME_STEP)
        self.plant: MultibodyPlant = plant
        self.scene_graph = scene_graph
        self.robot = add_hsr(plant, Parser(plant))
        self.scene = scene
        self.geometry: dict[str, list[GeometryId]] = {}
        self.upright: Upright | None = None  # the held object's, while `holding`
        if scene.table is not None:
            self._add(TABLE, *_table_block(scene.table))
        for shape in scene.objects:
            self._add(shape.label, *_object_solid(shape))
        for capsule in scene.person:
            self._add(PERSON, *_capsule_solid(capsule))
        plant.Finalize()
        self._owner = {gid: name for name, ids in self.geometry.items() for gid in ids}
        bodies = [plant.get_body(body) for body in plant.GetBodyIndices(self.robot)]
        self._robot_ids = [g for b in bodies for g in plant.GetCollisionGeometriesForBody(b)]
        self.robot_geometry = GeometrySet(self._robot_ids)
        scene_graph.collision_filter_manager().Apply(
            CollisionFilterDeclaration().ExcludeWithin(self.robot_geometry)
        )
        self.diagram = builder.Build()
        self.context = self.diagram.CreateDefaultContext()
        self.plant_context = plant.GetMyMutableContextFromRoot(self.context)
        self._scene_graph_context = scene_graph.GetMyMutableContextFromRoot(self.context)

    def _add(self, name: str, shape: Shape, pose: RigidTransform) -> None:
        index = sum(len(ids) for ids in self.geometry.values())
        gid = self.plant.RegisterCollisionGeometry(
            self.plant.world_body(), pose, shape, f"{name}_{index}", CoulombFriction(0.5, 0.5)
        )
        self.geometry.setdefault(name, []).append(gid)

    def set_positions(self, positions: Mapping[str, float]) -> None:
        """Put the HSR in a configuration (actuated joint names, or "gripper" for the opening;
        the torso follows the arm lift), held within the joints' limits."""
        hsr_set_positions(self.plant, self.plant_context, self.robot, positions)
        # Sensors read a hair outside a limit (a finger at -1e-23 m): the planner starts inside.
        q = self.plant.GetPositions(self.plant_context)
        lower, upper = self.plant.GetPositionLowerLimits(), self.plant.GetPositionUpperLimits()
        self.plant.SetPositions(self.plant_context, np.clip(q, lower, upper))

    def index(self, joint: str) -> int:
        """The joint's index in the plant's position vector (not the joint order)."""
        return self.plant.GetJointByName(joint, self.robot).position_start()

    def positions(self) -> np.ndarray:
        return self.plant.GetPositions(self.plant_context).copy()

    def couplings(self) -> tuple[np.ndarray, np.ndarray]:
        """(A, b) with A q = b: the torso at half the arm lift, the right finger with the left
        (the plant's mimic joints, which optimisation does not see)."""
        rows = []
        for follower, leader, ratio in ((TORSO_JOINT, "arm_lift_joint", TORSO_PER_LIFT),
                                        (GRIPPER_MIMIC_JOINT, GRIPPER_JOINT, 1.0)):  # fmt: skip
            row = np.zeros(self.plant.num_positions())
            row[self.index(follower)], row[self.index(leader)] = 1.0, -ratio
            rows.append(row)
        return np.array(rows), np.zeros(len(rows))

    def moving_parts(self) -> list[GeometryId]:
        """The HSR's collision geometries and the object it holds, if any."""
        return [*self._robot_ids, *self.geometry.get(HELD, [])]

    def _moving(self) -> GeometrySet:
        return GeometrySet(self.moving_parts())

    def obstacles_but(self, names: Iterable[str]) -> list[str]:
        """The scene's obstacles other than those named (the held object is the robot's)."""
        left_out = set(names)
        return [name for name in self.geometry if name not in left_out and name != HELD]

    def _obstacle_set(self, names: Iterable[str]) -> GeometrySet:
        return GeometrySet([gid for name in names for gid in self.geometry.get(name, [])])

    def _excluding(self, names: Sequence[str]) -> CollisionFilterDeclaration:
        return CollisionFilterDeclaration().ExcludeBetween(
            self._moving(), self._obstacle_set(names)
        )

    @contextlib.contextmanager
    def ignoring(self, names: Sequence[str]) -> Iterator[None]:
        """Within the block, the HSR and the object it holds do not collide with the obstacles
        named (a target being grasped, the object held): distance queries and constraints
        leave them out."""
        manager = self.scene_graph.collision_filter_manager(self._scene_graph_context)
        handle = manager.ApplyTransient(self._excluding(names))
        try:
            yield
        finally:
            manager.RemoveDeclaration(handle)

    def ignoring_context(self, names: Sequence[str]) -> tuple[Context, Context]:
        """A copy of the scene's context (the HSR as it is, any object held, the obstacles
        ignored now) in which the obstacles named are left out too, for good: for constraints
        that must see other obstacles than the scene's own context does. Returns the copy and
        its plant context; keep the copy alive while the plant context is used."""
        return self._filtered_copy(self._excluding(names))

    def pairs_context(
        self, pairs: Iterable[tuple[GeometryId, str]], only: bool
    ) -> tuple[Context, Context]:
        """As `ignoring_context`, a copy of the scene's context that sees, of the (part,
        obstacle) `pairs` (a part of `moving_parts` and an obstacle's name), only those pairs
        (`only`) or everything but them."""
        touching: dict[str, set[GeometryId]] = {}
        for part, name in pairs:
            touching.setdefault(name, set()).add(part)
        declaration = CollisionFilterDeclaration()
        if only:
            declaration.ExcludeBetween(
                self._moving(), self._obstacle_set(self.obstacles_but(touching))
            )
        for name, parts in touching.items():
            excluded = [p for p in self.moving_parts() if p not in parts] if only else parts
            declaration.ExcludeBetween(GeometrySet(list(excluded)), self._obstacle_set([name]))
        return self._filtered_copy(declaration)

    def _filtered_copy(self, declaration: CollisionFilterDeclaration) -> tuple[Context, Context]:
        """A copy of the scene's context with `declaration` applied on top of the filters it
        holds (the copy may hold transient ones), and the copy's plant context."""
        root = self.context.Clone()
        scene_graph_context = self.scene_graph.GetMyMutableContextFromRoot(root)
        self.scene_graph.collision_filter_manager(scene_graph_context).ApplyTransient(declaration)
        return root, self.plant.GetMyMutableContextFromRoot(root)

    @contextlib.contextmanager
    def holding(
        self,
        label: str,
        q_grasp: np.ndarray,
        shape: ObjectShape | None = None,
        q_now: np.ndarray | None = None,
    ) -> Iterator[None]:
        """Within the block, the perceived object `label` moves with the hand, as it sat in the
        hand closed on it at `q_grasp` (plant positions): its solid hangs on the palm's body,
        an obstacle to all but the robot, and its copy in the scene is left out. `shape` is
        the object as perceived when grasped (default: as perceived now, which is right only
        while it still stands where the hand closed on it), widened by HELD_SPREAD all round,
        underneath too. With the HSR's positions now, `q_now`, the detections that are the
        held object seen again where it is now (`seen_in_hand`) are left out too. An object
        not in the scene and without a `shape` changes nothing. Every IK and path within the
        block keeps the object up (`upright`)."""
        shape = self.scene.object_named(label) if shape is None else shape
        if shape is None:
            yield
            return
        X_WH = self.hand_pose(q_grasp)
        seen = () if q_now is None else self.seen_in_hand(shape, X_WH, q_now)
        solid, X_WO = _object_solid(shape, HELD_SPREAD, below=HELD_SPREAD)
        instance = GeometryInstance(X_WH.inverse() @ X_WO, solid, f"held_{label}")
        instance.set_proximity_properties(ProximityProperties())
        source = self.plant.get_source_id()
        hand = self.hand()
        held = self.scene_graph.RegisterGeometry(
            self._scene_graph_context, source, self.plant.GetBodyFrameIdOrThrow(hand.index()),
            instance,
        )  # fmt: skip
        manager = self.scene_graph.collision_filter_manager(self._scene_graph_context)
        handle = manager.ApplyTransient(
            CollisionFilterDeclaration().ExcludeBetween(self.robot_geometry, GeometrySet([held]))
        )
        self.geometry[HELD] = [held]
        self.upright = upright_for(shape, X_WH.rotation().matrix())
        try:
            with self.ignoring((label, *seen)):
                yield
        finally:
            self.upright = None
            del self.geometry[HELD]
            manager.RemoveDeclaration(handle)
            self.scene_graph.RemoveGeometry(self._scene_graph_context, source, held)

    def hand(self) -> Body:
        """The body that PALM_FRAME is on: a held object hangs on it."""
        return self.plant.GetFrameByName(PALM_FRAME, self.robot).body()

    def hand_pose(self, q: np.ndarray) -> RigidTransform:
        """The hand's body (`_hand`) in the world with the HSR at `q`; the scene's own positions
        are left as they were."""
        positions = self.positions()
        self.plant.SetPositions(self.plant_context, q)
        X_WH = self.hand().EvalPoseInWorld(self.plant_context)
        self.plant.SetPositions(self.plant_context, positions)
        return X_WH

    def seen_in_hand(
        self, shape: ObjectShape, X_WH_grasp: RigidTransform, q_now: np.ndarray
    ) -> tuple[str, ...]:
        """The labels of the perceived objects that are `shape`, held since the hand closed on
        it with its frame at `X_WH_grasp`, seen again where the hand has it at `q_now`: each
        one whose footprint's centre lies within the held object's and whose top rises above
        its bottom. (Lifted, the camera sees it as a column from the table up to its top, and
        as a new detection when the old one is remembered where it stood.)"""
        X_WH_now = self.hand_pose(q_now)
        centre = X_WH_now @ (X_WH_grasp.inverse() @ shape.centroid)
        bottom = centre[2] - shape.height / 2
        return tuple(
            seen.label
            for seen in self._others_within(shape, centre[:2])
            if seen.bottom + seen.height > bottom
        )

    def seen_where_it_stood(self, shape: ObjectShape) -> tuple[str, ...]:
        """The labels of the perceived objects of `shape`'s colour, other than `shape`, whose
        footprint's centre lies within its footprint where it stood: the object itself,
        remembered there from a view in which the arm split its blob in two (a second label),
        which a put back would otherwise meet at the very place it puts the object."""
        colour = label_colour(shape.label)
        return tuple(
            seen.label
            for seen in self._others_within(shape, shape.center)
            if label_colour(seen.label) == colour
        )

    def _others_within(self, shape: ObjectShape, centre: np.ndarray) -> list[ObjectShape]:
        """The perceived objects but `shape` whose footprint's centre lies within `shape`'s
        footprint (its radius) round `centre` (x, y)."""
        return [seen for seen in self.scene.objects if seen.label != shape.label
                and np.hypot(*(seen.center - centre)) < shape.radius]  # fmt: skip

    def query(self) -> QueryObject:
        return self.plant.get_geometry_query_input_port().Eval(self.plant_context)

    def clearance_at(
        self, q: np.ndarray, ignore: tuple[str, ...] = (), within: float = NEAR
    ) -> float:
        """The least signed distance (m) with the HSR put at `q` (plant positions); inf when
        nothing is within `within` (`clearances`)."""
        self.plant.SetPositions(self.plant_context, q)
        return self.clearance(ignore, within)[0]

    def clearance(self, ignore: tuple[str, ...] = (), within: float = NEAR) -> tuple[float, str]:
        """The least signed distance (m) between the HSR (and the object it holds) and any
        obstacle but those named in `ignore`, and that obstacle's name; (inf, "") when nothing
        is within `within` (`clearances`)."""
        distances = self.clearances(ignore, within)
        nearest = min(distances, key=distances.get, default="")
        return distances.get(nearest, math.inf), nearest

    def part_clearances_at(
        self, q: np.ndarray, ignore: tuple[str, ...] = (), within: float = NEAR
    ) -> dict[tuple[GeometryId, str], float]:
        """`part_clearances` with the HSR put at `q` (plant positions)."""
        self.plant.SetPositions(self.plant_context, q)
        return self.part_clearances(ignore, within)

    def part_clearances(
        self, ignore: tuple[str, ...] = (), within: float = NEAR
    ) -> dict[tuple[GeometryId, str], float]:
        """`clearances` by (part, obstacle): the least signed distance between each of
        `moving_parts` and each obstacle within `within` of each other."""
        return _least(((part, name), d) for part, name, d in self._pairs(ignore, within))

    def _pairs(self, ignore: tuple[str, ...], within: float):
        """(part, obstacle's name, signed distance) of each pair within `within` (m), the
        obstacles in `ignore` left out."""
        for pair in self.query().ComputeSignedDistancePairwiseClosestPoints(within):
            obstacle, part = self._owner.get(pair.id_A), pair.id_B
            if obstacle is None:
                obstacle, part = self._owner.get(pair.id_B), pair.id_A
            if obstacle is not None and obstacle not in ignore:
                yield part, obstacle, pair.distance

    def clearances_at(
        self, q: np.ndarray, ignore: tuple[str, ...] = (), within: float = NEAR
    ) -> dict[str, float]:
        """`clearances` with the HSR put at `q` (plant positions)."""
        self.plant.SetPositions(self.plant_context, q)
        return self.clearances(ignore, within)

    def clearances(self, ignore: tuple[str, ...] = (), within: float = NEAR) -> dict[str, float]:
        """The least signed distance (m) between the HSR (and the object it holds) and each
        obstacle within `within` (m, at most NEAR) but those named in `ignore`, by the
        obstacle's name. A caller that compares distances with a bound asks only `within` it:
        Drake then computes fewer pairs. The obstacles ignored are dropped from the pairs
        rather than filtered out of the query: a transient collision filter applied and
        removed per query cost a third of it, and the pairs left are the same."""
        return _least((name, d) for _, name, d in self._pairs(ignore, within))


def _least(distances: Iterable[tuple[Hashable, float]]) -> dict:
    """The least distance by key of (key, distance) pairs."""
    least: dict = {}
    for key, distance in distances:
        if distance < least.get(key, math.inf):
            least[key] = distance
    return least
