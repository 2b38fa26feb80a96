"""Atomic file writes: a reader of the target sees the old file or the whole new one.

The text goes to a temporary file in the same folder, is flushed and fsynced, then renamed
over the target (``os.replace`` is atomic on POSIX and Windows). If anything fails on the
way, the temporary file is removed and the old target is left as it was.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path


def atomic_write_text(path: str | os.PathLike[str], chunks: Iterable[str] | str, encoding: str = "utf-8") -> None:
    """Write ``chunks`` (a string or an iterable of strings) to ``path`` atomically."""
    atomic_write_bytes(path, (c.encode(encoding) for c in ([chunks] if isinstance(chunks, str) else chunks)))


def atomic_write_bytes(path: str | os.PathLike[str], chunks: Iterable[bytes] | bytes) -> None:
    """Write ``chunks`` (bytes or an iterable of bytes) to ``path`` atomically."""
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    fd, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            for chunk in [chunks] if isinstance(chunks, bytes) else chunks:
                handle.write(chunk)
            handle.flush()
            os.fsync(handle.fileno())
        if target.exists():
            os.chmod(temporary, target.stat().st_mode & 0o7777)
        else:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, target)
    except BaseException:
        try:
            os.unlink(temporary)
        except FileNotFoundError:
            pass
        raise
