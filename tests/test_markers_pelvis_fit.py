"""The pelvis fit residual on real markers (CMU 01_01.c3d, the cmu map, 01.asf): the real
markers' fit to the cluster template and the three-marker Procrustes on real markers, checked
frame by frame against a plain per-frame computation, and varying as real markers do."""

from __future__ import annotations

import functools

import numpy as np

from gmr_studio.core.formats import load_gmr
from gmr_studio.core.markers import load_marker_map, read_markers, recover_pelvis
from gmr_studio.core.markers.pelvis import rest_positions
from gmr_studio.core.markers.report import pelvis_fit_summary, pelvis_fit_text
from tests.conftest import shared_path

CLUSTER = ("LFWT", "RFWT", "LBWT", "RBWT")


@functools.cache
def cmu_pelvis():
    markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    skeleton = load_gmr(shared_path("cmu/subject01/01.asf"))
    return markers, skeleton, recover_pelvis(markers, "cmu", skeleton=skeleton)


def kabsch(source: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One frame's least-squares rotation and translation taking source (K, 3) onto target."""
    s0, t0 = source.mean(axis=0), target.mean(axis=0)
    u, _, vt = np.linalg.svd((target - t0).T @ (source - s0))
    d = np.sign(np.linalg.det(u @ vt))
    rotation = u @ np.diag([1.0, 1.0, d]) @ vt
    return rotation, t0 - rotation @ s0


def note_frame(x1, x2, x3) -> np.ndarray:
    p1 = (x1 - x2) / np.linalg.norm(x1 - x2)
    b = x1 - x3
    p2 = b - (b @ p1) * p1
    p2 /= np.linalg.norm(p2)
    return np.column_stack([p1, p2, np.cross(p1, p2)])


def test_the_fit_is_the_real_markers_against_the_template_frame_by_frame():
    markers, skeleton, pelvis = cmu_pelvis()
    cmu = load_marker_map("cmu")
    root, lhip, rhip = (cmu.virtual[cmu.names.index(n)] for n in ("root", "lhipjoint", "rhipjoint"))
    assert root.markers == CLUSTER and pelvis.fit_labels == CLUSTER[:3]
    home = cmu.alignment.inverse().apply(rest_positions(skeleton, ("root", "lhipjoint", "rhipjoint")))
    # the template in the home pose: the rigid motion taking the three offsets onto their home
    to_home, shift = kabsch(np.stack([root.offset, lhip.offset, rhip.offset]), home)
    raw_home = root.template[:3] @ to_home.T + shift
    index = [markers.index(label) for label in CLUSTER]
    checked = 0
    for f in range(0, markers.n_frames, 25):
        real = markers.positions[f, index]
        if not np.isfinite(real).all():
            continue
        rotation, translation = kabsch(root.template, real)
        cluster_rms = np.sqrt(np.mean(np.sum((root.template @ rotation.T + translation - real) ** 2, axis=1)))
        assert abs(pelvis.marker_fit[f] - cluster_rms) < 1e-9
        # the note's Procrustes on LFWT, RFWT, LBWT: R = P H^T (both orthonormal), home placed at X1
        turn = note_frame(*real[:3]) @ note_frame(*raw_home).T
        np.testing.assert_allclose(pelvis.rotations[f], turn, atol=1e-9)
        placed = real[0] + (raw_home - raw_home[0]) @ turn.T
        three_rms = np.sqrt(np.mean(np.sum((placed - real[:3]) ** 2, axis=1)))
        assert abs(pelvis.residuals[f] - three_rms) < 1e-9
        virtual_home = real[0] + (home - raw_home[0]) @ turn.T
        virtual = [rotation @ v.offset + translation for v in (root, lhip, rhip)]
        np.testing.assert_allclose(
            pelvis.virtual_residuals[f], np.linalg.norm(virtual_home - virtual, axis=1), atol=1e-9
        )
        checked += 1
    assert checked > 100


def test_the_residuals_vary_as_real_markers_do():
    _, _, pelvis = cmu_pelvis()
    summary = pelvis_fit_summary(pelvis)
    three, cluster = summary["procrustes"], summary["markers"]
    # measured: 0.33 / 2.49 / 5.00 / 15.20 mm and 0.44 / 1.99 / 3.95 / 11.79 mm
    assert 0.1 < three["min"] < 1.0 < 1.5 < three["median"] < 4.0 < three["p95"] < 8.0 < three["max"] < 25.0
    assert 0.1 < cluster["min"] < 1.0 < cluster["median"] < 3.0 < cluster["p95"] < 6.0 < cluster["max"] < 20.0
    for name in ("root", "lhipjoint", "rhipjoint"):
        figures = summary["virtual"][name]["residual"]
        assert figures["min"] < 0.5 < figures["median"] < figures["p95"] < figures["max"]
    # every frame has a pelvis: where a cluster marker was missing, the lab's gap filling
    # (its computed samples, kept) completes it
    assert int(pelvis.valid.sum()) == 2751 and int(np.isfinite(pelvis.residuals).sum()) == 2751
    text = pelvis_fit_text(summary)
    assert "Procrustes on LFWT, RFWT, LBWT: 0.33 / 2.49 / 5.00 / 15.20" in text
    markers, skeleton, _ = cmu_pelvis()
    measured = recover_pelvis(markers.without_computed(), "cmu", skeleton=skeleton)  # the cameras' samples only
    assert int(measured.valid.sum()) == 2750 and int(np.isfinite(measured.residuals).sum()) == 2745
    assert "incomplete in frames 740, 905-906, 1148, 1198" in " ".join(measured.reasons)
