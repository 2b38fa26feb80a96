"""The motion files of a folder tree: what batch conversion, checks, datasets and the library read."""

from __future__ import annotations

from pathlib import Path

from gmr_studio.core.formats import READERS

#: the suffixes of motion files read one by one (an ``.asf`` is the skeleton of the ``.amc``
#: files beside it, not a take of its own)
MOTION_SUFFIXES = tuple(suffix for suffix in READERS if suffix != ".asf")


def find_motion_files(in_dir: Path, out_dir: Path | None, suffixes: tuple[str, ...] = MOTION_SUFFIXES) -> list[Path]:
    """Every input file under ``in_dir`` (sorted) with one of ``suffixes``, none from inside
    ``out_dir`` (if given)."""
    out = out_dir.resolve() if out_dir is not None else None
    files = []
    for path in sorted(in_dir.rglob("*")):
        if path.suffix.lower() not in suffixes or not path.is_file():
            continue
        resolved = path.resolve()
        if out is not None and (resolved == out or out in resolved.parents):
            continue
        files.append(path)
    return files
