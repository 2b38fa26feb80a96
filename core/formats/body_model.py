"""SMPL-family body models (SMPL, SMPL-H, SMPL-X), as far as a skeleton needs them.

A body model file in the official layout holds, among others:

================  ===============  =====================================================
key               shape            meaning
================  ===============  =====================================================
v_template        (V, 3)           the mean-shape template mesh, metres, model axes
shapedirs         (V, 3, B)        shape blend shapes (betas -> vertex offsets)
J_regressor       (J, V)           joint locations as a linear function of the vertices
kintree_table     (2, J)           row 0: parent id of each joint (root: -1 or 2**32-1),
                                   row 1: the joint's own id
================  ===============  =====================================================

The joints of a shape ``betas`` (B',) are ``J_regressor @ (v_template + shapedirs[..., :B'] @ betas)``
(:func:`rest_joints`). Joint names are those of the family with that many joints (24 SMPL,
52 SMPL-H, 55 SMPL-X), else ``joint_<k>``.

Files are data, never code: ``.npz`` is read with ``allow_pickle=False``; a ``.pkl`` (the
official SMPL downloads) through a restricted unpickler that admits numpy arrays, scipy
sparse matrices and plain containers, nothing else (a pickle of chumpy objects is refused,
saying to convert the model to ``.npz``). Body models are licensed and not shipped: the user
passes theirs (``--body-model PATH``).
"""

from __future__ import annotations

import dataclasses
import io
import pickle
import zipfile
from pathlib import Path

import numpy as np

from gmr_studio.core.errors import MotionFileError, read_input

REQUIRED_KEYS = ("v_template", "shapedirs", "J_regressor", "kintree_table")

SMPL_BODY = (
    "pelvis left_hip right_hip spine1 left_knee right_knee spine2 left_ankle right_ankle spine3 left_foot "
    "right_foot neck left_collar right_collar head left_shoulder right_shoulder left_elbow right_elbow "
    "left_wrist right_wrist"
).split()
_FINGERS = [f"{finger}{k}" for finger in ("index", "middle", "pinky", "ring", "thumb") for k in (1, 2, 3)]
HAND_JOINTS = [f"left_{f}" for f in _FINGERS] + [f"right_{f}" for f in _FINGERS]
JOINT_NAMES = {
    24: (*SMPL_BODY, "left_hand", "right_hand"),
    52: (*SMPL_BODY, *HAND_JOINTS),
    55: (*SMPL_BODY, "jaw", "left_eye_smplhf", "right_eye_smplhf", *HAND_JOINTS),
}

#: (module, name) pairs the restricted unpickler admits: numpy arrays and scalars, scipy's
#: sparse matrices (SMPL's J_regressor), and nothing that runs code
_ADMITTED = {
    ("numpy", "ndarray"),
    ("numpy", "dtype"),
    ("numpy.core.multiarray", "_reconstruct"),
    ("numpy._core.multiarray", "_reconstruct"),
    ("numpy.core.multiarray", "scalar"),
    ("numpy._core.multiarray", "scalar"),
    ("scipy.sparse.csc", "csc_matrix"),
    ("scipy.sparse._csc", "csc_matrix"),
    ("scipy.sparse.csr", "csr_matrix"),
    ("scipy.sparse._csr", "csr_matrix"),
    ("_codecs", "encode"),  # how protocol-2 pickles store an array's bytes
    ("copy_reg", "_reconstructor"),
    ("copyreg", "_reconstructor"),
    ("__builtin__", "object"),
    ("builtins", "object"),
}


@dataclasses.dataclass(frozen=True, eq=False)
class BodyModel:
    """The skeleton-relevant arrays of a body model (shapes in the module docstring)."""

    path: str
    v_template: np.ndarray
    shapedirs: np.ndarray
    J_regressor: np.ndarray
    parents: np.ndarray
    names: tuple[str, ...]

    @property
    def n_joints(self) -> int:
        return len(self.names)


class _RestrictedUnpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str):
        if (module, name) not in _ADMITTED:
            raise pickle.UnpicklingError(f"{module}.{name} is not an array or a plain container")
        return super().find_class(module, name)


