"""The figure's heading: the one fit of its main direction of travel.

The view's camera (a walk crosses the screen), the filmstrip and the library's thumbnails
(poses side by side along the travel) all look at a figure from the side of this direction.
"""

from __future__ import annotations

import numpy as np

#: a path spreading no more than this fraction of its distance from the origin stands still
#: (its mean's rounding: a still figure gets the first axis, not a direction of noise)
STILL_RELATIVE = 1e-9


def travel_axis(
    positions: np.ndarray,
    up: int,
    figure: np.ndarray | None = None,
    still_below: float = 0.0,
    samples: int | None = None,
) -> np.ndarray:
    """(3,) unit horizontal direction of the figure's main travel over ``positions`` (K, J, 3):
    the first principal axis of its centroid's horizontal path, pointing from where it starts
    to where it ends; the first horizontal axis when it stands still (its path spreads no
    more than ``still_below`` from its mean, or than :data:`STILL_RELATIVE` of its distance
    from the origin). ``up``: the up axis' column (1 or 2);
    ``figure`` (J,) bool: the joints that make the figure (default all; an anchor pinned at
    the origin is no part of it). ``samples``: fit the path at that many frames at most,
    evenly spread from the first to the last (a long take's path, seen every few frames,
    has the same main direction; the view's camera fits a take of any length in the same
    time); None: every frame."""
    across = [a for a in (0, 1, 2) if a != up]
    if samples is not None and len(positions) > samples:
        positions = positions[np.linspace(0, len(positions) - 1, max(int(samples), 2)).round().astype(np.intp)]
    if figure is not None:
        positions = positions[:, figure]
    # the centroid first (no copy of every joint): einsum sums over the joints several
    # times faster than mean's strided reduction, the same sums to rounding
    path = (np.einsum("fjk->fk", positions) / positions.shape[1])[:, across]
    spread = path - path.mean(axis=0)
    axis = np.zeros(3)
    still = max(still_below, STILL_RELATIVE * np.abs(path).max(initial=0.0))
    if len(path) > 1 and np.abs(spread).max() > still:
        _, _, vt = np.linalg.svd(spread, full_matrices=False)
        axis[across] = vt[0]
        if axis @ (positions[-1].mean(axis=0) - positions[0].mean(axis=0)) < 0:
            axis = -axis
    else:
        axis[across[0]] = 1.0
    return axis
