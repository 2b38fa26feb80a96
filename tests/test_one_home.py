"""One home per concept (issue 21): one fit, one up-axis rule, rotation helpers in
core.rotations.euler, the marker alignment in core; the app and the CLI call them."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.compare import fit_alignment
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import procrustes
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.rigs import make_rig
from gmr_studio.core.rotations.euler import angle_axis_degrees, axis_permutations, rotation_about_axis
from gmr_studio.core.space import similarity as fit
from gmr_studio.core.space.up_axis import detect_up_axis, up_axis_of


def test_one_fit_for_comparisons_and_markers(rng):
    from gmr_studio.core.markers import alignment as marker_alignment

    assert procrustes.fit_rigid is fit.fit_rigid
    b = rng.normal(size=(200, 3))
    truth = Rotation.random(random_state=4).as_matrix()
    a = 2.5 * b @ truth.T + [1.0, -2.0, 0.5]
    rotation, translation, scale = fit.fit_points(a, b, scaled=True)
    np.testing.assert_allclose(rotation, truth, atol=1e-12)
    assert scale == pytest.approx(2.5, rel=1e-12)
    same, s, offset, rms = marker_alignment.similarity_fit(b, a)
    np.testing.assert_allclose(same, rotation, atol=1e-13)
    assert s == pytest.approx(scale, rel=1e-13) and rms < 1e-12
    np.testing.assert_allclose(offset, translation, atol=1e-12)
    rotations = fit.fit_rigid(b[:20], (b[:20] @ truth.T)[None])[0]
    np.testing.assert_allclose(rotations[0], truth, atol=1e-12)


@pytest.mark.parametrize("kind", ["rigid", "similarity"])
def test_a_fit_onto_a_mirror_image_is_a_rotation_not_a_reflection(kind):
    """The reflection fix: B is A mirrored (x -> -x); the best proper rotation has det +1
    and leaves a residual, where a reflection would fit exactly."""
    walk = make_rig("metres")
    a = world_positions(walk)[:60]
    b = a * [-1.0, 1.0, 1.0]
    rotation, _translation, _scale = fit_alignment(a, b, kind)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-12)
    u, _, vt = np.linalg.svd(np.einsum("fji,fjk->ik", a - a.mean((0, 1)), b - b.mean((0, 1))))
    assert np.linalg.det(u @ vt) < 0  # the unconstrained fit would be a reflection


def test_one_up_axis_rule():
    metres, z_up, pinned = make_rig("metres"), make_rig("z_up_millimetres"), make_rig("origin_root")
    # a file that states nothing: the figure decides, for conversions and views alike
    assert [up_axis_of(m) for m in (metres, z_up, pinned)] == ["y", "z", "y"]
    stated = z_up.replace(facts=FileFacts(up_axis="z"))
    assert up_axis_of(stated) == "z"
    lying = z_up.replace(facts=FileFacts(up_axis="y"))
    assert up_axis_of(lying) == "y"  # what a file states wins over what it looks like
    assert detect_up_axis(world_positions(z_up)) == "z"


def test_rotation_helpers_live_in_core_rotations():
    permutations = axis_permutations()
    assert len(permutations) == 24 and all(np.linalg.det(p) == 1.0 for p in permutations)
    turn = rotation_about_axis("Z", np.radians(90.0))
    np.testing.assert_allclose(turn @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
    degrees, axis = angle_axis_degrees(rotation_about_axis("X", np.radians(30.0)))
    assert degrees == pytest.approx(30.0, abs=1e-12) and np.allclose(axis, [1.0, 0.0, 0.0])
    degrees, axis = angle_axis_degrees(rotation_about_axis("Y", np.pi))
    assert degrees == pytest.approx(180.0) and np.allclose(np.abs(axis), [0.0, 1.0, 0.0])
    assert angle_axis_degrees(np.eye(3)) == (0.0, pytest.approx([0.0, 1.0, 0.0]))
