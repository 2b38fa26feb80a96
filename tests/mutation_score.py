"""Mutation score per module, with cosmic-ray (docs/reliability.md, "Mutation testing").

cosmic-ray plants one small change at a time (an operator, a comparison, a number, a
condition negated...) in a module *on disk*, runs the tests chosen for that module, and
puts the file back. The project is installed editable (``gmr_studio.core`` is the
checkout's ``core/``), so the tests import the mutated file. A mutant the tests do not fail
is a survivor: a blind spot, unless it is *equivalent* (no input can tell it from the code),
which ``tests/mutation_equivalents.toml`` says with the reason.

    nice .venv/bin/python -m tests.mutation_score run core/edits/clip.py [MODULE ...]   # minutes each
    GMR_REQUIRE_GUI=1 nice xvfb-run -a .venv/bin/python -m tests.mutation_score run app/reliability/autosave.py
    .venv/bin/python -m tests.mutation_score                     # the table, from the sessions kept
    .venv/bin/python -m tests.mutation_score survivors MODULE    # each non-equivalent survivor's diff
    nice .venv/bin/python -m tests.mutation_score rerun MODULE   # the survivors again, after new tests

Sessions are kept in ``.mutation/`` (not committed); ``run`` starts a module afresh. Not part
of the test suite and not run in CI (it edits the working tree while it runs: run it on a
tree nothing else is reading, one module at a time).

The operators are cosmic-ray's, reduced to a selective set (:data:`EXCLUDE`) so that a
module takes minutes, not hours, on 2 cores: each arithmetic operator is replaced by its
counterpart only (``+``/``-``, ``*``/``/``, ``|``/``&``...), not by all eleven others (which
on float arrays mostly raise TypeError, trivially killed); each comparison by its boundary
and its negation (``<`` by ``<=`` and ``>=``); unary operators only removed. Numbers,
booleans, ``not`` added, ``and``/``or``, ``break``/``continue``, exceptions and
zero-iteration loops are all kept.
"""

from __future__ import annotations

import json
import os
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

from tests.mutation_modules import MODULES

ROOT = Path(__file__).resolve().parent.parent
SESSIONS = ROOT / ".mutation"
EQUIVALENTS = ROOT / "tests" / "mutation_equivalents.toml"
#: goal: at most this fraction of the non-equivalent mutants survive, per module
GOAL = 0.10


#: operators left out (regular expressions, matched from the start of cosmic-ray's names)
EXCLUDE = [
    r"core/ReplaceBinaryOperator_(?!(Add_Sub|Sub_Add|Mul_Div|Div_Mul|FloorDiv_Div|Mod_FloorDiv|Pow_Mul"
    r"|BitOr_BitAnd|BitAnd_BitOr|BitXor_BitOr|LShift_RShift|RShift_LShift)$)",
    r"core/ReplaceComparisonOperator_(?!(Lt_LtE|Lt_GtE|LtE_Lt|LtE_Gt|Gt_GtE|Gt_LtE|GtE_Gt|GtE_Lt|Eq_NotEq"
    r"|NotEq_Eq|Is_IsNot|IsNot_Is|In_NotIn|NotIn_In)$)",
    r"core/ReplaceUnaryOperator_(?!(USub_UAdd|Delete_Not|Delete_Invert|Delete_USub)$)",
]


def slug(module: str) -> str:
    return module.replace("/", "_").removesuffix(".py")


def config_text(module: str) -> str:
    tests, timeout = MODULES[module]
    command = ["env", "PYTEST_DISABLE_PLUGIN_AUTOLOAD=1", *pytest_command(module), "-x", *tests]
    excludes = ", ".join(_toml_string(e) for e in EXCLUDE)
    return (
        "[cosmic-ray]\n"
        f'module-path = "{module}"\n'
        f"timeout = {float(timeout)}\n"
        "excluded-modules = []\n"
        f'test-command = "{shlex.join(command)}"\n\n'
        '[cosmic-ray.distributor]\nname = "local"\n\n'
        f"[cosmic-ray.filters.operators-filter]\nexclude-operators = [{excludes}]\n"
    )


def pytest_command(module: str) -> list[str]:
    """pytest without its plugins' autoload (half the start-up time of a mutant's run), with
    pytest-qt for the app's modules."""
    qt = ["-p", "pytestqt.plugin"] if module.startswith("app/") else []
    return [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *qt]


def _toml_string(text: str) -> str:
    """A TOML literal string (no escapes: the regular expressions' backslashes stay)."""
    assert "'" not in text
    return f"'{text}'"


