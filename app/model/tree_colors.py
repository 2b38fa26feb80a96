"""Tree colours that follow a tree's identity across edits and undo (no Qt, no VTK).

A tree's identity is the smallest joint index in it: shift root keeps it, and a split
leaves it to the part that holds that joint, so the tree a user did not touch keeps its
colour while the new tree gets one of its own. :class:`TreeColors` remembers the colour
each identity got, so undo, redo and history jumps show the trees as they were drawn. A new
identity gets the palette colour the fewest current trees use (the first such).
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.library.drawing import PALETTE, tree_identities
from gmr_studio.core.model.motion import Motion

__all__ = ["PALETTE", "TreeColors", "tree_identities"]  # the colours live in core (thumbnails draw them)


class TreeColors:
    """The colour of every tree, remembered by identity for one skeleton (its joint names;
    another skeleton starts afresh)."""

    def __init__(self) -> None:
        self._names: tuple[str, ...] | None = None
        self._slot: dict[int, int] = {}  # tree identity -> palette index

    def slots(self, motion: Motion) -> np.ndarray:
        """(J,) int64 palette index of each joint's tree."""
        if motion.names != self._names:
            self._names, self._slot = motion.names, {}
        identities = tree_identities(motion)
        current = np.unique(identities)
        uses = np.zeros(len(PALETTE), np.int64)
        for identity in current:
            if int(identity) in self._slot:
                uses[self._slot[int(identity)]] += 1
        for identity in current:
            if int(identity) not in self._slot:
                slot = int(np.argmin(uses))
                self._slot[int(identity)] = slot
                uses[slot] += 1
        lookup = np.array([self._slot[int(i)] for i in current])
        return lookup[np.searchsorted(current, identities)]

    def colors(self, motion: Motion) -> np.ndarray:
        """(J, 3) RGB in [0, 1] of each joint's tree."""
        return PALETTE[self.slots(motion)]
