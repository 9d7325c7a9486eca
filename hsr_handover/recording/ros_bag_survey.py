"""What a bag holds for the robot's perception, surveyed in one pass: the head camera's colour,
depth and intrinsics, their frames paired by stamp, the camera's pose from TF at each image's
stamp, the skeletons and the robot's settings; and every problem that keeps `intent` from
reading it, in the order they are met. `bag check` prints a survey; `ros_bag_session` reads
frames from one with no problems."""

from __future__ import annotations

import collections
import dataclasses
from pathlib import Path

import numpy as np
import yaml

from hsr_handover.interface.keypoints import Detection
from hsr_handover.interface.pinhole import PinholeCamera
from hsr_handover.recording import ros_messages as msgs
from hsr_handover.recording.rgbd_session import SessionError, check_settings
from hsr_handover.recording.ros_bag import BagError, RosBag, TopicIndex
from hsr_handover.recording.ros_pairing import default_tolerance, nearest_index, pair_stamps
from hsr_handover.recording.ros_skeletons import (
    NO_SKELETON,
    detections_from_openpose,
    detections_from_points,
)
from hsr_handover.recording.ros_tf import TfLookupError, TransformTree
from hsr_handover.recording.ros_topics import (
    BASE_FRAME,
    COMPRESSED_SUFFIX,
    HSR_TOPICS,
    ODOM_FRAME,
    SETTINGS_TOPIC,
    TF_STATIC_TOPIC,
    TF_TOPIC,
    BagTopics,
)

COLOR, DEPTH, INFO, JOINTS, SKELETON = "color", "depth", "camera_info", "joint_states", "skeleton"
TF, TF_STATIC = "tf", "tf_static"
EXPECTED_TYPES = {
    COLOR: (msgs.IMAGE, msgs.COMPRESSED_IMAGE), DEPTH: (msgs.IMAGE,), INFO: (msgs.CAMERA_INFO,),
    JOINTS: (msgs.JOINT_STATE,), SKELETON: (msgs.POLYGON_STAMPED,), TF: (msgs.TF_MESSAGE,),
    TF_STATIC: (msgs.TF_MESSAGE,),
}  # fmt: skip
UNPAIRED_NAMED = 5  # unpaired stamps a summary names


@dataclasses.dataclass
class StreamSurvey:
    """One topic: its `msgtype` (None when the bag lacks it), `messages`, `rate_hz` (over its
    stamps), `encodings` seen, and whether `intent` needs it."""

    topic: str
    needed: bool
    msgtype: str | None = None
    messages: int = 0
    rate_hz: float | None = None
    encodings: list[str] = dataclasses.field(default_factory=list)


@dataclasses.dataclass
class BagSurvey:
    """A bag surveyed (JSON-ready through `to_dict`). `frames`: the usable frames as (colour
    index, depth index), with `poses` and `keypoints` alongside; `problems`: why `intent`
    cannot read it (none: it can), the first being the one it reports."""

    path: str
    format: str
    duration_s: float
    message_count: int
    streams: dict[str, StreamSurvey]
    tolerance_s: float = 0.0
    paired: int = 0
    unpaired_color: list[float] = dataclasses.field(default_factory=list)
    unpaired_depth: list[float] = dataclasses.field(default_factory=list)
    base_frame: str = ""
    base_frame_note: str = ""
    tf_chain: list[str] | None = None
    without_pose: list[float] = dataclasses.field(default_factory=list)
    skeleton_source: str = ""
    skeleton_frames: int = 0
    settings: dict = dataclasses.field(default_factory=dict)
    problems: list[str] = dataclasses.field(default_factory=list)
    camera: PinholeCamera | None = None
    frames: list[tuple[int, int]] = dataclasses.field(default_factory=list)
    stamps: list[float] = dataclasses.field(default_factory=list)
    poses: list[np.ndarray] = dataclasses.field(default_factory=list)
    keypoints: list[Detection] = dataclasses.field(default_factory=list)
    color_index: TopicIndex | None = None
    depth_index: TopicIndex | None = None

    def to_dict(self) -> dict:
        fields = ("path", "format", "duration_s", "message_count", "tolerance_s", "paired",
                  "unpaired_color", "unpaired_depth", "base_frame", "base_frame_note", "tf_chain",
                  "without_pose", "skeleton_source", "skeleton_frames", "problems")  # fmt: skip
        summary = {name: getattr(self, name) for name in fields}
        summary["streams"] = {role: dataclasses.asdict(s) for role, s in self.streams.items()}
        summary["frames"] = len(self.frames)
        summary["usable"] = not self.problems
        return summary


def _rate(stamps) -> float | None:
    span = stamps[-1] - stamps[0] if len(stamps) > 1 else 0.0
    return (len(stamps) - 1) / span if span > 0 else None


