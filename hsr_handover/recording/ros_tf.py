"""The TF tree of a bag (/tf and /tf_static): each frame's pose in its parent over time, and a
frame's pose in another at a time, composed along the tree and interpolated between the
samples around that time (linear in translation, spherical in rotation) as tf2 looks it up,
or before the first or after the last sample taken from the nearest within a tolerance."""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from hsr_handover.recording.ros_pairing import nearest_index


@dataclasses.dataclass
class _Edge:
    """A child's poses in its parent: `static`, or sampled at `times`."""

    parent: str
    static: bool
    times: list[float] = dataclasses.field(default_factory=list)
    poses: list[np.ndarray] = dataclasses.field(default_factory=list)


class TfLookupError(ValueError):
    """No pose of a frame in another: names the frames and why."""


def strip_frame(frame_id: str) -> str:
    """A frame's name without ROS 1's leading slash."""
    return frame_id.lstrip("/")


class TransformTree:
    """Add transforms with `add`; then `chain` names the frames between two and `lookup` gives
    one's pose in the other at a time."""

    def __init__(self) -> None:
        self._edges: dict[str, _Edge] = {}
        self._sorted = True

    @property
    def frames(self) -> set[str]:
        return set(self._edges) | {edge.parent for edge in self._edges.values()}

    def add(self, parent: str, child: str, time: float, X: np.ndarray, static: bool) -> None:
        """`child`'s 4 x 4 pose `X` in `parent` at `time` (s); a static one holds at all times.
        A child keeps the first parent it is given (a tree)."""
        parent, child = strip_frame(parent), strip_frame(child)
        edge = self._edges.setdefault(child, _Edge(parent, static))
        if edge.parent != parent:
            return
        if static:
            edge.static, edge.times, edge.poses = True, [time], [X]
        elif not edge.static:
            edge.times.append(time)
            edge.poses.append(X)
            self._sorted = False

    def _ancestors(self, frame: str) -> list[str]:
        path = [frame]
        while path[-1] in self._edges and len(path) <= len(self._edges):
            path.append(self._edges[path[-1]].parent)
        return path

    def chain(self, fixed: str, target: str) -> list[str] | None:
        """The frames from `fixed` to `target` through their nearest common ancestor, or None
        when they are not joined."""
        up_fixed, up_target = self._ancestors(fixed), self._ancestors(target)
        common = next((frame for frame in up_fixed if frame in up_target), None)
        if common is None:
            return None
        down = up_target[: up_target.index(common)]
        return up_fixed[: up_fixed.index(common) + 1] + down[::-1]

    def _sort(self) -> None:
        for edge in self._edges.values():
            order = np.argsort(edge.times, kind="stable")
            edge.times = [edge.times[i] for i in order]
            edge.poses = [edge.poses[i] for i in order]
        self._sorted = True

    def _edge_pose(self, child: str, time: float, tolerance: float) -> np.ndarray:
        edge = self._edges[child]
        if edge.static:
            return edge.poses[0]
        times = np.asarray(edge.times)
        after = int(np.searchsorted(times, time))
        if 0 < after < len(times) and times[after] != time:  # between samples: interpolated
            before = after - 1
        else:  # on a sample, or beyond them: the nearest, if near enough
            nearest = nearest_index(times, time)
            if abs(times[nearest] - time) > tolerance:
                raise TfLookupError(
                    f"{edge.parent} -> {child}: expected a transform within "
                    f"{tolerance * 1e3:.1f} ms of {time:.3f} s, the nearest is "
                    f"{abs(times[nearest] - time) * 1e3:.1f} ms away"
                )
            return edge.poses[nearest]
        t0, t1 = times[before], times[after]
        share = (time - t0) / (t1 - t0)
        X0, X1 = edge.poses[before], edge.poses[after]
        rotations = Rotation.from_matrix(np.stack([X0[:3, :3], X1[:3, :3]]))
        X = np.eye(4)
        X[:3, :3] = Slerp([0.0, 1.0], rotations)([share]).as_matrix()[0]
        X[:3, 3] = (1 - share) * X0[:3, 3] + share * X1[:3, 3]
        return X

    def lookup(self, fixed: str, target: str, time: float, tolerance: float) -> np.ndarray:
        """`target`'s 4 x 4 pose in `fixed` at `time`. Raises TfLookupError when the frames are
        not joined or a moving link has no samples around `time` nor one within `tolerance`
        s of it."""
        if not self._sorted:
            self._sort()
        frames = self.chain(fixed, target)
        if frames is None:
            raise TfLookupError(f"{fixed} -> {target}: expected frames joined in the TF tree")
        X = np.eye(4)
        for parent, child in zip(frames, frames[1:], strict=False):
            if child in self._edges and self._edges[child].parent == parent:
                X = X @ self._edge_pose(child, time, tolerance)
            else:  # going up from `fixed` towards the common ancestor
                X = X @ np.linalg.inv(self._edge_pose(parent, time, tolerance))
        return X
