"""The glTF reader gives the same numbers, bit for bit, with and without numba.

Its quaternion -> matrix conversion runs as a compiled kernel when numba is installed
(:func:`core.rotations.quaternions.matrix_from_quaternion`); the numpy path is the
reference. Both must give identical matrices for any quaternion a file can hold (any
length, int8/int16 normalised keys, a single one filling many frames), and every real glTF
of the shared data must read to identical motions either way (every skin's default
animation and every animation): the numpy side is read in a process with numba disabled.
The kernel is used where numba is loaded already; a process converting a few quaternions
without it (the FBX reader's child) does not load numba.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.gltf_in import gltf_contents
from gmr_studio.core.rotations.quaternions import compiled_at_hand, compiled_kernels, matrix_from_quaternion
from tests.conftest import shared_files

pytestmark = pytest.mark.skipif(compiled_kernels() is None, reason="numba is not installed")


def quaternions(rng: np.random.Generator, count: int) -> np.ndarray:
    """Quaternions (count, 4) of every kind a file holds: unit float32 keys, int8 and
    int16 normalised keys, lengths far from one, tiny and huge, with exact zeros."""
    unit = rng.normal(size=(count, 4))
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    kinds = [
        unit.astype(np.float32).astype(np.float64),
        np.maximum(np.round(unit * 127) / 127, -1.0),
        np.maximum(np.round(unit * 32767) / 32767, -1.0),
        unit * rng.uniform(0.5, 2.0, size=(count, 1)),
        unit * 10.0 ** rng.uniform(-150, 150, size=(count, 1)),
        np.where(rng.random((count, 4)) < 0.3, 0.0, unit),
    ]
    return np.concatenate(kinds)


@pytest.mark.parametrize("scalar_last", [False, True])
def test_compiled_matrices_are_numpys_bit_for_bit(scalar_last):
    q = quaternions(np.random.default_rng(7), 5000)
    compiled = matrix_from_quaternion(q, scalar_last=scalar_last, backend="numba")
    with np.errstate(all="ignore"):  # zero quaternions have no rotation: NaN either way
        reference = matrix_from_quaternion(q, scalar_last=scalar_last, backend="numpy")
    assert compiled.tobytes() == reference.tobytes()


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_float32_quaternions_give_the_matrices_of_their_float64_values(backend):
    """A file's float32 keys are converted as they are read: the same matrices as from
    their float64 copies, either way."""
    with np.errstate(over="ignore"):  # the huge ones overflow float32: a file holds none (refused)
        q = quaternions(np.random.default_rng(10), 2000).astype(np.float32)
    q = q[np.isfinite(q).all(axis=1)]
    with np.errstate(all="ignore"):
        stored = matrix_from_quaternion(q, scalar_last=True, backend=backend)
        reference = matrix_from_quaternion(q.astype(np.float64), scalar_last=True, backend="numpy")
    assert stored.dtype == np.float64
    assert stored.tobytes() == reference.tobytes()


def test_one_quaternion_fills_every_matrix_alike():
    q = quaternions(np.random.default_rng(8), 1)[3:4]
    compiled = matrix_from_quaternion(q, scalar_last=True, out=np.empty((5, 3, 3)), backend="numba")
    reference = matrix_from_quaternion(q, scalar_last=True, out=np.empty((5, 3, 3)), backend="numpy")
    assert compiled.tobytes() == reference.tobytes()
    assert (compiled == compiled[:1]).all()


def test_compiled_writes_into_a_column_of_a_block():
    """A node's matrices go straight into its column of the block of all nodes."""
    q = quaternions(np.random.default_rng(9), 200)
    block = np.zeros((len(q), 3, 3, 3))
    matrix_from_quaternion(q, scalar_last=True, out=block[:, 1], backend="numba")
    with np.errstate(all="ignore"):
        reference = matrix_from_quaternion(q, scalar_last=True, backend="numpy")
    assert block[:, 1].tobytes() == reference.tobytes()
    assert not block[:, [0, 2]].any()


def _read_all(path) -> dict[str, np.ndarray]:
    """Every animation of the file read: its rotations, translations and offsets by name."""
    count = max(1, len(gltf_contents(path)["animations"]))
    arrays = {}
    for index in range(count):
        motion = read_motion(path, animation=index) if count > 1 else read_motion(path)
        for name in ("rotations", "translations", "offsets", "has_translation"):
            arrays[f"{index}-{name}"] = getattr(motion, name)
    return arrays


@pytest.mark.parametrize("path", shared_files("gltf/**/*.gl[tb]*"))
def test_real_files_read_alike_with_and_without_numba(path, tmp_path):
    saved = tmp_path / "numpy.npz"
    script = (
        "import sys, numpy as np; from tests.test_gltf_compiled_agrees import _read_all; "
        "np.savez(sys.argv[2], **_read_all(sys.argv[1]))"
    )
    assert compiled_at_hand() is not None  # this process reads with the compiled kernel
    env = {**os.environ, "GMR_DISABLE_NUMBA": "1"}
    subprocess.run([sys.executable, "-c", script, str(path), str(saved)], check=True, env=env, cwd=os.getcwd())
    reference = np.load(saved)
    compiled = _read_all(path)
    assert sorted(compiled) == sorted(reference.files), json.dumps(sorted(compiled))
    for name, value in compiled.items():
        assert value.tobytes() == reference[name].tobytes(), name


def test_a_few_quaternions_converted_without_loading_numba():
    script = (
        "import sys, numpy as np; from gmr_studio.core.rotations.quaternions import matrix_from_quaternion; "
        "matrix_from_quaternion(np.array([[0.0, 0.0, 0.0, 1.0]]), scalar_last=True); print('numba' in sys.modules)"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"
