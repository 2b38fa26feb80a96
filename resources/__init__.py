"""Files the app and the library ship: icons, styles, marker maps and the demo motion.

Installed as package data of ``gmr_studio.resources``, so they are found from a checkout and from
an installed wheel alike.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent


def resource_path(*parts: str) -> Path:
    """A file or folder under ``resources/`` (existence not checked)."""
    return ROOT.joinpath(*parts)