def cosmic(*args: str) -> None:
    tool = Path(sys.executable).with_name(args[0])
    subprocess.run([str(tool), *args[1:]], cwd=ROOT, check=True)


def run(modules: list[str]) -> int:
    """Mutate and test each module afresh (sequentially)."""
    SESSIONS.mkdir(exist_ok=True)
    for module in modules:
        if module not in MODULES:
            raise SystemExit(f"mutation_score: no test selection for {module}; known: {', '.join(MODULES)}")
        if module.startswith("app/") and not (os.environ.get("DISPLAY") or os.environ.get("QT_QPA_PLATFORM")):
            raise SystemExit(f"mutation_score: {module}'s tests need a display: run under xvfb-run -a")
        config, session = SESSIONS / f"{slug(module)}.toml", SESSIONS / f"{slug(module)}.sqlite"
        config.write_text(config_text(module))
        session.unlink(missing_ok=True)
        if not baseline_passes(module):
            raise SystemExit(f"mutation_score: the tests of {module} fail without a mutant; fix them first")
        cosmic("cosmic-ray", "init", str(config), str(session))
        cosmic("cr-filter-operators", str(session), str(config))
        skip_annotations(module, session)
        print(f"mutation_score: {module}: {len(results(module)[0])} mutants to run", flush=True)
        cosmic("cosmic-ray", "exec", str(config), str(session))
    print(table(modules))
    return 0


def baseline_passes(module: str) -> bool:
    """The module's tests pass on the module as it is (no mutant): else every mutant would
    count as killed."""
    tests, _ = MODULES[module]
    env = {**os.environ, "PYTEST_DISABLE_PLUGIN_AUTOLOAD": "1"}
    return subprocess.run([*pytest_command(module), *tests], env=env).returncode == 0


def rerun(modules: list[str]) -> int:
    """Run each module's survivors again (after tests were added; the module itself must be
    unchanged since its session began, as the mutants' positions refer to it)."""
    import sqlite3

    for module in modules:
        config, session = SESSIONS / f"{slug(module)}.toml", SESSIONS / f"{slug(module)}.sqlite"
        config.write_text(config_text(module))  # the test selection as it now is
        if not baseline_passes(module):
            print(f"mutation_score: the tests of {module} fail without a mutant; not run again", flush=True)
            continue
        with sqlite3.connect(session) as db:
            cleared = db.execute("DELETE FROM work_results WHERE lower(test_outcome) = 'survived'").rowcount
        print(f"mutation_score: {module}: {cleared} survivors to run again", flush=True)
        cosmic("cosmic-ray", "exec", str(config), str(session))
    print(table(modules))
    return 0


def annotation_spans(module: str) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """(start, end) (line, column) of every annotation in the module: with ``from __future__
    import annotations`` they are strings never evaluated, so a mutant inside one is
    equivalent by construction (``int | None`` -> ``int & None``)."""
    import ast

    source = (ROOT / module).read_text()
    tree = ast.parse(source)
    assert "from __future__ import annotations" in source, f"{module}: annotations are evaluated"
    nodes = []
    for node in ast.walk(tree):
        if isinstance(node, ast.arg | ast.AnnAssign) and node.annotation is not None:
            nodes.append(node.annotation)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.returns is not None:
            nodes.append(node.returns)
    return [((n.lineno, n.col_offset), (n.end_lineno, n.end_col_offset)) for n in nodes]


def in_annotation(mutation, spans) -> bool:
    start, end = tuple(mutation.start_pos), tuple(mutation.end_pos)
    return any(a <= start and end <= b for a, b in spans)


def skip_annotations(module: str, session: Path) -> None:
    """Mark the mutants inside annotations as skipped (never run; see :func:`annotation_spans`)."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome, WorkResult

    spans = annotation_spans(module)
    session.with_suffix(".spans.json").write_text(json.dumps(spans))  # read while the file is intact
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item in db.pending_work_items:
            if all(in_annotation(m, spans) for m in item.mutations):
                db.set_result(item.job_id, WorkResult(worker_outcome=WorkerOutcome.SKIPPED, output="annotation"))


def results(module: str) -> tuple[list, list]:
    """(mutants run or to run, their results or None) of a module's session, filtered ones left out."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome

    session = SESSIONS / f"{slug(module)}.sqlite"
    if not session.exists():
        return [], []
    with use_db(str(session), WorkDB.Mode.open) as db:
        done = {item.job_id: result for item, result in db.completed_work_items}
        items = [item for item in db.work_items]
    kept = [(i, done.get(i.job_id)) for i in items]
    kept = [(i, r) for i, r in kept if r is None or r.worker_outcome != WorkerOutcome.SKIPPED]
    return [i for i, _ in kept], [r for _, r in kept]


