"""`pip install .` (not editable): the wheel carries the HSR model and its package.xml, and the
installed copy, on its own, validates and runs a bundled scenario."""

from __future__ import annotations

import importlib.metadata
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
MODEL_FILES = (
    "hsr_handover/models/package.xml", "hsr_handover/models/hsrb/hsrb.sdf",
    "hsr_handover/models/shapes/sphere.obj",
)  # fmt: skip
# Build inputs only: not the virtual environment, caches or an earlier in-tree build.
NOT_SOURCES = shutil.ignore_patterns(
    ".git", ".venv", "build", "dist", "*.egg-info", "__pycache__", ".*_cache", ".hypothesis",
    "*.html", "out",
)  # fmt: skip


def _can_build_offline() -> bool:
    """setuptools >= 68 and wheel in this environment (the `test` extra pins both), so the wheel
    builds without fetching a build environment."""
    try:
        setuptools = importlib.metadata.version("setuptools")
        importlib.metadata.version("wheel")
    except importlib.metadata.PackageNotFoundError:
        return False
    return int(setuptools.split(".")[0]) >= 68


def _pip(*args: str, cwd: Path) -> None:
    command = [sys.executable, "-m", "pip", "--disable-pip-version-check", *args]
    result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The project's wheel, built from a copy of the sources: pip builds in-tree, and the shared
    working tree should get no build/ folder from a test."""
    root = tmp_path_factory.mktemp("packaging")
    source = shutil.copytree(REPO, root / "source", ignore=NOT_SOURCES)
    isolation = ["--no-build-isolation"] if _can_build_offline() else []
    _pip("wheel", "--no-deps", *isolation, "-w", str(root / "dist"), str(source), cwd=root)
    (built,) = (root / "dist").glob("hsr_handover-*.whl")
    return built


@pytest.fixture(scope="module")
def site(wheel: Path) -> Path:
    """The wheel installed into a folder of its own (no dependencies: this venv has them)."""
    target = wheel.parent.parent / "site"
    _pip(
        "install",
        "--no-deps",
        "--no-compile",
        "--target",
        str(target),
        str(wheel),
        cwd=target.parent,
    )
    return target


def _python(site: Path, *args: str) -> subprocess.CompletedProcess:
    """This interpreter with the installed copy first on the path, run outside the source tree
    (the editable install in .venv would otherwise find the sources)."""
    workdir = site.parent / "work"
    workdir.mkdir(exist_ok=True)
    env = {**os.environ, "PYTHONPATH": str(site)}
    return subprocess.run(
        [sys.executable, *args], cwd=workdir, env=env, capture_output=True, text=True, timeout=300
    )


def test_wheel_carries_the_models_and_the_command(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
        (entry_points,) = [name for name in names if name.endswith(".dist-info/entry_points.txt")]
        scripts = archive.read(entry_points).decode()
    assert set(MODEL_FILES) <= names
    assert "hsr-handover = hsr_handover.cli:main" in scripts
    assert not [name for name in names if "__pycache__" in name or name.startswith("tests/")]


def test_installed_copy_is_the_one_imported(site: Path) -> None:
    code = "import hsr_handover, hsr_handover.hsr as h; print(hsr_handover.__file__, h.PACKAGE_XML)"
    result = _python(site, "-c", code)
    assert result.returncode == 0, result.stderr
    module, package_xml = map(Path, result.stdout.split())
    assert module.is_relative_to(site) and package_xml.is_relative_to(site)
    assert package_xml.is_file()


@pytest.mark.parametrize(
    "command", [["validate"], ["run", "--duration", "0.05", "--html", "out.html"]]
)
def test_installed_copy_runs_the_demo(site: Path, command: list[str]) -> None:
    demo = str(REPO / "scenarios" / "demo.yaml")
    result = _python(site, "-m", "hsr_handover.cli", command[0], demo, *command[1:])
    assert result.returncode == 0, result.stdout + result.stderr
    if command[0] == "run":
        assert (site.parent / "work" / "out.html").stat().st_size > 0
