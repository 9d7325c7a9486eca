"""What every planning step returns first: whether it found what was asked (`ok`), or why not
(`reason`). The results that extend it are built with keywords only, so a field added or
moved never shifts another's meaning."""

from __future__ import annotations

import dataclasses


@dataclasses.dataclass(frozen=True, kw_only=True)
class Outcome:
    """`ok`, or not with the `reason` ("ok" when it is)."""

    ok: bool
    reason: str
