"""The pelvis orientation recovered from three virtual markers (technical note, section 1).

:class:`PelvisFrames` is the result the app draws over the markers: one frame per motion
frame, with the fit residual and a flag for frames that could not be recovered.
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class PelvisFrames:
    """Recovered pelvis frames.

    Attributes
    ----------
    rotations : (F, 3, 3) float64, world rotation of the pelvis per frame (identity where
        not ``valid``).
    origins : (F, 3) float64, the pelvis root (virtual marker X1) per frame, NaN where not
        ``valid``.
    residuals : (F,) float64, the least-squares fit residual ``|R* H - P|_F`` per frame
        (NaN where not ``valid``).
    valid : (F,) bool, the three virtual markers were present and not degenerate.
    units : str, length unit of ``origins``.
    reasons : tuple of str, for each distinct cause of invalid frames, a message naming it
        and the frames it spoiled.
    """

    rotations: np.ndarray
    origins: np.ndarray
    residuals: np.ndarray
    valid: np.ndarray
    units: str = "mm"
    reasons: tuple[str, ...] = ()

    @property
    def n_frames(self) -> int:
        return self.rotations.shape[0]
