"""core/ never imports the GUI stack: checked on the source, and in a clean interpreter."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import gmr_studio.core as core

FORBIDDEN = {"PyQt6", "pyvista", "pyvistaqt", "vtk", "vtkmodules", "PySide6"}
CORE = Path(core.__file__).parent


def imported_roots(path: Path) -> set[str]:
    roots = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            roots.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            roots.add(node.module.split(".")[0])
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) in (
            "import_module",
            "__import__",
        ):
            roots.update(arg.value.split(".")[0] for arg in node.args if isinstance(arg, ast.Constant))
    return roots


def test_no_core_module_imports_the_gui_stack():
    offenders = {
        str(path.relative_to(CORE.parent)): sorted(imported_roots(path) & FORBIDDEN)
        for path in CORE.rglob("*.py")
        if imported_roots(path) & FORBIDDEN
    }
    assert offenders == {}


def test_the_checker_sees_imports(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text("import numpy\nfrom PyQt6.QtCore import Qt\nimport vtk.util\n")
    assert imported_roots(sample) & FORBIDDEN == {"PyQt6", "vtk"}


def test_importing_all_of_core_loads_no_gui_module():
    modules = [
        "gmr_studio.core." + ".".join(p.relative_to(CORE).with_suffix("").parts)
        for p in CORE.rglob("*.py")
        if p.name not in ("__init__.py", "__main__.py")
    ]
    # the compiled kernels need the optional numba (the `fast` extra); without it their
    # callers run their numpy paths and the kernels' modules are the only ones that cannot import
    optional = {m: "numba" for m in modules if m.endswith("._kernels")}
    code = (
        "import importlib, importlib.util, sys\n"
        f"optional = {optional!r}\n"
        f"for m in {modules!r}:\n"
        "    if m in optional and importlib.util.find_spec(optional[m]) is None: continue\n"
        "    importlib.import_module(m)\n"
        f"print(sorted(n for n in sys.modules if n.split('.')[0] in {sorted(FORBIDDEN)!r}))\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "[]"
