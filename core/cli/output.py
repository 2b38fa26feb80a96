"""What the commands write besides their tables: JSON documents to a file or stdout."""

from __future__ import annotations

import json
import sys

from gmr_studio.core.atomic import atomic_write_text


def write_json(value: dict, where: str, indent: int = 1) -> None:
    """``value`` as JSON on stdout (``where`` is ``-``) or in the file ``where`` (atomically)."""
    text = json.dumps(value, indent=indent) + "\n"
    if where == "-":
        sys.stdout.write(text)
    else:
        atomic_write_text(where, text)
