"""How a figure looks in any picture, with no renderer: the colours of the view and of each
tree, the direction a figure travels, and poses set side by side.

The app's view (:mod:`app.scene`), its filmstrips (:mod:`app.media.filmstrip`) and the
library's thumbnails (:mod:`core.library.thumbnails`) all draw with these, so a thumbnail
shows a take as the view does.

- :data:`BACKGROUND`, :data:`GROUND_COLOR`, :data:`MARKER_COLOR`: RGB in [0, 1].
- :data:`PALETTE`: the trees' colours, in the order new trees get them; :func:`tree_identities`
  names each tree by its smallest joint index (the app's :class:`~app.model.tree_colors.
  TreeColors` remembers them across edits; a freshly read motion gives its trees the palette
  in the order of their identities, :func:`first_tree_colors`).
- :func:`core.space.heading.travel_axis`: the figure's main horizontal direction of travel (the first principal
  axis of its centroid's path); :func:`side_by_side`: poses moved along it so that none overlaps.
- :func:`side_view`: the filmstrip's camera, a parallel projection from the side of the travel
  a little from above, fitted to the poses; :meth:`SideView.pixels` projects points with it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.heading import travel_axis

BACKGROUND = (0.16, 0.17, 0.20)
GROUND_COLOR = (0.36, 0.38, 0.42)
MARKER_COLOR = (0.92, 0.92, 0.95)

PALETTE = np.array(
    [
        (0.122, 0.467, 0.706),  # blue
        (1.000, 0.498, 0.055),  # orange
        (0.173, 0.627, 0.173),  # green
        (0.839, 0.153, 0.157),  # red
        (0.580, 0.404, 0.741),  # purple
        (0.090, 0.745, 0.812),  # cyan
        (0.890, 0.467, 0.761),  # pink
        (0.737, 0.741, 0.133),  # olive
        (0.549, 0.337, 0.294),  # brown
        (0.498, 0.498, 0.498),  # grey
    ]
)


def tree_identities(motion: Motion) -> np.ndarray:
    """(J,) int64: the identity of each joint's tree, its smallest joint index."""
    smallest = np.full(motion.n_joints, motion.n_joints, np.int64)
    np.minimum.at(smallest, motion.tree_roots, np.arange(motion.n_joints))
    return smallest[motion.tree_roots]


def first_tree_colors(motion: Motion) -> np.ndarray:
    """(J, 3) RGB of each joint's tree as the view first draws a motion: the trees take the
    palette's colours in the order of their identities (the first tree blue, then orange...)."""
    identities = tree_identities(motion)
    order = np.searchsorted(np.unique(identities), identities)
    return PALETTE[order % len(PALETTE)]


def side_by_side(positions: np.ndarray, up: int, gap: float = 0.25, figure: np.ndarray | None = None) -> np.ndarray:
    """(K, J, 3) poses moved along the travel axis so that each figure sits beside the previous
    one (``gap`` of the widest figure between them), keeping their own heights; ``figure``
    (J,) bool as for :func:`travel_axis` (every joint moves, only the figure's are spaced)."""
    figure = np.ones(positions.shape[1], dtype=bool) if figure is None else figure
    axis = travel_axis(positions, up, figure)
    along = positions[:, figure] @ axis  # (K, A)
    width = float((along.max(axis=1) - along.min(axis=1)).max())
    # a figure thin along the travel (a vertical chain of two bones) still gets room for its label
    width = max(width, 0.3 * float(np.ptp(positions[:, figure], axis=1).max()))  # the largest pose's extent
    spacing = width * (1.0 + gap) if width > 0 else 1.0
    centre = (along.max(axis=1) + along.min(axis=1)) / 2
    shift = (np.arange(len(positions)) * spacing - centre)[:, None, None] * axis
    return positions + shift


#: the side view looks down at the figure this much (up component of the view direction, the
#: side one being 1)
SIDE_ELEVATION = 0.3
#: half the picture's height, in units of the fitted points' extent (a tenth for margins)
SIDE_FILL = 0.55


@dataclasses.dataclass(frozen=True)
class SideView:
    """A parallel projection (the filmstrip's camera, the library's thumbnails).

    Attributes
    ----------
    centre : (3,) the point at the middle of the picture.
    direction : (3,) from ``centre`` towards the camera (not normalised).
    right, up : (3,) unit vectors of the picture's x (right) and y (up) in the world.
    half_height : world length from the middle of the picture to its top edge.
    """

    centre: np.ndarray
    direction: np.ndarray
    right: np.ndarray
    up: np.ndarray
    half_height: float

    def pixels(self, points: np.ndarray, width: int, height: int) -> np.ndarray:
        """(..., 2) pixel x (right) and y (down from the top) of world ``points`` (..., 3) in a
        picture ``width`` x ``height``, pixel ``(i, j)``'s centre at ``(i + 0.5, j + 0.5)``."""
        scale = height / 2 / self.half_height
        relative = np.asarray(points, dtype=np.float64) - self.centre
        x = width / 2 + (relative @ self.right) * scale
        y = height / 2 - (relative @ self.up) * scale
        return np.stack([x, y], axis=-1)


def side_view(points: np.ndarray, up: int, travel: np.ndarray, width: int, height: int) -> SideView:
    """The view from the side of ``travel`` (3,) (which then runs left to right), a little
    from above, up axis ``up`` (1 or 2) pointing up the picture, fitted so that ``points``
    (N, 3) fill a ``width`` x ``height`` picture (:data:`SIDE_FILL`)."""
    up_vector = np.eye(3)[up]
    side = np.cross(travel, up_vector)
    low, high = points.min(axis=0), points.max(axis=0)
    centre = (low + high) / 2
    direction = side + SIDE_ELEVATION * up_vector
    view = -direction / np.linalg.norm(direction)
    screen_up = up_vector - (up_vector @ view) * view
    screen_up /= np.linalg.norm(screen_up)
    screen_right = np.cross(view, screen_up)
    extent_right = np.ptp(points @ screen_right)
    extent_up = np.ptp(points @ screen_up)
    half_height = SIDE_FILL * max(extent_up, extent_right * height / max(width, 1), 1e-9)
    return SideView(centre, direction, screen_right, screen_up, float(half_height))
