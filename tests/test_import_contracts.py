"""The package's layering holds: `lint-imports` checks the contracts in pyproject.toml (the robot
and the world do not import each other; the CLI sits on the experiments, on the simulation, on
recording and replay, on the two sides; the shared algorithms and the interface sit below; the
numpy algorithms run without Drake)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_every_import_contract_is_kept():
    result = subprocess.run(
        [sys.executable, "-c", "import sys; from importlinter.cli import lint_imports_command; "
         "sys.exit(lint_imports_command())", "--no-cache"],
        capture_output=True, text=True, cwd=REPO, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-2000:]
    assert "0 broken" in result.stdout
