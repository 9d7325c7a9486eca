"""The arm's effectivity map: size, eq. 11 seeds, reachability, and the on-disk cache."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from hsr_handover.kinematics.hsr_arm import ARM_LOWER, ARM_UPPER, palm_position, sample_arm_joints
from hsr_handover.robot.effectivity import ArmEffectivity, ArmMapParams, arm_map, load_or_build

SMALL = ArmMapParams(max_nodes=120, samples=6_000, signals=20_000)


@pytest.fixture(scope="module")
def built() -> ArmEffectivity:
    return ArmEffectivity.build(SMALL)


def _targets(n: int = 1000, seed: int = 7) -> np.ndarray:
    return palm_position(sample_arm_joints(n, np.random.default_rng(seed)))


def test_the_map_has_the_papers_nodes_each_with_joints_in_limits(built):
    assert built.nodes.shape == (120, 3) and built.joints.shape == (120, 5)
    assert np.all((built.joints >= ARM_LOWER) & (built.joints <= ARM_UPPER))
    assert 0.05 < built.resolution < 0.3


def test_eq11_seeds_put_the_palm_near_reachable_targets(built):
    errors = built.palm_errors(_targets())
    assert np.median(errors) < 0.07 and np.percentile(errors, 95) < 0.15
    seeds = built.seed(_targets(50))
    assert np.all((seeds >= ARM_LOWER) & (seeds <= ARM_UPPER))


def test_reachability_follows_the_arms_range(built):
    assert built.reachable(_targets()).mean() > 0.9
    far = np.array([[2.5, 0.0, 0.8], [0.0, 0.0, 2.5], [-1.0, -1.0, 0.2]])
    assert not built.reachable(far).any()
    assert not built.reachable(np.array([[np.nan, 0.0, 0.5]])).any()


def test_nodes_near_a_point_are_those_within_the_radius(built):
    point = built.nodes[0]
    near = built.nodes_near(point, 0.2)
    assert 0 in near
    gaps = np.linalg.norm(built.nodes - point, axis=1)
    np.testing.assert_array_equal(near, np.flatnonzero(gaps <= 0.2))


def test_the_first_call_builds_and_caches_later_calls_load_the_same_map(tmp_path):
    first, cached = load_or_build(SMALL, tmp_path)
    again, cached_again = load_or_build(SMALL, tmp_path)
    assert not cached and cached_again
    np.testing.assert_array_equal(first.nodes, again.nodes)
    np.testing.assert_array_equal(first.joints, again.joints)
    other, cached_other = load_or_build(dataclasses.replace(SMALL, seed=1), tmp_path)
    assert not cached_other and not np.array_equal(other.nodes, first.nodes)
    assert len(list(tmp_path.glob("arm_effectivity_*.npz"))) == 2


def test_a_corrupt_cache_is_rebuilt_and_an_unwritable_one_is_skipped(tmp_path):
    _, _ = load_or_build(SMALL, tmp_path)
    (cached,) = tmp_path.glob("arm_effectivity_*.npz")
    cached.write_bytes(b"not an npz")
    rebuilt, from_cache = load_or_build(SMALL, tmp_path)
    assert not from_cache and rebuilt.nodes.shape == (120, 3)
    assert load_or_build(SMALL, tmp_path)[1]  # written again, whole
    blocked = tmp_path / "file"
    blocked.write_text("a file where the folder should be")
    unwritable, from_cache = load_or_build(SMALL, blocked / "cache")
    assert not from_cache and unwritable.nodes.shape == (120, 3)


def test_the_cache_key_follows_the_model_file(tmp_path, monkeypatch):
    key = arm_map.cache_key(SMALL)
    copy = tmp_path / "hsrb.sdf"
    copy.write_bytes(arm_map.MODEL_FILE.read_bytes() + b"<!-- changed -->")
    monkeypatch.setattr(arm_map, "MODEL_FILE", copy)
    assert arm_map.cache_key(SMALL) != key


@pytest.mark.parametrize(
    "field, value", [("max_nodes", 50), ("samples", 10), ("signals", 1.5), ("mu3", -1.0)]
)
def test_params_are_checked(field, value):
    with pytest.raises(ValueError, match=field):
        ArmMapParams(**{field: value})


def test_a_truncated_cache_is_rebuilt(tmp_path):
    load_or_build(SMALL, tmp_path)
    (cached,) = tmp_path.glob("arm_effectivity_*.npz")
    cached.write_bytes(cached.read_bytes()[:200])  # a zip cut short, as by a full disk
    rebuilt, from_cache = load_or_build(SMALL, tmp_path)
    assert not from_cache and rebuilt.nodes.shape == (120, 3)
