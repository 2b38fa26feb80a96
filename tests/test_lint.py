"""The code base is ruff-clean (the same check as the editor's)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def ruff() -> list[str]:
    found = shutil.which("ruff", path=str(Path(sys.executable).parent)) or shutil.which("ruff")
    if not found:
        pytest.fail("ruff is not installed: install the project's test extra")
    return [found]


def test_ruff_check_is_clean():
    result = subprocess.run([*ruff(), "check", str(ROOT)], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr


def test_core_gui_ban_is_active():
    # the probe goes through stdin, named as a file in core/ so that core/ruff.toml applies: no
    # file is written into the tree that other checks (tests/test_layers.py) read meanwhile
    result = subprocess.run(
        [*ruff(), "check", "--stdin-filename", str(ROOT / "core" / "_ruff_probe.py"), "-"],
        input="import pyvista\n",
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert result.returncode == 1 and "TID251" in result.stdout
