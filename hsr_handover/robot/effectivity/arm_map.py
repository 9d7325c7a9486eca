"""The HSR arm's effectivity (paper 3.1, fig. 8): a Growing Cell Structures map of the palm
positions the five arm joints reach with the base fixed, each node carrying the joint vector
that put the palm there, so a point gives a joint-space first guess by eq. 11.

The map learns from forward-kinematics samples drawn uniformly within the joint limits
(`kinematics.hsr_arm`, checked against the SDF model in the tests). Building it takes seconds,
so it is built once and kept on disk, keyed by everything it depends on: the kinematic
constants, the model file and the parameters (`load_or_build`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from hsr_handover.kinematics import hsr_arm
from hsr_handover.model_files import HSR_SDF
from hsr_handover.topology import GrowingCellStructures

CACHE_ENV = "HSR_HANDOVER_CACHE"
"""Environment variable naming the cache folder (default ~/.cache/hsr_handover)."""
MODEL_FILE = HSR_SDF


@dataclasses.dataclass(frozen=True)
class ArmMapParams:
    """max_nodes: the map's size (the paper's arm map has 108). samples: forward-kinematics
    samples learnt from. signals: training signals. mu3: eq. 11's neighbour weighting (1/m).
    seed: the samples' and the map's random seed."""

    max_nodes: int = 200
    samples: int = 20_000
    signals: int = 60_000
    mu3: float = 30.0
    seed: int = 0

    def __post_init__(self) -> None:
        if not (isinstance(self.max_nodes, int) and self.max_nodes >= 108):
            raise ValueError(f"max_nodes: expected an integer >= 108, got {self.max_nodes}")
        for name in ("samples", "signals"):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= self.max_nodes):
                raise ValueError(f"{name}: expected an integer >= max_nodes, got {value}")
        if not (np.isfinite(self.mu3) and self.mu3 >= 0):
            raise ValueError(f"mu3: expected a finite value >= 0, got {self.mu3}")


class ArmEffectivity:
    """The arm's reachable range in the base frame (m), as a map of `cells` nodes."""

    def __init__(self, cells: GrowingCellStructures, params: ArmMapParams):
        self.cells, self.params = cells, params
        edges = cells.edges
        lengths = np.linalg.norm(cells.nodes[edges[:, 0]] - cells.nodes[edges[:, 1]], axis=1)
        self.resolution = float(np.median(lengths))
        """Median edge length (m): how finely the map resolves the range."""

    @classmethod
    def build(cls, params: ArmMapParams | None = None) -> ArmEffectivity:
        """Learn the map from `params.samples` forward-kinematics samples."""
        params = ArmMapParams() if params is None else params
        rng = np.random.default_rng(params.seed)
        joints = hsr_arm.sample_arm_joints(params.samples, rng)
        cells = GrowingCellStructures(
            max_nodes=params.max_nodes, mu3=params.mu3, random_state=params.seed
        )
        cells.fit(hsr_arm.palm_position(joints), joints, n_signals=params.signals)
        return cls(cells, params)

    @property
    def nodes(self) -> np.ndarray:
        """Node positions (n, 3), base frame (m)."""
        return self.cells.nodes

    @property
    def joints(self) -> np.ndarray:
        """Each node's joint vector (n, 5), in `hsr_arm.ARM_JOINT_NAMES` order."""
        return self.cells.payload

    def reachable(self, points: np.ndarray, tol: float | None = None) -> np.ndarray:
        """Whether each point (n, 3) lies within `tol` (default: half the map's resolution) of
        a node: the map's answer, which inverse kinematics must confirm."""
        return self.cells.reachable(points, self.resolution / 2 if tol is None else tol)

    def seed(self, points: np.ndarray) -> np.ndarray:
        """A joint-space first guess (n, 5) for palm positions (n, 3): eq. 11's weighted joint
        vectors of the nearest node and its neighbours."""
        return np.clip(self.cells.payload_at(points), hsr_arm.ARM_LOWER, hsr_arm.ARM_UPPER)

    def nodes_near(self, point: np.ndarray, radius: float) -> np.ndarray:
        """Indices of the nodes within `radius` (m) of `point` (3,)."""
        gaps = np.linalg.norm(self.nodes - np.asarray(point, dtype=float).reshape(1, 3), axis=1)
        return np.flatnonzero(gaps <= radius)

    def palm_errors(self, points: np.ndarray) -> np.ndarray:
        """How far (m) the palm lands from each point when the arm takes the eq. 11 seed."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        return np.linalg.norm(hsr_arm.palm_position(self.seed(points)) - points, axis=1)


def cache_key(params: ArmMapParams) -> str:
    """A digest of everything the map depends on: the kinematic constants, the model file and
    the parameters."""
    digest = hashlib.sha256()
    constants = {name: np.asarray(getattr(hsr_arm, name)).tolist() for name in (
        "ARM_LOWER", "ARM_UPPER", "ARM_LIFT_ORIGIN", "ARM_FLEX_ORIGIN", "ARM_ROLL_ORIGIN",
        "PALM_IN_WRIST_ROLL")}  # fmt: skip
    digest.update(json.dumps([constants, dataclasses.asdict(params)], sort_keys=True).encode())
    digest.update(MODEL_FILE.read_bytes())
    return digest.hexdigest()[:16]


def default_cache_dir() -> Path:
    return Path(os.environ.get(CACHE_ENV) or Path.home() / ".cache" / "hsr_handover")


def load_or_build(
    params: ArmMapParams | None = None, cache_dir: Path | None = None
) -> tuple[ArmEffectivity, bool]:
    """The arm map from the cache, or built and cached when missing or unreadable; also whether
    it came from the cache. A cache that cannot be written leaves the map built in memory."""
    params = ArmMapParams() if params is None else params
    folder = default_cache_dir() if cache_dir is None else Path(cache_dir)
    path = folder / f"arm_effectivity_{cache_key(params)}.npz"
    try:
        return ArmEffectivity(GrowingCellStructures.load(path), params), True
    except (OSError, ValueError, KeyError, zipfile.BadZipFile):
        pass  # missing or unreadable: build it anew
    arm_map = ArmEffectivity.build(params)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, suffix=".npz", delete=False) as handle:
            arm_map.cells.save(handle)
        os.replace(handle.name, path)  # whole or not at all, even with two builders at once
    except OSError:
        pass
    return arm_map, False
