"""Offline Meshcat replays: record a run and write it as one self-contained HTML file."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from pydrake.geometry import Meshcat, MeshcatParams


def make_local_meshcat() -> Meshcat:
    """A Meshcat server that listens on localhost only (nothing is served to the network)."""
    return Meshcat(MeshcatParams(host="localhost"))


def start_recording(meshcat: Meshcat, frames_per_second: float) -> None:
    """Record transforms and properties from now on. Objects created later with SetObject are
    not recorded (a Meshcat limitation): create them up front and animate their visibility."""
    meshcat.StartRecording(frames_per_second, set_visualizations_while_recording=False)


def write_replay(meshcat: Meshcat, path: Path) -> Path:
    """Stop recording and write the static HTML replay atomically: no partial file on failure."""
    meshcat.StopRecording()
    meshcat.PublishRecording()
    html = meshcat.StaticHtml()
    path = Path(path)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "w") as stream:
            stream.write(html)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes it private; a replay is not
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
