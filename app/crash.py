"""Last-resort error handling: an unexpected exception is logged, shown, and survived.

Nothing the app does may lose the user's document. Every unexpected exception (a bug, an
out-of-memory, a disk error nobody foresaw) goes through :func:`report_unexpected`: its
traceback is appended to the crash log in the user's config folder, a one-line message
names it and the log, and the document and undo stack stay as they were (edits are pure
functions of immutable motions, applied only when they succeed). :func:`install_hooks`
routes exceptions that escape a Qt slot or a thread there too; by default PyQt6 would abort
the process on those.

The config folder is ``$GMR_STUDIO_CONFIG`` if set, else Qt's AppConfigLocation
(``~/.config/GMR Studio`` on Linux).
"""

from __future__ import annotations

import datetime
import os
import sys
import threading
import traceback
from collections.abc import Callable
from pathlib import Path

#: the log is cut to its newest half when it grows beyond this many bytes
LOG_LIMIT = 1_000_000


def config_folder() -> Path:
    """The user's config folder for GMR Studio (created on demand)."""
    override = os.environ.get("GMR_STUDIO_CONFIG")
    if override:
        return Path(override)
    from PyQt6.QtCore import QStandardPaths

    location = QStandardPaths.writableLocation(QStandardPaths.StandardLocation.AppConfigLocation)
    return Path(location) if location else Path.home() / ".config" / "GMR Studio"


def crash_log_path() -> Path:
    return config_folder() / "crash.log"


def log_exception(context: str, exc: BaseException) -> Path | None:
    """Append the exception's traceback to the crash log; its path, or None if even that fails."""
    path = crash_log_path()
    stamp = datetime.datetime.now().isoformat(timespec="seconds")
    entry = f"=== {stamp} {context}\n" + "".join(traceback.format_exception(exc)) + "\n"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.exists() and path.stat().st_size > LOG_LIMIT:
            text = path.read_text(errors="replace")
            path.write_text(text[len(text) // 2 :])
        with path.open("a", encoding="utf-8") as handle:
            handle.write(entry)
    except OSError:
        print(entry, file=sys.stderr)
        return None
    return path


def unexpected_message(context: str, exc: BaseException, log: Path | None) -> str:
    where = f" (details in {log})" if log else ""
    return f"{context} failed unexpectedly: {type(exc).__name__}: {exc}{where}. Your document is unchanged."


#: shows a message to the user; set by :func:`install_hooks` (the status bar, a dialog...)
_show: Callable[[str], None] = lambda text: print(text, file=sys.stderr)  # noqa: E731


def describe_unexpected(context: str, exc: BaseException) -> str:
    """Log ``exc``; the message for the user (for callers that show it their own way)."""
    return unexpected_message(context, exc, log_exception(context, exc))


def report_unexpected(context: str, exc: BaseException, show: Callable[[str], None] | None = None) -> str:
    """Log ``exc`` and tell the user; returns the message shown."""
    text = describe_unexpected(context, exc)
    (show or _show)(text)
    return text


def install_hooks(show: Callable[[str], None]) -> None:
    """Route exceptions that escape slots and threads to the crash log and ``show``."""
    global _show
    _show = show

    def hook(exc_type, exc, tb) -> None:
        if issubclass(exc_type, KeyboardInterrupt):
            sys.__excepthook__(exc_type, exc, tb)
            return
        report_unexpected("An action", exc.with_traceback(tb))

    def thread_hook(args: threading.ExceptHookArgs) -> None:
        if args.exc_value is not None:
            report_unexpected(f"Thread {getattr(args.thread, 'name', '?')}", args.exc_value)

    sys.excepthook = hook
    threading.excepthook = thread_hook
