"""What a joint's ``channels`` numbers are, said the same way in the inspector and the curves
dock: the file's own values only while they are the ones the file holds
(:data:`core.analysis.curves.CHANNEL_ORIGINS`), never for angles computed from a glTF's quaternions."""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.analysis.curves import CHANNEL_ORIGINS, Curves
from gmr_studio.core.formats import NON_EULER_ROTATIONS


def channels_caption(curves: Curves, path: str | Path | None, edited: bool) -> str:
    """A joint's ``channels`` values in words, from their origin (:attr:`core.analysis.curves.Curves.origin`),
    the document's file ``path`` and whether the document was ``edited`` since it was read.

    - the file's values: ``"the file's own values, as written"`` (``"..., this joint
      unchanged by the edits"`` in an edited document);
    - recomputed after an edit: ``"computed from the edited motion, in the file's channel columns"``;
    - no channels in the file: ``"the motion's rotation as Euler angles in the joint's order,
      computed"``, and what the file stores when it is not Euler angles (``"; the file
      stores quaternions"``: a glTF).
    """
    text = CHANNEL_ORIGINS.get(curves.origin, "")
    if curves.origin == "file" and edited:
        text += ", this joint unchanged by the edits"
    if curves.origin == "motion" and path is not None:
        stored = NON_EULER_ROTATIONS.get(Path(path).suffix.lower())
        if stored is not None:
            text += f"; the file stores {stored}"
    return text
