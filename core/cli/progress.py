"""Progress bars of the long commands (batch conversion, dataset export, fuzz, stress), drawn
by tqdm on stderr: redrawn in place on a terminal, silent otherwise (logs and pipes get only
the commands' own lines: errors and the summary)."""

from __future__ import annotations

import sys
import time
from typing import TextIO

from tqdm import tqdm


class Progress:
    """A bar of ``total`` items on ``stream`` counting the done and the failed ones; lines
    written with :meth:`message` appear above it (and always, terminal or not)."""

    def __init__(self, total: int, stream: TextIO | None = None, *, unit: str = "files", label: str = "") -> None:
        self.total = total
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()
        self.done = self.failed = 0
        self.bar = tqdm(
            total=total,
            desc=label or None,
            unit=f" {unit}",
            file=self.stream,
            disable=not _is_terminal(self.stream),
            dynamic_ncols=True,
            leave=True,
        )

    def message(self, text: str, stream: TextIO | None = None) -> None:
        """One line above the bar, on the bar's stream or on ``stream`` (e.g. stdout)."""
        line = " ".join(text.splitlines())
        target = stream or self.stream
        if self.bar.disable:
            target.write(line + "\n")
            target.flush()
        else:
            self.bar.write(line, file=target)

    def advance(self, ok: bool = True, count: int = 1) -> None:
        self.done += count
        self.failed += 0 if ok else count
        if self.failed:
            self.bar.set_postfix_str(f"{self.failed} failed", refresh=False)
        self.bar.update(count)

    @property
    def seconds(self) -> float:
        return time.perf_counter() - self.start

    def close(self) -> None:
        self.bar.close()


def _is_terminal(stream: TextIO) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False
