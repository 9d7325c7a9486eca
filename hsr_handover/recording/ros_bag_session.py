"""A ROS bag read as a recorded session (`recorded_session.RecordedSession`): the frames a
survey (`ros_bag_survey`) found usable, each frame's colour and depth read from the bag when
asked for, so `intent` runs on a bag as on a session folder."""

from __future__ import annotations

from pathlib import Path

from hsr_handover.recording import ros_messages as msgs
from hsr_handover.recording.rgbd_session import SessionFrame
from hsr_handover.recording.ros_bag import BagError, RosBag
from hsr_handover.recording.ros_bag_survey import BagSurvey, survey_bag
from hsr_handover.recording.ros_topics import HSR_TOPICS, SETTINGS_TOPIC, BagTopics


class RosBagSession:
    """A surveyed bag's usable frames (`survey.frames`) as a session. Close it (or use it in a
    `with`) to close the bag."""

    def __init__(self, bag: RosBag, survey: BagSurvey):
        if survey.problems:
            raise BagError(survey.problems[0])
        self.bag, self.survey = bag, survey
        self.camera = survey.camera
        self.stamps = tuple(survey.stamps)
        self.keypoints = tuple(survey.keypoints)
        self.settings = survey.settings
        self.skipped = tuple(
            [f"colour image at {t:.3f} s: no depth image within the tolerance"
             for t in survey.unpaired_color]
            + [f"frame at {t:.3f} s: no camera pose in TF" for t in survey.without_pose]
        )  # fmt: skip

    @property
    def settings_source(self) -> str:
        return f"{self.bag.path}: {SETTINGS_TOPIC}"

    def __enter__(self) -> RosBagSession:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.bag.close()

    def frame(self, k: int) -> SessionFrame:
        """Frame k: its colour and depth read from the bag, its pose and skeleton as surveyed.
        Raises BagError naming the topic when an image cannot be decoded."""
        survey = self.survey
        color_k, depth_k = survey.frames[k]
        images = []
        for index, k_in_topic, decode in (
            (survey.color_index, color_k, msgs.color_rgba),
            (survey.depth_index, depth_k, msgs.depth_metres),
        ):
            message = self.bag.message(index, k_in_topic)
            try:
                image = decode(message, index.msgtype)
            except msgs.UnsupportedEncoding as error:
                raise BagError(f"{self.bag.path}: {index.topic}: {error}") from None
            if image.shape[:2] != (self.camera.height, self.camera.width):
                raise BagError(
                    f"{self.bag.path}: {index.topic}: expected {self.camera.width} x "
                    f"{self.camera.height} images, got {image.shape[1]} x {image.shape[0]} at "
                    f"{self.stamps[k]:.3f} s"
                )
            images.append(image)
        color, depth = images
        return SessionFrame(self.stamps[k], color, depth, survey.poses[k], self.keypoints[k])


def read_bag_session(path: Path, topics: BagTopics = HSR_TOPICS, tolerance: float | None = None,
                     openpose: Path | None = None) -> RosBagSession:  # fmt: skip
    """Open a bag and read it as a session. Raises BagError with the first problem found (a
    missing topic, an unsupported encoding, no paired frames, no TF chain...)."""
    bag = RosBag(path)
    try:
        return RosBagSession(bag, survey_bag(bag, topics, tolerance, openpose))
    except BaseException:
        bag.close()
        raise
