"""A command's output files written together: each under a temporary name beside it, and all
moved into place only once every one is written, so a command that fails part way leaves none
of them (nor a temporary) behind."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path


def partial_name(path: Path) -> Path:
    """Where `path` is written before it is moved into place: hidden, with its suffix kept (a
    figure's format is told by it)."""
    return path.with_name(f".{path.stem}.partial{path.suffix}")


def write_together(writes: Mapping[Path, Callable[[Path], object]]) -> None:
    """Call each `write(temporary)` in turn, then move every temporary to its path; if any
    write raises, remove what was written and re-raise."""
    written: list[Path] = []
    try:
        for path, write in writes.items():
            written.append(partial_name(path))
            write(written[-1])
        for path, temporary in zip(writes, written, strict=True):
            os.replace(temporary, path)
    except BaseException:
        for temporary in written:
            temporary.unlink(missing_ok=True)
        raise
