"""The optional compiled kernels (core/compiled.py): which path an operation asked for a
backend runs, and GMR_DISABLE_NUMBA=1 turning every package to its numpy path."""

from __future__ import annotations

import os
import subprocess
import sys
import types

import numpy as np
import pytest

from gmr_studio.core.compiled import chosen_kernels
from gmr_studio.core.demo import demo_motion
from gmr_studio.core.kinematics.engine import forward_kinematics

KERNELS = types.ModuleType("kernels")


@pytest.mark.parametrize(("backend", "expected"), [("auto", KERNELS), ("numba", KERNELS), ("numpy", None)])
def test_with_kernels_auto_and_numba_run_them_numpy_does_not(backend, expected):
    assert chosen_kernels(backend, KERNELS) is expected


def test_without_kernels_auto_and_numpy_run_numpy_and_numba_is_refused_saying_what_to_install():
    assert chosen_kernels("auto", None) is None and chosen_kernels("numpy", None) is None
    with pytest.raises(RuntimeError, match="install the 'fast' extra"):
        chosen_kernels("numba", None)


@pytest.mark.parametrize("backend", ["gpu", "Numba", ""])
def test_an_unknown_backend_is_refused_naming_the_known_ones(backend):
    with pytest.raises(ValueError, match=r"unknown backend .*'auto', 'numba' or 'numpy'"):
        chosen_kernels(backend, KERNELS)


def test_every_operation_refuses_an_unknown_backend_alike():
    with pytest.raises(ValueError, match="unknown backend 'gpu'"):
        forward_kinematics(demo_motion(), backend="gpu")


def test_disabling_numba_turns_every_package_to_numpy_with_the_same_kinematics(tmp_path):
    script = """
import sys, numpy as np, pytest
from gmr_studio.core.checks.passes import largest_steps
from gmr_studio.core.demo import demo_motion
from gmr_studio.core.edits.frame_programs import use_kernel
from gmr_studio.core.kinematics.engine import forward_kinematics
from gmr_studio.core.rotations.quaternions import matrix_from_quaternion
from gmr_studio.core.timebase.sampling import interpolate_rotations
motion = demo_motion()
positions = forward_kinematics(motion)[0]
for numba_only in (
    lambda: forward_kinematics(motion, backend="numba"),
    lambda: use_kernel("numba"),
    lambda: largest_steps(positions, backend="numba"),
    lambda: interpolate_rotations(motion.rotations, np.array([0.5]), backend="numba"),
    lambda: matrix_from_quaternion(np.array([[1.0, 0, 0, 0]]), backend="numba"),
):
    with pytest.raises(RuntimeError, match="numba backend is not available"):
        numba_only()
np.save(sys.argv[1], positions)
"""
    saved = tmp_path / "numpy.npy"
    env = {**os.environ, "GMR_DISABLE_NUMBA": "1"}
    subprocess.run([sys.executable, "-c", script, str(saved)], check=True, env=env, cwd=os.getcwd())
    np.testing.assert_allclose(np.load(saved), forward_kinematics(demo_motion())[0], rtol=0, atol=1e-12)
