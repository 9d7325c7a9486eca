"""The documentation's links and paths resolve, and the README stays a front door.

Every relative Markdown link, every inline-code path that names a file or folder of the
repository and every repository path in a shell block, in README.md and docs/*.md, must exist.
README.md stays under 250 lines, links every file in docs/, and holds its two set-up commands
verbatim, the test command being the one CI runs (the last line of .ci/run). Plain pathlib and
re, no Drake: it runs in well under a second.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PACKAGE = ROOT / "hsr_handover"
DOC_FILES = [README, *sorted(DOCS.glob("*.md"))]
DOC_IDS = [path.relative_to(ROOT).as_posix() for path in DOC_FILES]

README_MAX_LINES = 250
INSTALL_AND_DEMO = (
    "python3.11 -m venv .venv && .venv/bin/pip install -e . && "
    ".venv/bin/hsr-handover run scenarios/demo.yaml --html demo.html"
)

TOP_LEVEL = ("hsr_handover", "scenarios", "benchmarks", "docs", "tests", ".ci")
"""First segments that make a path a repository path wherever it appears."""
SOURCE_SUFFIXES = (".py", ".yaml", ".yml", ".md", ".sdf", ".xml", ".toml", ".obj")
"""A path with one of these suffixes and a `/` names a file of the repository, from its root or
from inside the package (`robot/intent/tracker.py`)."""

FENCED = re.compile(r"^(`{3,}|~{3,})([^\n]*)\n(.*?)^\1[ \t]*$", re.M | re.S)
LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
INLINE_CODE = re.compile(r"(`+)((?:[^`\n]|\n(?!\s*\n))+?)\1")
"""A code span, which may run over a line break (not over a blank line)."""
PLACEHOLDER = re.compile(r"^[A-Z][A-Z0-9_]*(\.\w+)?$|\d{6}")
"""A segment standing for a name the reader chooses (SCENARIO.yaml, OUT.json, DIR) or an
example file of a recording (000000000042.png)."""
LINE_SUFFIX = re.compile(r":\d+(-\d+)?$")


def _prose(text: str) -> str:
    """The text with its fenced blocks taken out."""
    return FENCED.sub("", text)


def _shell_blocks(text: str) -> list[str]:
    return [body for _, lang, body in FENCED.findall(text) if lang.strip() in ("bash", "sh")]


def _clean(path: str) -> str:
    """The path without an #anchor, a ?query or a :line suffix."""
    path = path.split("#", 1)[0].split("?", 1)[0]
    return LINE_SUFFIX.sub("", path)


def _is_skipped(path: str) -> bool:
    return (
        not path
        or path.startswith(("/", "~", "$", "-"))
        or any(mark in path for mark in "*<>{}|")
        or any(PLACEHOLDER.search(segment) for segment in path.rstrip("/").split("/"))
    )


def _repository_path(token: str, *, in_command: bool = False) -> str | None:
    """The repository path a code span or a command's word names, or None if it names none. A
    word of a command counts only if it starts at a top-level folder."""
    path = _clean(token.strip().strip("'\""))
    if " " in path or "/" not in path or "://" in path or _is_skipped(path):
        return None
    if path.split("/", 1)[0] in TOP_LEVEL:
        return path
    if not in_command and path.rstrip("/").endswith(SOURCE_SUFFIXES):
        return path
    return None


def _exists(path: str) -> bool:
    """From the repository's root, or (an abbreviated package path) from inside the package."""
    if (ROOT / path).exists():
        return True
    return path.split("/", 1)[0] not in TOP_LEVEL and (PACKAGE / path).exists()


def _links(doc: Path) -> list[str]:
    """The local targets of the Markdown links (images too) outside fenced blocks."""
    targets = []
    for target in LINK.findall(_prose(doc.read_text(encoding="utf-8"))):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I) or target.startswith("#"):
            continue  # http(s), mailto and the like; an anchor in the same file
        targets.append(target)
    return targets


def _code_paths(doc: Path) -> list[str]:
    """The repository paths named in inline code and in shell blocks."""
    text = doc.read_text(encoding="utf-8")
    spans = [" ".join(match.group(2).split()) for match in INLINE_CODE.finditer(_prose(text))]
    paths = [_repository_path(span) for span in spans if " " not in span]
    words = [word for span in spans if " " in span for word in span.split()]
    for block in _shell_blocks(text):
        words += re.split(r"[\s;&|()]+", block)
    paths += [_repository_path(word, in_command=True) for word in words]
    return sorted({path for path in paths if path is not None})


@pytest.mark.parametrize("doc", DOC_FILES, ids=DOC_IDS)
def test_every_relative_link_resolves(doc: Path):
    missing = [
        target for target in _links(doc) if not (doc.parent / _clean(target)).resolve().exists()
    ]
    assert not missing, f"{doc.relative_to(ROOT)} links to what does not exist: {missing}"


@pytest.mark.parametrize("doc", DOC_FILES, ids=DOC_IDS)
def test_every_repository_path_in_code_exists(doc: Path):
    missing = [path for path in _code_paths(doc) if not _exists(path)]
    assert not missing, f"{doc.relative_to(ROOT)} names paths that do not exist: {missing}"


def test_the_checks_find_what_they_look_for():
    """The path and link rules catch a stale path and skip placeholders and URLs."""
    assert _repository_path("hsr_handover/no_such_module.py") == "hsr_handover/no_such_module.py"
    assert not _exists("hsr_handover/no_such_module.py")
    assert _repository_path("robot/gone/away.py") == "robot/gone/away.py"
    assert _repository_path("tests/test_docs_links.py:12") == "tests/test_docs_links.py"
    assert _exists("scenarios/demo.yaml") and _exists("tests/test_docs_links.py")
    assert _repository_path("robot/gone/away.py", in_command=True) is None
    for skipped in (
        "SCENARIO.yaml", "OUT.json", "DIR", "scenarios/*.yaml", "scenarios/layouts/NAME.yaml",
        "color/000000000042.png", "perception/gng", "https://drake.mit.edu/x.py",
        "~/.cache/hsr_handover", "/usr/bin/chromium", "<name>_keypoints.json",
    ):  # fmt: skip
        assert _repository_path(skipped) is None, skipped
    assert _clean("docs/intent.md#targets") == "docs/intent.md"


def test_readme_is_a_front_door_under_250_lines():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) < README_MAX_LINES, f"README.md has {len(lines)} lines"


def test_readme_links_every_docs_file():
    linked = {(README.parent / _clean(target)).resolve() for target in _links(README)}
    unlinked = [doc.name for doc in sorted(DOCS.glob("*.md")) if doc.resolve() not in linked]
    assert not unlinked, f"README.md does not link {unlinked}"


def test_readme_holds_the_setup_commands_verbatim():
    """The install-and-demo command, and the install-and-test command that CI runs."""
    ci_lines = [line for line in (ROOT / ".ci" / "run").read_text().splitlines() if line.strip()]
    test_command = ci_lines[-1].strip()
    commands = [
        line.strip()
        for _, lang, body in FENCED.findall(README.read_text(encoding="utf-8"))
        if lang.strip() == "bash"
        for line in body.splitlines()
    ]
    assert INSTALL_AND_DEMO in commands
    assert test_command in commands, f"README.md lacks CI's command: {test_command}"
    assert "pytest" in test_command
