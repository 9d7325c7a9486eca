"""How a library's error is told in one line."""

from __future__ import annotations


def first_line(error: BaseException) -> str:
    """The first line of `error`'s message, or its type's name when the message says nothing."""
    text = str(error).strip()
    return text.splitlines()[0] if text else type(error).__name__
