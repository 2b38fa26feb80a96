"""Other Python BVH libraries computing the same positions (the optional ``bench`` extra).

Each peer reads the same tiled BVH file, computes every joint's world position for every
frame its own fastest documented way, and is checked against our positions (joints
matched by name; end sites where the peer has them). What each timed path starts from:

- ``pybvh``: ``frames_to_node_positions`` on its FK topology from the root positions and
  the Euler angles as stored (radians): Euler -> matrices -> FK, numpy, per joint.
- ``upc-pymotion``: ``pymotion.ops.skeleton_np.fk`` from the unit quaternions its
  ``BVH.get_data`` returns (rotations cached at load; 4x4 matrices per joint, numpy).
  Also timed with ``get_data`` included (from the Euler angles as stored).
- ``bvhio``: its transform hierarchy, ``loadPose(frame)`` then ``PositionWorld`` of every
  joint: one frame at a time through Python objects (float32 GLM), so it is timed on the
  first ``peer_frames`` frames only.

Every row is checked on the positions of its own timed run. A peer that is installed but
fails is not dropped: it gets a row whose ``failure`` says why (and never agrees).
"""

from __future__ import annotations

import dataclasses
import importlib.metadata
from collections.abc import Callable
from pathlib import Path

import numpy as np

from gmr_studio.core.benchmark.timing import time_call, time_returning


@dataclasses.dataclass(frozen=True)
class PeerResult:
    """One peer's timing and its agreement with our positions.

    frames : frames it was timed on; us_per_frame : best run / frames.
    max_error : largest distance from our position over the joints compared, in file
        units; relative_error : that over the skeleton's size (largest extent, frame 0).
    """

    name: str
    version: str
    starts_from: str
    frames: int
    us_per_frame: float
    max_error: float
    relative_error: float
    joints_compared: int
    failure: str = ""

    def agrees(self, tolerance: float = 1e-6) -> bool:
        return not self.failure and self.joints_compared > 0 and self.relative_error <= tolerance


def _version(distribution: str) -> str | None:
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return None


def _compare(ours: np.ndarray, names: tuple[str, ...], theirs: np.ndarray, their_names: list[str]) -> tuple[float, int]:
    """Largest distance between matching joints (by name) and how many were matched."""
    index = {name: j for j, name in enumerate(names)}
    pairs = [(k, index[n]) for k, n in enumerate(their_names) if n in index]
    if not pairs:
        return float("inf"), 0
    theirs_k, ours_j = (list(side) for side in zip(*pairs))
    frames = theirs.shape[0]
    error = np.linalg.norm(theirs[:, theirs_k] - ours[:frames, ours_j], axis=-1).max()
    return float(error), len(pairs)


def _pybvh(path: Path, repeat: int, frames: int) -> list[tuple[str, str, int, float, np.ndarray, list[str]]]:
    import pybvh
    from pybvh.spatial_coord import frames_to_node_positions

    bvh = pybvh.read_bvh_file(path)
    topology, root, angles = bvh.fk_topology, bvh.root_pos, bvh.joint_angles
    timing, positions = time_returning(
        lambda: frames_to_node_positions(topology, root_pos=root, joint_angles=angles), repeat
    )
    names = [_pybvh_name(node.name) for node in bvh.nodes]
    return [("pybvh", "Euler angles as stored", bvh.frame_count, timing.best, positions, names)]


def _pybvh_name(name: str) -> str:
    # pybvh names an end site 'EndSite<parent>'; our reader names it '<parent>_End'
    return f"{name[len('EndSite') :]}_End" if name.startswith("EndSite") else name


def _pymotion(path: Path, repeat: int, frames: int) -> list[tuple[str, str, int, float, np.ndarray, list[str]]]:
    from pymotion.io.bvh import BVH
    from pymotion.ops.skeleton_np import fk

    bvh = BVH()
    bvh.load(str(path))
    rotations, local, parents, offsets, _, _ = bvh.get_data()
    names = [str(n) for n in bvh.data["names"]]
    count = rotations.shape[0]
    cached, cached_positions = time_returning(lambda: fk(rotations, local[:, 0], offsets, parents)[0], repeat)

    def from_euler() -> np.ndarray:
        quaternions, positions, parent_list, joint_offsets, _, _ = bvh.get_data()
        return fk(quaternions, positions[:, 0], joint_offsets, parent_list)[0]

    stored, stored_positions = time_returning(from_euler, max(1, repeat // 2))
    return [
        ("upc-pymotion", "quaternions cached at load", count, cached.best, cached_positions, names),
        ("upc-pymotion", "Euler angles as stored (get_data + fk)", count, stored.best, stored_positions, names),
    ]


def _bvhio(path: Path, repeat: int, frames: int) -> list[tuple[str, str, int, float, np.ndarray, list[str]]]:
    import bvhio

    root = bvhio.readAsHierarchy(str(path))
    layout = [joint for joint, _, _ in root.layout()]
    count = min(frames, root.getKeyframeRange()[1] + 1)
    out = np.empty((count, len(layout), 3))

    def positions() -> None:
        for f in range(count):
            root.loadPose(f)
            for k, joint in enumerate(layout):
                point = joint.PositionWorld
                out[f, k] = (point.x, point.y, point.z)

    timing = time_call(positions, max(1, repeat // 2))
    return [("bvhio", "Euler angles as stored, one frame at a time", count, timing.best, out, [j.Name for j in layout])]


#: (distribution name, runner, reads the whole file?) — bvhio reads a short file only
PEERS: tuple[tuple[str, Callable, bool], ...] = (
    ("pybvh", _pybvh, True),
    ("upc-pymotion", _pymotion, True),
    ("bvhio", _bvhio, False),
)


def run_peers(
    full_path: Path,
    short_path: Path,
    ours: np.ndarray,
    names: tuple[str, ...],
    size: float,
    repeat: int,
    peer_frames: int,
    log: Callable[[str], None] = print,
) -> list[PeerResult]:
    """Time every installed peer and compare each row's own positions with ``ours`` (F, J, 3).

    A peer that raises gets a row with its ``failure`` (it must not stop the benchmark, nor
    vanish from it)."""
    results = []
    for distribution, runner, whole in PEERS:
        version = _version(distribution)
        if version is None:
            log(f"  {distribution}: not installed (pip install '.[bench]')")
            continue
        try:
            rows = runner(full_path if whole else short_path, repeat, peer_frames)
        except Exception as exc:
            failure = f"{type(exc).__name__}: {exc}"
            log(f"  {distribution} {version}: FAILED: {failure}")
            nan = float("nan")
            results.append(PeerResult(distribution, version, "(failed)", 0, nan, nan, nan, 0, failure))
            continue
        for name, starts_from, frames, seconds, positions, their_names in rows:
            error, compared = _compare(ours, names, positions, their_names)
            results.append(
                PeerResult(name, version, starts_from, frames, seconds / frames * 1e6, error, error / size, compared)
            )
    return results
