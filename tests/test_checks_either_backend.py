"""The checks find the same in real files whichever backend computes their passes over the
frames (core.checks.passes): the compiled kernels and the numpy reference give the same
findings (kind, joints, frames, severity), their values equal to rounding (sums of three or
nine products added in another order), with thresholds at their defaults and set low enough
to find thousands of things."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, run_checks
from gmr_studio.core.checks import passes as checks_passes
from gmr_studio.core.checks.markers import run_marker_checks
from gmr_studio.core.formats import read_motion
from gmr_studio.core.kinematics.engine import have_numba
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import read_markers
from tests.conftest import shared_files

#: low thresholds: pops, jitter, flips, slides, bones and holds found by the hundred
SENSITIVE = CheckSettings(
    pop_mad=3.0,
    pop_limits=(0.0005, 0.002, 0.01),
    jitter_limits=(0.0003, 0.001, 0.005),
    flip_limits=(5.0, 20.0, 60.0),
    flip_speed=150.0,
    skate_limits=(0.001, 0.01, 0.05),
    skate_speed=0.005,
    penetration_limits=(0.002, 0.01, 0.05),
    bone_limits=(0.01, 0.5, 5.0),
    teleport_limits=(0.005, 0.02, 0.1),
    same_pose=1e-5,
)
MOTIONS = [*shared_files("cmu/subject01/01_01.bvh"), *shared_files("bvh/*.bvh")]
MARKERS = [*shared_files("c3d/c3dorg_s03_gait-pig.c3d"), *shared_files("trc/opensim-core_markers_walk.trc")]


def _both(find, monkeypatch):
    """``find()`` with the compiled passes, then with numpy's (the backend is chosen when
    core.checks.passes is imported, so the test takes its kernels away to get numpy's)."""
    compiled = find()
    monkeypatch.setattr(checks_passes, "_kernels", None)
    return compiled, find()


def _assert_same(compiled, reference):
    assert [(f.kind, f.joints, f.start, f.end, f.severity) for f in compiled] == [
        (f.kind, f.joints, f.start, f.end, f.severity) for f in reference
    ]
    np.testing.assert_allclose([f.value for f in compiled], [f.value for f in reference], rtol=1e-12)


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
@pytest.mark.parametrize("settings", [CheckSettings(), SENSITIVE], ids=["default", "sensitive"])
@pytest.mark.parametrize("path", MOTIONS)
def test_a_motion_gets_the_same_findings_from_either_backend(path, settings, monkeypatch):
    motion = read_motion(path)
    positions = world_positions(motion)
    compiled, reference = _both(lambda: run_checks(motion, settings, positions), monkeypatch)
    assert compiled or settings is not SENSITIVE
    _assert_same(compiled, reference)


@pytest.mark.skipif(not have_numba(), reason="numba is not installed")
@pytest.mark.parametrize("settings", [CheckSettings(), SENSITIVE], ids=["default", "sensitive"])
@pytest.mark.parametrize("path", MARKERS)
def test_markers_get_the_same_findings_from_either_backend(path, settings, monkeypatch):
    markers = read_markers(path)
    compiled, reference = _both(lambda: run_marker_checks(markers, settings)[1], monkeypatch)
    _assert_same(compiled, reference)
