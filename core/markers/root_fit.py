"""Where the closed form puts the root: the least-squares translation given its rotations.

The paper's closed form stands the root at the pelvis root virtual marker (X1, from the
waist markers alone) and hangs every joint from it with the skeleton's fixed bone lengths.
With ``root="fit"`` (:func:`core.markers.solve.solve_positions`'s default) the rotations stay
the closed form's and the root is placed, per frame, by the translation ``t`` minimising the
weighted squared distances between the model's joints and their virtual markers,

    t = sum_j w_j (m_j - p_j) / sum_j w_j,

over the joints seen in that frame whose positions hang from the root: the translation step
of the Procrustes fit (Arun K.S., Huang T.S., Blostein S.D. 1987, "Least-squares fitting of
two 3-D point sets", IEEE Trans. PAMI 9:698-700: with the rotation fixed, the optimal
translation matches the weighted centroids) and of the fixed-length fit of a skeleton to all
the markers that Vicon's solver, whose output CMU's AMC files are, and OpenSim's inverse
kinematics make (Lu T.-W., O'Connor J.J. 1999, "Bone position estimation from skin marker
co-ordinates using global optimisation with joint constraints", J. Biomech. 32:129-134). The
weights are the map's inverse calibration variances (the refinement's), 1 without them.

Still a closed form (no iteration), and exact on markers generated from a known skeleton:
the differences are then zero, so is ``t``. ``root="pelvis"`` keeps the paper's X1.
"""

from __future__ import annotations

from collections.abc import Collection

import numpy as np

from gmr_studio.core.model.motion import Motion


def hanging_from_root(skeleton: Motion, root: int, split_roots: Collection[int], have: np.ndarray) -> np.ndarray:
    """(F, J) bool: the joints whose position in the solved chain follows ``root``'s translation.

    ``have`` (F, J) bool: the joint is measured. A joint of ``split_roots`` (a root of its own,
    holding its measured position) stops the chain where it is measured; elsewhere it and its
    descendants hang from their parent as any joint.
    """
    n_frames, n_joints = have.shape
    follows = np.zeros((n_frames, n_joints), bool)
    follows[:, root] = True
    for j in skeleton.topological_order:
        p = int(skeleton.parents[j])
        if p < 0 or j == root:
            continue
        follows[:, j] = follows[:, p] & ~(have[:, j] if j in split_roots else False)
    return follows


def root_translations(
    positions: np.ndarray, measured: np.ndarray, use: np.ndarray, weights: np.ndarray | None = None
) -> np.ndarray:
    """(F, 3) the weighted least-squares translation of the joints onto their measurements.

    positions (F, J, 3) the model's joints, measured (F, J, 3) their virtual markers (NaN:
    none), use (F, J) bool the joints that may take part, weights (J,) (None: 1 each). A frame
    with no joint taking part gets 0 (the root stays where it is).
    """
    seen = use & np.isfinite(measured).all(axis=2)
    w = np.where(seen, 1.0 if weights is None else np.asarray(weights, dtype=np.float64)[None], 0.0)
    difference = np.where(seen[..., None], measured - positions, 0.0)
    total = w.sum(axis=1)
    shift = np.einsum("fj,fja->fa", w, difference)
    return np.divide(shift, total[:, None], out=np.zeros_like(shift), where=total[:, None] > 0)
