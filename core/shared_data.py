"""Where the real motion-capture files live: ``../shared/data`` beside the project.

They are never copied into the project. ``GMR_SHARED_DATA`` overrides the location.
"""

from __future__ import annotations

import os
from pathlib import Path

PROJECT_ROOT = Path(__file__).resolve().parent.parent


def shared_data_dir() -> Path:
    """The folder of real data (it may not exist in a user's fresh clone)."""
    return Path(os.environ.get("GMR_SHARED_DATA", PROJECT_ROOT.parent / "shared" / "data"))


def shared_file(relative: str) -> Path:
    """A file in the shared data folder (existence not checked)."""
    return shared_data_dir() / relative