class _Surveyor:
    """The survey's steps, each adding to `survey`; a step whose input is missing is skipped."""

    def __init__(self, bag: RosBag, topics: BagTopics, tolerance: float | None,
                 openpose: Path | None):  # fmt: skip
        self.bag, self.topics, self.tolerance, self.openpose = bag, topics, tolerance, openpose
        present = bag.topics()
        color = topics.color
        if color not in present and color + COMPRESSED_SUFFIX in present:
            color += COMPRESSED_SUFFIX
        needed = {COLOR: color, DEPTH: topics.depth, INFO: topics.camera_info,
                  SKELETON: topics.skeleton, JOINTS: topics.joint_states, TF: TF_TOPIC,
                  TF_STATIC: TF_STATIC_TOPIC}  # fmt: skip
        optional = {JOINTS, TF_STATIC} | ({SKELETON} if openpose is not None else set())
        streams = {
            role: StreamSurvey(topic, role not in optional) for role, topic in needed.items()
        }
        for stream in streams.values():
            if stream.topic in present:
                stream.msgtype, stream.messages = present[stream.topic]
        self.survey = BagSurvey(str(bag.path), bag.format, bag.duration_s, bag.message_count,
                                streams)  # fmt: skip

    def problem(self, text: str) -> None:
        self.survey.problems.append(text)

    def usable(self, role: str) -> bool:
        """Whether a stream is in the bag with an expected type (a problem if needed, not)."""
        stream = self.survey.streams[role]
        where = f"{self.bag.path}: {stream.topic}"
        if stream.msgtype is None:
            if stream.needed:
                self.problem(
                    f"{where}: expected {EXPECTED_TYPES[role][0]}, the topic is not in the bag"
                )
            return False
        if stream.msgtype not in EXPECTED_TYPES[role]:
            self.problem(
                f"{where}: expected {' or '.join(EXPECTED_TYPES[role])}, got {stream.msgtype}"
            )
            return False
        return True

    def index(self, role: str) -> TopicIndex:
        stream = self.survey.streams[role]
        encodings = collections.Counter()

        def visit(message) -> None:
            encodings[getattr(message, "encoding", None) or getattr(message, "format", "")] += 1

        index = self.bag.index(stream.topic, visit if role in (COLOR, DEPTH) else None)
        stream.rate_hz = _rate(index.stamps)
        stream.encodings = sorted(name for name in encodings if name)
        return index

    def run(self) -> BagSurvey:
        survey = self.survey
        color = self.index(COLOR) if self.usable(COLOR) else None
        depth = self.index(DEPTH) if self.usable(DEPTH) else None
        survey.color_index, survey.depth_index = color, depth
        camera = self.camera() if self.usable(INFO) else None
        if color is not None and camera is not None:
            self.check_image(COLOR, color, camera)
        if depth is not None and camera is not None:
            self.check_image(DEPTH, depth, camera)
        if self.usable(JOINTS):
            self.index(JOINTS)
        self.usable(TF_STATIC)
        tree = self.transforms() if self.usable(TF) else None
        keypoints = self.skeletons(color, camera)
        self.settings()
        if color is None or depth is None:
            return survey
        self.pair(color, depth)
        if tree is not None:
            self.pose(tree, color)
        if keypoints is not None and survey.frames:
            survey.keypoints = [keypoints[c] for c, _ in survey.frames]
        if not survey.frames and not survey.problems:
            self.problem(
                f"{self.bag.path}: expected frames with colour, depth and the camera's pose, "
                "found none"
            )
        return survey

    def camera(self) -> PinholeCamera | None:
        topic = self.survey.streams[INFO].topic
        message = next(iter(self.bag.messages(topic)), None)
        try:
            camera = msgs.camera_from_info(message)
        except ValueError as error:
            self.problem(f"{self.bag.path}: {topic}: {error}")
            return None
        self.survey.camera = camera
        return camera

    def check_image(self, role: str, index: TopicIndex, camera: PinholeCamera) -> None:
        """The first image decodes, at the camera's size."""
        topic = index.topic
        message = self.bag.message(index, 0)
        try:
            image = (msgs.color_rgba if role == COLOR else msgs.depth_metres)(
                message, index.msgtype
            )
        except msgs.UnsupportedEncoding as error:
            self.problem(f"{self.bag.path}: {topic}: {error}")
            return
        if image.shape[:2] != (camera.height, camera.width):
            self.problem(
                f"{self.bag.path}: {topic}: expected {camera.width} x {camera.height} images as "
                f"camera_info says, got {image.shape[1]} x {image.shape[0]}"
            )

    def pair(self, color: TopicIndex, depth: TopicIndex) -> None:
        survey = self.survey
        tolerance = self.tolerance_for(color)
        pairing = pair_stamps(color.stamps, depth.stamps, tolerance)
        survey.tolerance_s, survey.paired = tolerance, len(pairing.pairs)
        survey.unpaired_color = [color.stamps[i] for i in pairing.unpaired_first]
        survey.unpaired_depth = [depth.stamps[j] for j in pairing.unpaired_second]
        survey.frames = list(pairing.pairs)
        if not pairing.pairs and color.stamps and depth.stamps:
            self.problem(
                f"{self.bag.path}: {color.topic}, {depth.topic}: expected colour and depth images "
                f"stamped within {tolerance * 1e3:.1f} ms of each other, found no such pair"
            )
        if np.any(np.diff(color.stamps) <= 0):
            self.problem(
                f"{self.bag.path}: {color.topic}: expected header stamps rising image by image"
            )

    def transforms(self) -> TransformTree:
        tree = TransformTree()
        for topic, static in ((TF_STATIC_TOPIC, True), (TF_TOPIC, False)):
            if self.survey.streams[TF_STATIC if static else TF].msgtype is None:
                continue
            for message in self.bag.messages(topic):
                for transform in message.transforms:
                    tree.add(transform.header.frame_id, transform.child_frame_id,
                             msgs.stamp_seconds(transform.header.stamp),
                             msgs.transform_matrix(transform.transform), static)  # fmt: skip
        return tree

    def pose(self, tree: TransformTree, color: TopicIndex) -> None:
        """The camera's pose at each paired image's stamp; frames without one are dropped."""
        survey, camera_frame = self.survey, self.topics.camera_frame
        base = self.topics.base_frame
        if base is None:
            base = ODOM_FRAME if ODOM_FRAME in tree.frames else BASE_FRAME
            if base != ODOM_FRAME:
                survey.base_frame_note = f"no {ODOM_FRAME} frame in TF: poses in {BASE_FRAME}"
        survey.base_frame = base
        survey.tf_chain = tree.chain(base, camera_frame)
        if survey.tf_chain is None:
            known = ", ".join(sorted(tree.frames)) or "none"
            self.problem(f"{self.bag.path}: {TF_TOPIC}: expected a chain of transforms from "
                         f"{base} to {camera_frame}, found frames {known}")  # fmt: skip
            survey.frames = []
            return
        kept, first_error = [], None
        for pair in survey.frames:
            stamp = color.stamps[pair[0]]
            try:
                survey.poses.append(tree.lookup(base, camera_frame, stamp, survey.tolerance_s))
            except TfLookupError as error:
                survey.without_pose.append(stamp)
                first_error = first_error or error
                continue
            kept.append(pair)
            survey.stamps.append(stamp)
        survey.frames = kept
        if not kept and first_error is not None:
            self.problem(f"{self.bag.path}: {TF_TOPIC}: {first_error}")

    def skeletons(self, color: TopicIndex | None, camera: PinholeCamera | None) -> list | None:
        """Each colour image's followed person, or None when they cannot be had."""
        survey = self.survey
        if color is None or camera is None:
            return None
        try:
            if self.openpose is not None:
                survey.skeleton_source = str(self.openpose)
                detections = detections_from_openpose(
                    self.openpose, len(color.stamps), (camera.width, camera.height)
                )
                survey.skeleton_frames = len(detections)
                return detections
            if not self.usable(SKELETON):
                return None
            topic = survey.streams[SKELETON].topic
            survey.skeleton_source = topic
            index = self.index(SKELETON)
            tables = [msgs.skeleton_points(message) for message in self.bag.messages(topic)]
            followed = detections_from_points(tables, topic)
        except ValueError as error:
            self.problem(
                str(error)
                if str(error).startswith(str(self.bag.path))
                else f"{self.bag.path}: {error}"
            )
            return None
        stamps, tolerance = np.asarray(index.stamps), self.tolerance_for(color)
        detections = []
        for stamp in color.stamps:
            k = nearest_index(stamps, stamp)
            near = k >= 0 and abs(stamps[k] - stamp) <= tolerance
            detections.append(followed[k] if near else Detection.missing(NO_SKELETON))
        survey.skeleton_frames = sum(d.status != NO_SKELETON for d in detections)
        return detections

    def tolerance_for(self, color: TopicIndex) -> float:
        """The pairing tolerance (s): as given, else half the colour's median period (a median
        over every stamp: asked once per survey step, not per image)."""
        return self.tolerance if self.tolerance is not None else default_tolerance(color.stamps)

    def settings(self) -> None:
        """The robot's perception settings, if the bag was recorded with them."""
        if SETTINGS_TOPIC not in self.bag.topics():
            return
        where = f"{self.bag.path}: {SETTINGS_TOPIC}"
        message = next(iter(self.bag.messages(SETTINGS_TOPIC)), None)
        try:
            settings = yaml.safe_load(getattr(message, "data", ""))
            if not isinstance(settings, dict):
                raise SessionError(f"{where}: expected a YAML mapping of the robot's settings")
            check_settings(settings, where)
        except (yaml.YAMLError, SessionError) as error:
            self.problem(str(error).splitlines()[0] if isinstance(error, SessionError)
                         else f"{where}: expected YAML: {error}".splitlines()[0])  # fmt: skip
            return
        self.survey.settings = settings


def survey_bag(bag: RosBag, topics: BagTopics = HSR_TOPICS, tolerance: float | None = None,
               openpose: Path | None = None) -> BagSurvey:  # fmt: skip
    """Survey an open bag: `topics` where it holds each stream, `tolerance` (s) for pairing and
    TF (default half the colour's median period), `openpose` a folder of OpenPose JSON frames
    instead of the skeleton topic. Raises BagError only for a bag that cannot be read."""
    if tolerance is not None and not tolerance > 0:
        raise BagError(f"tolerance: expected a positive number of seconds, got {tolerance}")
    return _Surveyor(bag, topics, tolerance, openpose).run()
