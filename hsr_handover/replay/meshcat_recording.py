"""Drawing into a Meshcat recording so that a replay shows what changed and when.

A recording replays transforms and properties but not `SetObject`: an object drawn anew in
place would replay as its last state throughout. So a thing that changes shape is drawn as a
new snapshot under its own path (`<root>/0000`, `<root>/0001`, ...) and the recording animates
the snapshots' `visible` property; a thing that only moves is drawn once and its transform is
recorded.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

from pydrake.geometry import Meshcat
from pydrake.math import RigidTransform


def recording_start(meshcat: Meshcat) -> float:
    return meshcat.get_mutable_recording().start_time()


def record_visible(meshcat: Meshcat, path: str, visible: bool, time: float) -> None:
    """A `visible` keyframe at `time` in the recording (none before its start)."""
    # A keyframe before the recording's start fails a DRAKE_DEMAND in MeshcatAnimation, which
    # ends the program (SystemExit in Python) rather than raising something catchable.
    if time >= recording_start(meshcat):
        meshcat.SetProperty(path, "visible", visible, time_in_recording=time)


def set_visible(meshcat: Meshcat, path: str, visible: bool, time: float) -> None:
    """Show or hide `path` live and from `time` in the recording."""
    # The live call updates browsers and the scene a replay starts from; the recording may be
    # set up not to show recorded calls live.
    meshcat.SetProperty(path, "visible", visible)
    record_visible(meshcat, path, visible, time)


def set_pose(meshcat: Meshcat, path: str, pose: RigidTransform, time: float) -> None:
    """Place `path` live and from `time` in the recording."""
    meshcat.SetTransform(path, pose)
    if time >= recording_start(meshcat):
        meshcat.SetTransform(path, pose, time_in_recording=time)


class Snapshots:
    """Snapshots of one changing thing under `root`, one shown at a time: `show(draw, time)`
    draws a new one with `draw(path)` and shows it from `time`, hiding the one before;
    `hide(time)` hides the one shown. Only the newest `keep` are kept (older ones are deleted,
    so a replay longer than they cover shows nothing at its start)."""

    def __init__(self, meshcat: Meshcat, root: str, keep: int):
        if keep < 1:
            raise ValueError(f"keep: expected at least 1 snapshot, got {keep}")
        self._meshcat, self.root, self._keep = meshcat, root.rstrip("/"), keep
        self.paths: deque[str] = deque()  # oldest first
        self._shown: str | None = None
        self._count = 0  # never reset: a path reused would replay as its newest object

    def clear(self) -> None:
        """Remove everything under the root (what an earlier simulation drew)."""
        self._meshcat.Delete(self.root)
        self.paths.clear()
        self._shown = None

    def show(self, draw: Callable[[str], None], time: float) -> str:
        self.hide(time)
        path = f"{self.root}/{self._count:04d}"
        self._count += 1
        self.paths.append(path)
        draw(path)
        # A boolean track holds its first keyframe's value before it, so without a keyframe at
        # the start the snapshot would show from the beginning of the replay.
        record_visible(self._meshcat, path, False, recording_start(self._meshcat))
        set_visible(self._meshcat, path, True, time)
        self._shown = path
        while len(self.paths) > self._keep:
            self._meshcat.Delete(self.paths.popleft())
        return path

    def hide(self, time: float) -> None:
        if self._shown is not None:
            set_visible(self._meshcat, self._shown, False, time)
            self._shown = None
