"""Dependencies point one way: each package of core and of the app imports only the layers below
its own, and core never imports the app or the GUI stack (pyproject.toml, [tool.importlinter]).

import-linter builds the whole import graph, so an import inside a function counts, and so does
one made through other modules: the check fails on either.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CONTRACTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]


def lint_imports(folder: Path, **env: str) -> subprocess.CompletedProcess:
    """``lint-imports`` on the contracts of ``folder``'s pyproject.toml."""
    found = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    if not found:
        pytest.fail("import-linter is not installed: install the project's test extra")
    return subprocess.run(
        [found, "--no-cache", "--no-logo"],
        capture_output=True,
        text=True,
        cwd=folder,
        env={**os.environ, **env},
    )


def test_every_layer_contract_is_kept():
    result = lint_imports(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    for contract in CONTRACTS:
        assert f"{contract['name']} KEPT" in result.stdout


#: file in a copy of the tree -> text added to it, and the line the check prints for it
VIOLATIONS = {
    # an import inside a function, up from the model to the formats
    "core/model/_probe.py": (
        "def read(path):\n    from gmr_studio.core.formats import read_motion\n\n    return read_motion(path)\n",
        "gmr_studio.core.model is not allowed to import gmr_studio.core.formats",
    ),
    # a feature calling the command line
    "core/formats/_probe.py": (
        "from gmr_studio.core.cli import main\n",
        "gmr_studio.core.formats is not allowed to import gmr_studio.core.cli",
    ),
    # the app reaching into the command line
    "app/docks/_probe.py": (
        "from gmr_studio.core.cli.curves import curves_for\n",
        "gmr_studio.app.docks._probe -> gmr_studio.core.cli.curves",
    ),
    # the model depending on what watches it
    "app/model/_probe.py": (
        "from gmr_studio.app.reliability.autosave import Autosaver\n",
        "gmr_studio.app.model is not allowed to import gmr_studio.app.reliability",
    ),
    # core importing the app: the arguments of gmr-studio then reach VTK through core
    "core/edits/steps.py": (
        "\n\ndef _view():\n    from gmr_studio.app.scene import view\n\n    return view\n",
        "gmr_studio.app.arguments -> gmr_studio.core.edits.steps",
    ),
}


def test_a_call_up_the_layers_fails_the_check(tmp_path):
    package = tmp_path / "gmr_studio"
    ignore = shutil.ignore_patterns("__pycache__")
    for part in ("core", "app"):
        shutil.copytree(ROOT / part, package / part, ignore=ignore)
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    for relative, (text, _) in VIOLATIONS.items():
        with (package / relative).open("a") as handle:
            handle.write(text)
    result = lint_imports(tmp_path, PYTHONPATH=str(tmp_path))
    assert result.returncode == 1, result.stdout + result.stderr
    for _, expected in VIOLATIONS.values():
        assert expected in result.stdout
    assert "core never imports the app or the GUI stack BROKEN" in result.stdout
    assert "gmr-studio's arguments parse without loading Qt or VTK BROKEN" in result.stdout
