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

from __future__ import annotations

import importlib

#: each name this package exports and the module that defines it, imported when first asked
#: for (PEP 562), so a command line that only needs a constant does not load the engine
_EXPORTS = {
    "ALIGN_KINDS": "align",
    "Alignment": "align",
    "fit_alignment": "align",
    "DEFAULT_OFFSET": "clock",
    "compare_motions": "engine",
    "compare_tracks": "engine",
    "Comparison": "result",
    "ErrorSummary": "result",
    "summarize": "result",
    "Track": "tracks",
    "track_of_motion": "tracks",
    "track_of_points": "tracks",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
