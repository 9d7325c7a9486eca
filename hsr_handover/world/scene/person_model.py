"""An articulated adult for the table scene, built from `BodyDimensions`.

The pelvis link carries the rigid trunk, legs and (when seated) a chair; the station welds it
to the world. The head turns on a two-joint neck (yaw, pitch); each arm has a three-joint
shoulder, an elbow and a wrist. Every joint is PD-driven through the plant's desired-state
input. All links are posed at the all-zero posture (arms hanging), so each joint frame sits at
its child link's origin. Frames `coco_<keypoint>` mark the OpenPose COCO-18 keypoints.
"""

from __future__ import annotations

import numpy as np

from hsr_handover.world.person.behavior import joint_limits
from hsr_handover.world.person.body import (
    FOREARM_RADIUS,
    HAND_THICKNESS,
    HAND_WIDTH,
    UPPER_ARM_RADIUS,
    BodyDimensions,
)
from hsr_handover.world.scene.sdf_shapes import (
    box_geometry,
    box_inertia,
    capsule_shape,
    coarse_sphere,
    cylinder_inertia,
    fmt,
    inertial,
    model,
    shape,
    sphere_shape,
    visual,
)

SKIN = (0.87, 0.70, 0.58, 1.0)
SHIRT = (0.45, 0.47, 0.50, 1.0)
TROUSERS = (0.15, 0.17, 0.22, 1.0)
CHAIR = (0.30, 0.24, 0.18, 1.0)
EYE = (0.08, 0.06, 0.05, 1.0)

# PD gains per joint (Nm/rad, Nm s/rad): stiff enough to follow the actor within a degree.
NECK_GAINS = (40.0, 4.0)
ARM_GAINS = (120.0, 8.0)
EFFORT = 80.0


def _link(name: str, origin: np.ndarray, mass: float, moments, body: str = "") -> str:
    return (
        f'<link name="{name}"><pose>{fmt((*origin, 0, 0, 0))}</pose>'
        f"{inertial(mass, moments)}{body}</link>"
    )


def _revolute(name: str, parent: str, child: str, axis, gains) -> str:
    lower, upper = joint_limits(name)
    return (
        f'<joint name="{name}" type="revolute"><parent>{parent}</parent><child>{child}</child>'
        f"<axis><xyz>{fmt(axis)}</xyz><limit><lower>{lower}</lower><upper>{upper}</upper>"
        f"<effort>{EFFORT}</effort><velocity>6</velocity></limit>"
        f"<dynamics><damping>0.5</damping></dynamics></axis>"
        f'<drake:controller_gains p="{gains[0]}" d="{gains[1]}"/></joint>'
    )


def _frame(name: str, link: str, position: np.ndarray, link_origin: np.ndarray) -> str:
    return (
        f'<frame name="coco_{name}" attached_to="{link}">'
        f'<pose relative_to="{link}">{fmt((*(position - link_origin), 0, 0, 0))}</pose></frame>'
    )


def _segment(name: str, start: np.ndarray, end: np.ndarray, radius: float, rgba) -> str:
    """A capsule from start to end, in the pelvis frame (which is the model frame at rest)."""
    middle, axis = (start + end) / 2, end - start
    length = float(np.linalg.norm(axis))
    pitch = float(np.arccos(np.clip(axis[2] / length, -1, 1)))
    yaw = float(np.arctan2(axis[1], axis[0]))
    return capsule_shape(name, radius, length, (*middle, 0, pitch, yaw), rgba)


def _pelvis(body: BodyDimensions) -> str:
    trunk_height = body.shoulder_z - body.hip_z + 0.05
    trunk_size = (0.22, 2 * body.shoulder_half_width - 0.06, trunk_height)
    geometry = shape(
        "trunk",
        box_geometry(trunk_size),
        (0, 0, body.hip_z + trunk_height / 2 - 0.05, 0, 0, 0),
        SHIRT,
    )
    neck_length = body.neck_pivot_z - body.shoulder_z + 0.02
    geometry += capsule_shape(
        "neck", 0.05, neck_length, (0, 0, body.shoulder_z + neck_length / 2, 0, 0, 0), SKIN
    )
    frames = ""
    for side in ("right", "left"):
        points = body.leg_points(side)
        prefix = side[0]
        geometry += _segment(f"{prefix}_thigh", points["hip"], points["knee"], 0.07, TROUSERS)
        geometry += _segment(f"{prefix}_shank", points["knee"], points["ankle"], 0.055, TROUSERS)
        for joint, point in points.items():
            frames += _frame(f"{prefix}_{joint}", "pelvis", point, np.zeros(3))
        frames += _frame(f"{prefix}_shoulder", "pelvis", body.shoulder(side), np.zeros(3))
    frames += _frame("neck", "pelvis", np.array([0, 0, body.shoulder_z]), np.zeros(3))
    if body.seated:
        geometry += _chair(body.seat_height)
    mass = 45.0
    moments = box_inertia(mass, trunk_size)
    return _link("pelvis", np.zeros(3), mass, moments, geometry) + frames


