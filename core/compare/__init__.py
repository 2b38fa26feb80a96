"""Comparing two motions (or marker sets): per-frame, per-joint errors on one clock.

Pure numpy, shared by ``gmr compare``, ``gmr audit`` and the app's comparison layers:

- :mod:`.tracks`: what is compared of each side (world positions and rotations, units, up axis);
- :mod:`.clock`: B sampled at A's frame times, with an offset given or found (the default
  offset, one rate rule, the ghost the app draws);
- :mod:`.offset`: the offset found from the whole body, with the next best and both mismatches;
- :mod:`.align`: the alignment of B onto A (none, rigid, similarity), always reported;
- :mod:`.engine`: :func:`compare_motions` / :func:`compare_tracks` -> :class:`Comparison`;
- :mod:`.result`: the result, its summaries (MPJPE, median, p95, max), JSON and CSV.

See ``docs/compare.md``.
"""

from gmr_studio.core.compare.align import ALIGN_KINDS, Alignment, fit_alignment
from gmr_studio.core.compare.clock import DEFAULT_OFFSET
from gmr_studio.core.compare.engine import compare_motions, compare_tracks
from gmr_studio.core.compare.result import Comparison, ErrorSummary, summarize
from gmr_studio.core.compare.tracks import Track, track_of_motion, track_of_points

__all__ = [
    "ALIGN_KINDS",
    "DEFAULT_OFFSET",
    "Alignment",
    "Comparison",
    "ErrorSummary",
    "Track",
    "compare_motions",
    "compare_tracks",
    "fit_alignment",
    "summarize",
    "track_of_motion",
    "track_of_points",
]
