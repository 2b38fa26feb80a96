"""The FBX reader composes the skeleton in compiled code (numba) or with numpy, the
reference, and the two read every file alike: rotations to 1e-12, translations and offsets
to 1e-12 of the figure's size, the same moving joints and notes.

Every real FBX of the shared data is read with numba and, in a process with numba
disabled, without it; a made-up worker result covers what those files do not hold: nodes
sent as channels (a baked take), a nonzero constant angle, pre- and post-rotations,
pivots and offsets, an armature turned and scaled above the root, scales that are not
uniform and change over the frames, rest orientations of a bind pose, and nodes evaluated
by ufbx beside them.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.core.compiled import optional_kernels
from gmr_studio.core.formats.fbx_in import read_fbx
from gmr_studio.core.formats.fbx_in.skeleton import motion_from_nodes
from gmr_studio.core.formats.fbx_in.worker import CHANNEL_BLOCK
from gmr_studio.core.rotations.quaternions import quaternion_from_matrix
from tests.conftest import shared_files

pytestmark = pytest.mark.skipif(
    optional_kernels("gmr_studio.core.formats.fbx_in._kernels") is None, reason="numba is not installed"
)

#: rotations agree to this; translations and offsets to this of the figure's size
AGREEMENT = 1e-12

READ_WITHOUT_NUMBA = """
import sys, numpy as np
from gmr_studio.core.compiled import optional_kernels
from gmr_studio.core.formats.fbx_in import read_fbx
assert optional_kernels("gmr_studio.core.formats.fbx_in._kernels") is None
m = read_fbx(sys.argv[1])
np.savez(sys.argv[2], rotations=m.rotations, translations=m.translations, offsets=m.offsets,
         has_translation=m.has_translation, comments=np.array(m.comments))
"""


def assert_alike(compiled, reference: dict) -> None:
    size = compiled.size
    assert np.abs(compiled.rotations - reference["rotations"]).max(initial=0) <= AGREEMENT
    assert np.abs(compiled.translations - reference["translations"]).max(initial=0) <= AGREEMENT * size
    assert np.abs(compiled.offsets - reference["offsets"]).max(initial=0) <= AGREEMENT * size
    assert np.array_equal(compiled.has_translation, reference["has_translation"])
    assert list(compiled.comments) == list(reference["comments"])


@pytest.mark.parametrize("path", shared_files("fbx/*.fbx"))
def test_real_files_read_alike_with_and_without_numba(path, tmp_path):
    saved = tmp_path / "numpy.npz"
    env = {**os.environ, "GMR_DISABLE_NUMBA": "1"}
    subprocess.run([sys.executable, "-c", READ_WITHOUT_NUMBA, str(path), str(saved)], check=True, env=env)
    with np.load(saved) as reference:
        assert_alike(read_fbx(path), dict(reference))


def rest(rng: np.random.Generator) -> np.ndarray:
    """A rest orientation (3, 3), as a bind pose gives one."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.diag(r)) * np.sign(np.linalg.det(q * np.sign(np.diag(r))))


def worker_result(rng: np.random.Generator, frames: int) -> tuple[dict, dict]:
    """A worker's output (meta, arrays) for a small skeleton under a static armature."""
    names = ["Armature", "Hips", "Spine", "Head", "Arm", "Hand", "Leg"]
    parents = [-1, 0, 1, 2, 2, 4, 1]
    rows, row_names = [], []

    def row(node: int, channel: int, values: np.ndarray) -> str:
        rows.append(values)
        row_names.append(f"c{node}.{channel}")
        return row_names[-1]

    def channels(node: int, constant: dict[int, float] | None = None) -> list:
        constant = constant or {}
        out = []
        for c in range(9):
            if c in constant:
                out.append(constant[c])
            elif c < 3:
                out.append(row(node, c, rng.normal(size=frames) * 10))
            elif c < 6:
                out.append(row(node, c, rng.uniform(-180, 180, frames)))
            else:
                out.append(row(node, c, rng.uniform(0.5, 2.0, frames)))
        return out

    zero = [0.0, 0.0, 0.0]
    still = {name: zero for name in ("PreRotation", "PostRotation", "RotationPivot", "RotationOffset")}
    still |= {"ScalingPivot": zero, "ScalingOffset": zero}
    armature = [1.0, 2.0, 3.0, -90.0, 0.0, 30.0, 2.0, 2.0, 3.0]
    nodes = {
        "0": {"kind": "channels", "order": 0, "stack": still, "channels": armature},
        "1": {"kind": "channels", "order": 0, "stack": still, "channels": channels(1)},
        "2": {
            "kind": "channels",
            "order": 4,
            "stack": {**still, "PreRotation": [10.0, 20.0, 30.0], "PostRotation": [5.0, 0.0, -7.0]},
            "channels": channels(2, {3: 15.0, 6: 1.0, 7: 1.0, 8: 1.0}),
        },
        "3": {
            "kind": "channels",
            "order": 2,
            "stack": {**still, "RotationPivot": [1.0, 2.0, 3.0], "ScalingOffset": [0.5, 0.0, -0.5]},
            "channels": channels(3),
        },
        "4": {"kind": "evaluated"},
        "5": {"kind": "static"},
        "6": {
            "kind": "channels",
            "order": 5,
            "stack": {**still, "PreRotation": [0.0, 90.0, 0.0]},
            "channels": channels(6),
        },
    }
    turns = rng.normal(size=(frames, 4))
    arrays = {
        CHANNEL_BLOCK: np.array(rows),
        "t4": rng.normal(size=(frames, 3)),
        "q4": turns / np.linalg.norm(turns, axis=1, keepdims=True),
        "s4": rng.uniform(0.5, 2.0, (frames, 3)),
        "t5": np.array([[0.0, 4.0, 0.0]]),
        "q5": quaternion_from_matrix(np.eye(3)[None], scalar_last=True),
        "s5": np.ones((1, 3)),
    }
    meta = {
        "unit_meters": 0.01,
        "axes": [0, 2, 4],
        "frame_rate": 30.0,
        "version": 7400,
        "ascii": False,
        "creator": "made up",
        "meshes": 0,
        "cameras": 0,
        "lights": 0,
        "stacks": [{"name": "Take", "begin": 0.0, "end": (frames - 1) / 30.0, "layers": ["Base"]}],
        "names": names,
        "parents": parents,
        "types": [0, 5, 5, 5, 5, 5, 5],
        "inherit": [0] * 7,
        "orders": [nodes[str(k)].get("order", 0) for k in range(7)],
        "take": 0,
        "joints": [1, 2, 3, 4, 5, 6],
        "above": [0],
        "selection": "6 bones",
        "frames": frames,
        "nodes": nodes,
        "channel_rows": row_names,
        "bind": {"source": "the file's bind pose", "linear": {str(k): rest(rng).tolist() for k in (1, 2, 4)}},
    }
    return meta, arrays


def test_a_made_up_take_of_every_kind_of_node_composes_alike():
    meta, arrays = worker_result(np.random.default_rng(3), 257)
    compiled = motion_from_nodes(meta, arrays, backend="numba")
    reference = motion_from_nodes(meta, arrays, backend="numpy")
    assert_alike(compiled, {name: getattr(reference, name) for name in ("rotations", "translations", "offsets")} | {
        "has_translation": reference.has_translation, "comments": reference.comments})  # fmt: skip
    assert compiled.has_translation.all() and compiled.n_frames == 257
