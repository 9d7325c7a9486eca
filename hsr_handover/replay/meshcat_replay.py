"""Offline Meshcat replays: record a run and write it as one self-contained HTML file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from pydrake.geometry import Meshcat, MeshcatParams

from hsr_handover.output_files import write_together
from hsr_handover.replay.legend import with_legend
from hsr_handover.replay.overlays import drawn_overlays

# Meshcat's perspective camera (three.js): 75 degrees vertical field of view.
MESHCAT_FOV_Y = np.radians(75.0)
# Frame for windows at least this wide for their height (4:3); wider windows show more margin.
MIN_ASPECT = 4.0 / 3.0
# The box's widest projection reaches this fraction of the view's half-width: a thin margin.
FILL = 0.9
# The 3/4 view: 45 degrees round from the `side` point, 30 degrees above the horizon.
AZIMUTH = np.radians(-45.0)
ELEVATION = np.radians(30.0)


def make_local_meshcat() -> Meshcat:
    """A Meshcat server that listens on localhost only (nothing is served to the network)."""
    return Meshcat(MeshcatParams(host="localhost"))


def start_recording(meshcat: Meshcat, frames_per_second: float) -> None:
    """Record transforms and properties from now on. Objects created later with SetObject are
    not recorded (a Meshcat limitation): create them up front and animate their visibility."""
    meshcat.StartRecording(frames_per_second, set_visualizations_while_recording=False)


def frame_view(
    meshcat: Meshcat, points: ArrayLike, side: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """Point Meshcat's camera at the bounding box of `points` (N x 3, world) in a 3/4 view from
    above, over the left shoulder of someone standing at `side` (x, y[, z], e.g. the robot's base)
    and facing the box; returns (camera, target) in the world.

    Call it before `write_replay`: the static HTML keeps the last camera pose set, recording or
    not, and the viewer opens there (the user can still orbit away)."""
    camera, target = framing_pose(points, side)
    meshcat.SetCameraPose(camera, target)
    return camera, target


def framing_pose(
    points: ArrayLike, side: ArrayLike, aspect: float = MIN_ASPECT
) -> tuple[np.ndarray, np.ndarray]:
    """(camera, target) for `frame_view`: looking along the 3/4 view direction, the nearest camera
    that keeps all eight corners of the box inside the view (to FILL of its half-size) of a
    window `aspect` times as wide as it is tall, with the box's image centred."""
    corners = _box_corners(np.asarray(points, dtype=float).reshape(-1, 3))
    centre = corners.mean(axis=0)
    forward = -_view_direction(centre, np.asarray(side, dtype=float))
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    offsets = corners - centre
    tan_y = FILL * np.tan(MESHCAT_FOV_Y / 2)
    shift_x, distance_x = _fit_axis(offsets @ right, offsets @ forward, aspect * tan_y)
    shift_y, distance_y = _fit_axis(offsets @ up, offsets @ forward, tan_y)
    target = centre + shift_x * right + shift_y * up
    return target - max(distance_x, distance_y) * forward, target


def _fit_axis(lateral: np.ndarray, depth: np.ndarray, tan_half: float) -> tuple[float, float]:
    """Along one image axis, the camera's sideways shift s and distance d behind the centre that
    fit every corner, |lateral - s| <= tan_half * (depth + d), at the least d. Both sides of the
    bound are linear in s, so the best s is where the two sides' outermost corners balance."""
    scaled = lateral / tan_half
    high, low = np.max(scaled - depth), np.max(-scaled - depth)
    return float(tan_half * (high - low) / 2), float((high + low) / 2)


def _box_corners(points: np.ndarray) -> np.ndarray:
    """The eight corners (8 x 3) of the axis-aligned bounding box of `points`."""
    low, high = points.min(axis=0), points.max(axis=0)
    pick = np.array([[i >> k & 1 for k in range(3)] for i in range(8)], dtype=bool)
    return np.where(pick, high, low)


def _view_direction(target: np.ndarray, side: np.ndarray) -> np.ndarray:
    """Unit vector from the target towards the camera: horizontally from the target towards
    `side`, turned by AZIMUTH, then raised by ELEVATION."""
    horizontal = side[:2] - target[:2]
    norm = np.linalg.norm(horizontal)
    horizontal = horizontal / norm if norm > 1e-9 else np.array([-1.0, 0.0])
    c, s = np.cos(AZIMUTH), np.sin(AZIMUTH)
    turned = np.array(
        [c * horizontal[0] - s * horizontal[1], s * horizontal[0] + c * horizontal[1]]
    )
    return np.array([*np.cos(ELEVATION) * turned, np.sin(ELEVATION)])


WEBGL_MISSING = (
    "This replay is drawn with WebGL, and this browser could not create a WebGL context. Turn "
    "on hardware acceleration, or start Chromium with --use-angle=swiftshader "
    "--enable-unsafe-swiftshader."
)
_WEBGL_NOTICE = f"""
  <div id="webgl-missing" style="display: none; font: 16px sans-serif; margin: 2em;">
    {WEBGL_MISSING}
  </div>
  <script>
    (function () {{
      var canvas = document.createElement("canvas");
      if (!(canvas.getContext("webgl2") || canvas.getContext("webgl"))) {{
        document.getElementById("webgl-missing").style.display = "block";
      }}
    }})();
  </script>"""


def with_webgl_notice(html: str) -> str:
    """Meshcat's page with a notice, in words, shown when the browser has no WebGL (without
    it the page stays blank: three.js throws before drawing anything)."""
    body = html.index("<body>") + len("<body>")
    return html[:body] + _WEBGL_NOTICE + html[body:]


def write_replay(meshcat: Meshcat, path: Path) -> Path:
    """Stop recording and write the static HTML replay atomically (no partial file on failure),
    with the legend of the overlays drawn (`replay.legend`)."""
    meshcat.StopRecording()
    meshcat.PublishRecording()
    html = with_legend(with_webgl_notice(meshcat.StaticHtml()), drawn_overlays(meshcat))
    path = Path(path)
    write_together({path: lambda temporary: temporary.write_text(html)})
    return path
