"""A mutation audit: plant small bugs in a module, one at a time, and list those the tests miss.

    nice .venv/bin/python -m tests.audit core/markers/trc.py
    nice .venv/bin/python -m tests.audit core/checks                       # every module of a package
    nice .venv/bin/python -m tests.audit core/edits/clip.py -- tests/test_clip.py  # the tests named
    GMR_REQUIRE_GUI=1 nice xvfb-run -a .venv/bin/python -m tests.audit app/docks/timeplot.py

cosmic-ray changes the module *on disk* (an operator, a comparison, a number, a condition
negated...), runs the tests, and puts the file back; the project is installed editable, so
the tests import the changed file. A mutant the tests pass with survived: a bug they would not
catch, unless no input can tell it from the code (an equivalent mutant). The survivors are
printed as diffs, with the count killed of each module (docs/testing.md, "Mutation audit").

The tests run are the test files that import the module (by its dotted name, or its name from
its package), unless test paths are given after ``--``. The operators are a selective set
(:data:`EXCLUDE`): each arithmetic operator is replaced by its counterpart only (``+`` by
``-``...), each comparison by its boundary and its negation; mutants inside annotations are
not run (never evaluated). Not part of the suite: it edits the working tree while it runs, so
run it on a tree nothing else is reading. The session is kept in ``.mutation/`` (not committed).
"""

from __future__ import annotations

import ast
import os
import re
import shlex
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SESSIONS = ROOT / ".mutation"

#: cosmic-ray's operators left out (regular expressions, matched from the start of their names)
EXCLUDE = [
    r"core/ReplaceBinaryOperator_(?!(Add_Sub|Sub_Add|Mul_Div|Div_Mul|FloorDiv_Div|Mod_FloorDiv|Pow_Mul"
    r"|BitOr_BitAnd|BitAnd_BitOr|BitXor_BitOr|LShift_RShift|RShift_LShift)$)",
    r"core/ReplaceComparisonOperator_(?!(Lt_LtE|Lt_GtE|LtE_Lt|LtE_Gt|Gt_GtE|Gt_LtE|GtE_Gt|GtE_Lt|Eq_NotEq"
    r"|NotEq_Eq|Is_IsNot|IsNot_Is|In_NotIn|NotIn_In)$)",
    r"core/ReplaceUnaryOperator_(?!(USub_UAdd|Delete_Not|Delete_Invert|Delete_USub)$)",
]


def covering_tests(modules: list[Path]) -> list[str]:
    """The test files that import one of ``modules`` (core/x/y.py is gmr_studio.core.x.y)."""
    patterns = []
    for module in modules:
        parts = ["gmr_studio", *module.with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        dotted = re.escape(".".join(parts))
        package, name = re.escape(".".join(parts[:-1])), re.escape(parts[-1])
        patterns.append(rf"\b{dotted}\b(?!\.)|from {package} import [^\n]*\b{name}\b")
    found = re.compile("|".join(patterns))
    return [str(p.relative_to(ROOT)) for p in sorted((ROOT / "tests").glob("test_*.py")) if found.search(p.read_text())]


def pytest_command(target: str, tests: list[str]) -> list[str]:
    """pytest without its plugins' autoload (half a mutant's start-up time), pytest-qt for the app."""
    qt = ["-p", "pytestqt.plugin"] if target.startswith("app") else []
    return [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *qt, *tests]


def annotation_spans(module: Path) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """(start, end) (line, column) of every annotation: with ``from __future__ import
    annotations`` they are never evaluated, so a mutant inside one changes nothing."""
    nodes = []
    for node in ast.walk(ast.parse(module.read_text())):
        if isinstance(node, ast.arg | ast.AnnAssign) and node.annotation is not None:
            nodes.append(node.annotation)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.returns is not None:
            nodes.append(node.returns)
    return [((n.lineno, n.col_offset), (n.end_lineno, n.end_col_offset)) for n in nodes]


def audit(target: str, tests: list[str]) -> int:
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome, WorkResult

    modules = [Path(target)] if target.endswith(".py") else sorted(Path(target).rglob("*.py"))
    tests = tests or covering_tests(modules)
    if not tests:
        raise SystemExit(f"audit: no test file imports {target}; name the tests after --")
    print(f"audit: {target} against {' '.join(tests)}", flush=True)
    env = {"PYTEST_DISABLE_PLUGIN_AUTOLOAD": "1"}
    start = time.monotonic()
    if subprocess.run(pytest_command(target, tests), cwd=ROOT, env={**os.environ, **env}).returncode:
        raise SystemExit("audit: the tests fail without a mutant; fix them first")
    timeout = 10.0 + 5 * (time.monotonic() - start)
    SESSIONS.mkdir(exist_ok=True)
    slug = target.strip("/").replace("/", "_").removesuffix(".py")
    config, session = SESSIONS / f"{slug}.toml", SESSIONS / f"{slug}.sqlite"
    command = shlex.join(["env", *(f"{k}={v}" for k, v in env.items()), *pytest_command(target, tests)])
    config.write_text(
        f'[cosmic-ray]\nmodule-path = "{target}"\ntimeout = {timeout:.0f}.0\nexcluded-modules = []\n'
        f'test-command = "{command}"\n\n[cosmic-ray.distributor]\nname = "local"\n\n'
        f"[cosmic-ray.filters.operators-filter]\nexclude-operators = [{', '.join(repr(e) for e in EXCLUDE)}]\n"
    )
    session.unlink(missing_ok=True)
    tool = Path(sys.executable).parent
    subprocess.run([tool / "cosmic-ray", "init", config, session], cwd=ROOT, check=True)
    subprocess.run([tool / "cr-filter-operators", session, config], cwd=ROOT, check=True)
    spans = {str(m): annotation_spans(m) for m in modules}
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item in db.pending_work_items:
            inside = [any(a <= tuple(m.start_pos) and tuple(m.end_pos) <= b for a, b in spans[str(m.module_path)])
                      for m in item.mutations]  # fmt: skip
            if all(inside):
                db.set_result(item.job_id, WorkResult(worker_outcome=WorkerOutcome.SKIPPED, output="annotation"))
    subprocess.run([tool / "cosmic-ray", "exec", config, session], cwd=ROOT, check=True)
    return report(session)


def report(session: Path) -> int:
    """Print each survivor's diff and, per module, the mutants killed of those run."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome

    counts: dict[str, list[int]] = {}
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item, result in db.completed_work_items:
            if result.worker_outcome == WorkerOutcome.SKIPPED:
                continue
            mutation = item.mutations[0]
            tally = counts.setdefault(str(mutation.module_path), [0, 0])
            tally[1] += 1
            if result.is_killed:
                tally[0] += 1
            else:
                print(f"\nSURVIVED {mutation.module_path}:{mutation.start_pos[0]} {mutation.operator_name}")
                print(result.diff or "")
    print()
    for module, (killed, total) in sorted(counts.items()):
        print(f"{module}: {killed} of {total} mutants killed, {total - killed} survived")
    return 0


def main(argv: list[str]) -> int:
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0
    target, tests = argv[0], argv[2:] if argv[1:2] == ["--"] else argv[1:]
    return audit(target, tests)


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
