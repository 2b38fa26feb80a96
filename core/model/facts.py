"""What a file states about its space: a motion's or a marker set's *file facts*.

=============  =================  ========================================================
field          type               meaning
=============  =================  ========================================================
unit           Unit or None       the length unit the lengths are in, as the file states it
                                  (:mod:`core.space.units`); None when it does not say
up_axis        "y", "z" or None   the up axis the file states; None when it does not say
                                  (then the figure decides: :func:`core.space.up_axis.up_axis_of`)
source_unit    Unit or None       for data converted from other units by this project (a glTF
                                  export, always in metres, of a motion in CMU units), the
                                  unit the lengths came from; writers of formats that cannot
                                  state a unit (BVH) write lengths in it again
=============  =================  ========================================================

Facts are never guessed: a reader sets what its format states (glTF: metres and Y up; AMASS:
metres and Z up; an ASF's ``:units length``; a GMR file's header lines), the edits keep them
true (scaling changes the unit, turning the world changes the up axis), and the features read
them from here, never from comments. On disk, a GMR file holds them as header lines
(:mod:`core.formats.facts`).
"""

from __future__ import annotations

import dataclasses

from gmr_studio.core.space.units import Unit
from gmr_studio.core.space.up_axis import UP_AXES


@dataclasses.dataclass(frozen=True)
class FileFacts:
    """A file's stated length unit and up axis, and the unit its data came from (module docstring)."""

    unit: Unit | None = None
    up_axis: str | None = None
    source_unit: Unit | None = None

    def __post_init__(self) -> None:
        if self.up_axis is not None:
            axis = str(self.up_axis).lower()
            if axis not in UP_AXES:
                raise ValueError(f"the up axis must be one of {', '.join(UP_AXES)}, not {self.up_axis!r}")
            object.__setattr__(self, "up_axis", axis)

    def replace(self, **changes) -> FileFacts:
        return dataclasses.replace(self, **changes)
