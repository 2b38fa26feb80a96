"""The optional compiled kernels: one rule for loading them and for choosing a backend.

Packages whose work runs over every frame (forward kinematics, the edits' frame programs,
resampling, quaternion conversion, the checks) keep a numpy path, the reference, and a
module of numba kernels beside it (``_kernels.py``) that computes the same. numba is an
optional dependency (the ``fast`` extra): without it, or with the environment variable
``GMR_DISABLE_NUMBA=1``, every package uses its numpy path.

An operation that takes ``backend`` accepts 'auto' (the kernels when they load, else
numpy), 'numba' (the kernels; an error without them) or 'numpy'.
"""

from __future__ import annotations

import functools
import importlib
import os
from types import ModuleType
from typing import Literal

Backend = Literal["auto", "numba", "numpy"]
BACKENDS = ("auto", "numba", "numpy")
#: set to "1" to make every package use its numpy path
DISABLE_VARIABLE = "GMR_DISABLE_NUMBA"


@functools.cache
def optional_kernels(module: str) -> ModuleType | None:
    """The module of compiled kernels named ``module`` (``gmr_studio.core.<package>._kernels``),
    imported on the first call, or None when numba is missing or disabled by
    ``GMR_DISABLE_NUMBA=1``. Calling it only when the kernels are first needed keeps numba
    out of what never runs them (a command's ``--help``)."""
    if os.environ.get(DISABLE_VARIABLE) == "1":
        return None
    try:
        return importlib.import_module(module)
    except ImportError:  # pragma: no cover - depends on the environment
        return None


def chosen_kernels(backend: str, kernels: ModuleType | None) -> ModuleType | None:
    """The kernels an operation asked for ``backend`` runs (``kernels``), or None for the
    numpy path: 'numpy', or 'auto' when ``kernels`` is None.

    Raises ValueError for a backend not in :data:`BACKENDS` and RuntimeError for 'numba'
    when the kernels are not available.
    """
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}: expected 'auto', 'numba' or 'numpy'")
    if backend == "numba" and kernels is None:
        raise RuntimeError("the numba backend is not available: install the 'fast' extra (numba)")
    return None if backend == "numpy" else kernels