def _dense(value) -> np.ndarray:
    return np.asarray(value.toarray() if hasattr(value, "toarray") else value, dtype=np.float64)


def _read_arrays(path: Path) -> dict:
    data = read_input(path)
    if path.suffix.lower() == ".pkl":
        try:
            loaded = _RestrictedUnpickler(io.BytesIO(data), encoding="latin1").load()
        except (pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError, ImportError) as exc:
            raise MotionFileError(
                path,
                f"not a body model pickle of plain arrays ({exc}); only numpy arrays and containers are "
                "admitted (chumpy pickles are not): convert the model to the .npz layout",
            ) from None
        if not isinstance(loaded, dict):
            raise MotionFileError(path, "a body model pickle must hold a dict of arrays")
        return loaded
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files if key in REQUIRED_KEYS}
    except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
        raise MotionFileError(path, f"not a body model .npz ({exc})") from None


def parents_from_kintree(kintree: np.ndarray) -> np.ndarray:
    """(J,) parent indices from a (2, J) kintree table (ids need not be 0..J-1)."""
    kintree = np.asarray(kintree).astype(np.int64)
    index = {int(i): k for k, i in enumerate(kintree[1])}
    return np.array([index.get(int(p), -1) for p in kintree[0]], dtype=np.int64)


def load_body_model(path: str | Path) -> BodyModel:
    """Read a body model file (.npz, or .pkl through the restricted unpickler); MotionFileError
    for anything missing or inconsistent."""
    path = Path(path)
    if path.suffix.lower() not in (".npz", ".pkl"):
        raise MotionFileError(path, "a body model is an .npz or .pkl file (SMPL, SMPL-H or SMPL-X layout)")
    arrays = _read_arrays(path)
    missing = [key for key in REQUIRED_KEYS if key not in arrays]
    if missing:
        raise MotionFileError(path, f"the body model lacks {', '.join(missing)} (needs {', '.join(REQUIRED_KEYS)})")
    try:
        v_template = _dense(arrays["v_template"])
        shapedirs = _dense(arrays["shapedirs"])
        regressor = _dense(arrays["J_regressor"])
        kintree = np.asarray(arrays["kintree_table"])
    except (TypeError, ValueError) as exc:
        raise MotionFileError(path, f"the body model's arrays are not numeric: {exc}") from None
    n_vertices = v_template.shape[0] if v_template.ndim == 2 else -1
    if v_template.shape != (n_vertices, 3) or shapedirs.ndim != 3 or shapedirs.shape[:2] != (n_vertices, 3):
        raise MotionFileError(
            path, f"v_template must be (V, 3) and shapedirs (V, 3, B), not {v_template.shape}, {shapedirs.shape}"
        )
    if kintree.ndim != 2 or kintree.shape[0] != 2 or regressor.shape != (kintree.shape[1], n_vertices):
        raise MotionFileError(
            path,
            f"kintree_table must be (2, J) and J_regressor (J, V={n_vertices}), not {kintree.shape}, {regressor.shape}",
        )
    if not (np.isfinite(v_template).all() and np.isfinite(shapedirs).all() and np.isfinite(regressor).all()):
        raise MotionFileError(path, "the body model holds NaN or infinite values")
    parents = parents_from_kintree(kintree)
    n_joints = parents.size
    names = JOINT_NAMES.get(n_joints, tuple(f"joint_{k}" for k in range(n_joints)))
    return BodyModel(str(path), v_template, shapedirs, regressor, parents, tuple(names))


def rest_joints(model: BodyModel, betas: np.ndarray) -> np.ndarray:
    """(J, 3) joint locations of the shape ``betas`` (B',), using the first B' shape directions
    (extra betas beyond the model's are ignored)."""
    betas = np.asarray(betas, dtype=np.float64).reshape(-1)[: model.shapedirs.shape[2]]
    vertices = model.v_template + model.shapedirs[..., : betas.size] @ betas
    return model.J_regressor @ vertices
