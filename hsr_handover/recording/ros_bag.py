"""A ROS bag opened for reading with `rosbags` (no ROS install): a ROS 1 `.bag` file or a ROS 2
bag folder (sqlite3 or MCAP); what topics it holds, each topic's messages indexed by their
header stamps, and any one message read back on demand (images are not held in memory)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import yaml
from rosbags.highlevel import AnyReader

from hsr_handover.error_text import first_line
from hsr_handover.recording.rgbd_session import SessionError
from hsr_handover.recording.ros_messages import stamp_seconds

ROS1_FORMAT = "ROS 1"
ROS2_METADATA = "metadata.yaml"


class BagError(SessionError):
    """A bag that cannot be read as asked: "<bag or topic>: expected ..."."""


@dataclasses.dataclass(frozen=True)
class TopicIndex:
    """A topic's messages in the bag's order: `msgtype`, each one's `stamps` (its header's, s;
    the time it was logged for a message without a header) and where to find it again."""

    topic: str
    msgtype: str
    stamps: tuple[float, ...]
    log_times: tuple[int, ...]
    ordinals: tuple[int, ...]  # among the topic's messages logged at the same time


def is_bag(path: Path) -> bool:
    """Whether `path` looks like a bag: a `.bag` file or a folder with a metadata.yaml."""
    path = Path(path)
    return (path.is_file() and path.suffix == ".bag") or (path / ROS2_METADATA).is_file()


def _ros2_storage(path: Path) -> str:
    try:
        info = yaml.safe_load((path / ROS2_METADATA).read_text())["rosbag2_bagfile_information"]
        return {"sqlite3": "sqlite3", "mcap": "MCAP"}.get(info["storage_identifier"], "?")
    except (OSError, yaml.YAMLError, KeyError, TypeError):
        return "?"


class RosBag:
    """An open bag (close it, or use it in a `with`). Raises BagError naming the path when it is
    not a bag that can be read."""

    def __init__(self, path: Path):
        self.path = Path(path)
        if self.path.is_file() and self.path.suffix == ".bag":
            self.format = ROS1_FORMAT
        elif (self.path / ROS2_METADATA).is_file():
            self.format = f"ROS 2 ({_ros2_storage(self.path)})"
        else:
            raise BagError(
                f"{self.path}: expected a ROS 1 .bag file or a ROS 2 bag folder (with "
                f"{ROS2_METADATA})"
            )
        try:
            self._reader = AnyReader([self.path])
            self._reader.open()
        except Exception as error:  # rosbags' errors differ by format; any means "not a bag"
            raise BagError(
                f"{self.path}: expected a readable {self.format} bag: {first_line(error)}"
            ) from None
        self._indices: dict[str, TopicIndex] = {}

    def __enter__(self) -> RosBag:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self._reader.stack is not None:
            self._reader.close()

    @property
    def duration_s(self) -> float:
        return self._reader.duration * 1e-9 if self._reader.message_count else 0.0

    @property
    def message_count(self) -> int:
        return int(self._reader.message_count)

    def topics(self) -> dict[str, tuple[str, int]]:
        """Each topic's message type and message count."""
        return {name: (info.msgtype, info.msgcount) for name, info in self._reader.topics.items()}

    def _connections(self, topic: str) -> list:
        return [c for c in self._reader.connections if c.topic == topic]

    def _read(self, topic: str, **window):
        """(connection, log time, raw bytes) of `topic`'s messages (in `window`: rosbags'
        start, stop), a chunk that cannot be read being a BagError, not rosbags' own."""
        try:
            yield from self._reader.messages(connections=self._connections(topic), **window)
        except Exception as error:
            raise BagError(f"{self.path}: {topic}: expected readable messages: "
                           f"{first_line(error)}") from None  # fmt: skip

    def _deserialize(self, topic: str, raw: bytes, msgtype: str):
        try:
            return self._reader.deserialize(raw, msgtype)
        except Exception as error:
            raise BagError(f"{self.path}: {topic}: expected {msgtype} messages: {error}") from None

    def messages(self, topic: str):
        """Every message of `topic`, deserialised, in the bag's order."""
        for connection, _, raw in self._read(topic):
            yield self._deserialize(topic, raw, connection.msgtype)

    def index(self, topic: str, visit=None) -> TopicIndex:
        """The topic's messages indexed (read once, then kept); `visit(message)` is called on
        each message read for the index (to gather its encodings)."""
        if topic in self._indices and visit is None:
            return self._indices[topic]
        connections = self._connections(topic)
        if not connections:
            raise BagError(f"{self.path}: {topic}: expected the topic, it is not in the bag")
        stamps, log_times, ordinals, last = [], [], [], (None, -1)
        for connection, log_time, raw in self._read(topic):
            message = self._deserialize(topic, raw, connection.msgtype)
            stamp = getattr(message, "header", None)
            stamps.append(stamp_seconds(stamp.stamp) if stamp is not None else log_time * 1e-9)
            ordinal = last[1] + 1 if last[0] == log_time else 0
            last = (log_time, ordinal)
            log_times.append(log_time)
            ordinals.append(ordinal)
            if visit is not None:
                visit(message)
        index = TopicIndex(topic, connections[0].msgtype, tuple(stamps), tuple(log_times),
                           tuple(ordinals))  # fmt: skip
        self._indices[topic] = index
        return index

    def message(self, index: TopicIndex, k: int):
        """Message k of an indexed topic, read again from the bag."""
        log_time, ordinal = index.log_times[k], index.ordinals[k]
        found = self._read(index.topic, start=log_time, stop=log_time + 1)
        for position, (connection, _, raw) in enumerate(found):
            if position == ordinal:
                return self._deserialize(index.topic, raw, connection.msgtype)
        raise BagError(
            f"{self.path}: {index.topic}: expected message {k}, it could not be read again"
        )
