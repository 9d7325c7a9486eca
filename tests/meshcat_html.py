"""Reading what a Meshcat replay holds: its commands decoded from the HTML, which paths end
hidden, and each animated path's keyframes."""

from __future__ import annotations

import base64
import re
from pathlib import Path

import msgpack

_BLOB = re.compile(rb"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)")


def meshcat_commands(html: str | bytes) -> list[dict]:
    """The Meshcat commands a static HTML replay holds (base64 msgpack blobs), decoded."""
    html = html.encode() if isinstance(html, str) else html
    return [
        msgpack.unpackb(base64.b64decode(blob), raw=False, strict_map_key=False)
        for blob in _BLOB.findall(html)
    ]


def replay_commands(meshcat, folder: Path) -> list[dict]:
    """Stop the recording of `meshcat` (a pydrake Meshcat), write the replay HTML into `folder`
    and decode its commands."""
    from hsr_handover.replay.meshcat_replay import write_replay

    return meshcat_commands(write_replay(meshcat, folder / "replay.html").read_bytes())


def hidden_paths(commands: list[dict]) -> set[str]:
    """Paths whose last `visible` setting in the scene is False."""
    visible = {
        c["path"]: c["value"]
        for c in commands
        if c["type"] == "set_property" and c["property"] == "visible"
    }
    return {path for path, value in visible.items() if value is False}


def animation_keys(commands: list[dict], track_name: str) -> dict[str, list[tuple[float, object]]]:
    """Each animated path's keyframes on one track (".visible", ".position", ...) as (time s,
    value)."""
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    keys = {}
    for entry in animation["animations"]:
        clip = entry["clip"]
        for track in clip["tracks"]:
            if track["name"] == track_name:
                keys[entry["path"]] = [(k["time"] / clip["fps"], k["value"]) for k in track["keys"]]
    return keys


def visibility_keys(commands: list[dict]) -> dict[str, list[tuple[float, bool]]]:
    """Each animated path's `visible` keyframes as (time s, value)."""
    return animation_keys(commands, ".visible")