def _chair(height: float) -> str:
    """A stool `height` (m) high under a seated person: visual and collision, so the robot
    plans around it."""
    seat = shape(
        "chair_seat", box_geometry((0.42, 0.42, 0.04)), (0, 0, height - 0.02, 0, 0, 0), CHAIR
    )
    post = shape(
        "chair_post",
        box_geometry((0.06, 0.06, height - 0.04)),
        (0, 0, (height - 0.04) / 2, 0, 0, 0),
        CHAIR,
    )
    return seat + post


def _head(body: BodyDimensions) -> str:
    pivot = body.neck_pivot()
    face = body.face_points()
    r = body.head_radius
    geometry = sphere_shape("skull", r, (*(body.head_center() - pivot), 0, 0, 0), SKIN)
    geometry += sphere_shape("nose", 0.18 * r, (*face["nose"], 0, 0, 0), SKIN)
    for eye in ("r_eye", "l_eye"):
        geometry += visual(eye, coarse_sphere(0.12 * r), (*face[eye], 0, 0, 0), EYE)
    frames = "".join(_frame(name, "head", pivot + point, pivot) for name, point in face.items())
    neck = _link("neck_link", pivot, 0.1, (1e-4, 1e-4, 1e-4))
    head = _link("head", pivot, 4.5, (0.02, 0.02, 0.02), geometry)
    joints = _revolute("neck_yaw", "pelvis", "neck_link", (0, 0, 1), NECK_GAINS)
    joints += _revolute("neck_pitch", "neck_link", "head", (0, 1, 0), NECK_GAINS)
    return neck + head + joints + frames


def _arm(body: BodyDimensions, side: str) -> str:
    p = side[0] + "_"
    shoulder = body.shoulder(side)
    elbow = shoulder - np.array([0, 0, body.upper_arm])
    wrist = elbow - np.array([0, 0, body.forearm])
    small = (1e-4, 1e-4, 1e-4)
    upper_geometry = capsule_shape(
        f"{p}upper_arm",
        UPPER_ARM_RADIUS,
        body.upper_arm - 2 * UPPER_ARM_RADIUS,
        (0, 0, -body.upper_arm / 2, 0, 0, 0),
        SHIRT,
    )
    fore_geometry = capsule_shape(
        f"{p}forearm",
        FOREARM_RADIUS,
        body.forearm - 2 * FOREARM_RADIUS,
        (0, 0, -body.forearm / 2, 0, 0, 0),
        SKIN,
    )
    hand_size = (HAND_WIDTH, HAND_THICKNESS, body.hand)
    hand_geometry = shape(
        f"{p}hand", box_geometry(hand_size), (0, 0, -body.hand / 2, 0, 0, 0), SKIN
    )
    links = (
        _link(f"{p}shoulder_link1", shoulder, 0.1, small)
        + _link(f"{p}shoulder_link2", shoulder, 0.1, small)
        + _link(
            f"{p}upper_arm",
            shoulder,
            2.0,
            cylinder_inertia(2.0, UPPER_ARM_RADIUS, body.upper_arm),
            upper_geometry,
        )
        + _link(
            f"{p}forearm",
            elbow,
            1.2,
            cylinder_inertia(1.2, FOREARM_RADIUS, body.forearm),
            fore_geometry,
        )
        + _link(f"{p}hand", wrist, 0.45, box_inertia(0.45, hand_size), hand_geometry)
    )
    joints = (
        _revolute(f"{p}shoulder_pitch", "pelvis", f"{p}shoulder_link1", (0, 1, 0), ARM_GAINS)
        + _revolute(
            f"{p}shoulder_roll", f"{p}shoulder_link1", f"{p}shoulder_link2", (1, 0, 0), ARM_GAINS
        )
        + _revolute(f"{p}shoulder_yaw", f"{p}shoulder_link2", f"{p}upper_arm", (0, 0, 1), ARM_GAINS)
        + _revolute(f"{p}elbow", f"{p}upper_arm", f"{p}forearm", (0, 1, 0), ARM_GAINS)
        + _revolute(f"{p}wrist", f"{p}forearm", f"{p}hand", (0, 1, 0), ARM_GAINS)
    )
    frames = _frame(f"{p}elbow", f"{p}forearm", elbow, elbow)
    frames += _frame(f"{p}wrist", f"{p}hand", wrist, wrist)
    return links + joints + frames


def _self_collision_filter() -> str:
    """A person's own links never collide with each other here: the actor keeps limbs apart."""
    return (
        '<drake:collision_filter_group name="person_self">'
        + "".join(f"<drake:member>{link}</drake:member>" for link in _LINKS)
        + "<drake:ignored_collision_filter_group>person_self"
        "</drake:ignored_collision_filter_group></drake:collision_filter_group>"
    )


_LINKS = (
    "pelvis", "neck_link", "head",
    *(f"{s}_{link}" for s in "rl" for link in
      ("shoulder_link1", "shoulder_link2", "upper_arm", "forearm", "hand")),
)  # fmt: skip


def person_sdf(body: BodyDimensions) -> str:
    """SDFormat for the person in its own frame (floor under the hips, facing +x)."""
    parts = _pelvis(body) + _head(body) + _arm(body, "right") + _arm(body, "left")
    return model("person", parts + _self_collision_filter()).replace(
        '<sdf version="1.9">', '<sdf version="1.9" xmlns:drake="http://drake.mit.edu">'
    )