def changed_lines(diff: str) -> tuple[str, str]:
    """(the line taken out, the line put in) of a mutant's diff, stripped."""
    minus = [line[1:].strip() for line in diff.splitlines() if line.startswith("-") and not line.startswith("---")]
    plus = [line[1:].strip() for line in diff.splitlines() if line.startswith("+") and not line.startswith("+++")]
    return " / ".join(minus), " / ".join(plus)


def equivalents() -> list[dict]:
    """The judged equivalents: module, operator, line before and after, optionally the
    function (``definition``, for a line written alike in two places), and the reason."""
    if not EQUIVALENTS.exists():
        return []
    return tomllib.loads(EQUIVALENTS.read_text()).get("equivalent", [])


def judged(known: list[dict], module: str, mutation, before: str, after: str) -> str | None:
    """The reason a survivor is equivalent, or None when it was not judged so."""
    for e in known:
        same = (e["module"], e["operator"], e["before"], e["after"]) == (module, mutation.operator_name, before, after)
        if same and e.get("definition", mutation.definition_name) == mutation.definition_name:
            return e["reason"]
    return None


def classify(module: str) -> dict:
    """Counts of a module's session and its survivors, equivalent (with reasons) or not."""
    items, outcomes = results(module)
    known = equivalents()
    cached = SESSIONS / f"{slug(module)}.spans.json"
    if cached.exists():  # the spans of the source the session mutated (the file may be a mutant now)
        spans = [(tuple(a), tuple(b)) for a, b in json.loads(cached.read_text())]
    else:
        spans = annotation_spans(module)
    annotated = [in_annotation(item.mutations[0], spans) for item in items]
    items = [item for item, a in zip(items, annotated) if not a]
    outcomes = [result for result, a in zip(outcomes, annotated) if not a]
    counts = {"mutants": len(items), "pending": 0, "killed": 0, "survived": 0, "equivalent": [], "open": []}
    for item, result in zip(items, outcomes):
        if result is None or result.test_outcome is None:
            counts["pending"] += 1
        elif result.is_killed:
            counts["killed"] += 1
        else:
            counts["survived"] += 1
            mutation = item.mutations[0]
            before, after = changed_lines(result.diff or "")
            reason = judged(known, module, mutation, before, after)
            entry = (mutation.start_pos[0], mutation.operator_name, before, after, result.diff or "")
            if reason is not None:
                counts["equivalent"].append((*entry, reason))
            else:
                counts["open"].append(entry)
    return counts


def table(modules: list[str]) -> str:
    rows = [
        "| module | mutants | killed | survived | equivalent | non-equivalent survivors | goal (<= 10%) |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    notes = []
    for module in modules:
        c = classify(module)
        if not c["mutants"]:
            rows.append(f"| `{module}` | not run | | | | | |")
            continue
        non_equivalent = c["mutants"] - len(c["equivalent"]) - c["pending"]
        share = len(c["open"]) / non_equivalent if non_equivalent else 0.0
        pending = f" ({c['pending']} not run)" if c["pending"] else ""
        verdict = "met" if share <= GOAL and not c["pending"] else "NOT met"
        rows.append(
            f"| `{module}` | {c['mutants']}{pending} | {c['killed']} | {c['survived']} | {len(c['equivalent'])} "
            f"| {len(c['open'])} ({100 * share:.1f}%) | {verdict} |"
        )
        for line, operator, before, after, _, reason in c["equivalent"]:
            notes.append(f"- `{module}:{line}` {operator.split('/')[-1]}: `{before}` -> `{after}`: {reason}")
    out = "\n".join(rows)
    if notes:
        out += "\n\nSurvivors judged equivalent:\n" + "\n".join(notes)
    return out


def survivors(module: str) -> str:
    c = classify(module)
    return "\n".join(f"{module}:{line} {operator}\n{diff}" for line, operator, _, _, diff in c["open"])


def main(argv: list[str]) -> int:
    if argv[:1] == ["run"]:
        return run(argv[1:] or list(MODULES))
    if argv[:1] == ["rerun"]:
        return rerun(argv[1:] or list(MODULES))
    if argv[:1] == ["survivors"]:
        for module in argv[1:] or list(MODULES):
            print(survivors(module))
        return 0
    print(table(argv or list(MODULES)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
