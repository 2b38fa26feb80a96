"""The project's error types.

:class:`MotionFileError` is the one error every reader raises for a bad file. It carries
where the problem is (path, line, column, all 1-based; line and column are ``None`` for
binary formats) and what was expected, and prints as ``path:line:col: message`` so that
editors and terminals can jump to it.

:class:`OperationError` is raised by the motion operations (shift root, split, join, ...)
when asked for something that makes no sense; the motion they were given is never changed.

:func:`quoted` is how every reader's message shows a piece of the file ("expected
'HIERARCHY', found '\\x00\\x00'"): characters that do not print escaped, long text cut.
"""

from __future__ import annotations

import os
from os import PathLike
from pathlib import Path


class MotionFileError(Exception):
    """A motion or marker file could not be read (or written).

    Attributes
    ----------
    path : str, the file as given by the caller.
    line, column : int or None, 1-based position of the problem.
    message : str, what was wrong and what was expected there.
    """

    def __init__(
        self,
        path: str | PathLike[str],
        message: str,
        line: int | None = None,
        column: int | None = None,
    ) -> None:
        self.path = str(path)
        self.line = line
        self.column = column
        self.message = message
        super().__init__(self.location() + ": " + message)

    def location(self) -> str:
        """``path``, ``path:line`` or ``path:line:col``, as much as is known."""
        parts = [self.path]
        if self.line is not None:
            parts.append(str(self.line))
            if self.column is not None:
                parts.append(str(self.column))
        return ":".join(parts)

    def __reduce__(self):  # keep the fields when the error crosses a process boundary
        return (type(self), (self.path, self.message, self.line, self.column))


#: characters of a file's text a message quotes at the most (the rest elided as ``...``)
QUOTE_LIMIT = 40


def quoted(text: str, limit: int = QUOTE_LIMIT) -> str:
    """``text`` read from a file as a message shows it: in single quotes, every character
    that does not print (NUL, control characters, a lone surrogate...) escaped as Python
    writes it (``'\\x00\\x00HIERARCHY'``, ``'\\t'``), cut after ``limit`` characters with
    ``...`` before the closing quote."""
    shown = "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in text[:limit])
    return f"'{shown}...'" if len(text) > limit else f"'{shown}'"


class OperationError(ValueError):
    """An operation on a motion was refused; the motion is unchanged."""


def read_input(path: str | PathLike[str], data: bytes | None = None) -> bytes:
    """The bytes of an input file (``data`` when the caller already has them); a file that
    cannot be read raises :class:`MotionFileError` naming the reason."""
    if data is not None:
        return data
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise _unreadable(path, exc) from None


def input_size(path: str | PathLike[str]) -> int:
    """The size in bytes of an input file that can be opened for reading (for a reader that
    hands the path to another process); one that cannot raises :class:`MotionFileError`
    as :func:`read_input` does."""
    try:
        with open(path, "rb") as handle:
            return os.fstat(handle.fileno()).st_size
    except OSError as exc:
        raise _unreadable(path, exc) from None


def _unreadable(path: str | PathLike[str], exc: OSError) -> MotionFileError:
    return MotionFileError(path, f"cannot read the file: {exc.strerror or exc}")
