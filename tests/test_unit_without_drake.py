"""The numpy algorithms' unit tests run without Drake: in a fresh interpreter whose imports of
`pydrake` fail, every test of the algorithms below the Drake systems passes. (Their modules may
not import Drake: the import contracts in pyproject.toml say so; this proves their tests do
not need it either, so they run in seconds.) Run them alone with the same paths:
`python -m pytest` followed by UNIT_TESTS."""

from __future__ import annotations

import re
import subprocess
import sys

from tests.paths import REPO

UNIT_TESTS = [
    "tests/topology", "tests/robot/intent", "tests/robot/effectivity",
    "tests/robot/perception/test_active_gaze.py", "tests/robot/perception/test_attention.py",
    "tests/robot/perception/test_body_check.py", "tests/robot/perception/test_chest_plane.py",
    "tests/robot/perception/test_cross_check.py", "tests/robot/perception/test_facing.py",
    "tests/robot/perception/test_keypoint_filter.py", "tests/robot/perception/test_torso_depth.py",
    "tests/robot/handover/test_cycle.py", "tests/robot/planning/test_plan_view.py",
    "tests/robot/handover/test_take.py", "tests/robot/handover/test_hand_follower.py",
    "tests/robot/handover/test_put_back.py", "tests/robot/handover/test_correction_watch.py",
    "tests/robot/handover/test_person_points.py", "tests/robot/planning/test_plan.py",
    "tests/robot/planning/test_shortcut.py",
    "tests/world/person/test_human.py", "tests/world/sensors/test_detector_model.py",
    "tests/interface/test_openpose_formats.py", "tests/interface/test_person_tracking.py",
    "tests/test_output_files.py",
]  # fmt: skip

_WITHOUT_DRAKE = """
import sys
class NoDrake:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == "pydrake":
            raise ImportError("pydrake is not available in this run")
sys.meta_path.insert(0, NoDrake())
import pytest
sys.exit(pytest.main(sys.argv[1:]))
"""


def test_the_algorithms_unit_tests_pass_without_drake():
    result = subprocess.run(
        [sys.executable, "-c", _WITHOUT_DRAKE, *UNIT_TESTS, "-q", "-p", "no:cacheprovider"],
        capture_output=True, text=True, cwd=REPO, timeout=600, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout[-3000:]
    passed = re.search(r"(\d+) passed", result.stdout)
    assert passed and int(passed.group(1)) >= 250, result.stdout[-500:]
