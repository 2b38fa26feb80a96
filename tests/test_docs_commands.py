"""Every command README.md and docs/*.md show runs (issue 40): a reader who copies one gets
the program, not "No module named ...".

Collected: every line of a shell code block (a fence marked ``sh``, ``bash``, ``shell`` or
``console``, or with no language: the usage summaries) and every inline code span of the
prose that is one of the project's own commands: ``gmr SUBCOMMAND ...``, ``gmr-studio ...``
or ``python -m MODULE ...``, each maybe written ``.venv/bin/...`` and after environment
settings (``GMR_REQUIRE_GUI=1``), ``nice`` or ``xvfb-run -a [-s "..."]``. A line holding
several commands (``&&``, ``;``, ``|``) gives each. Recognised and skipped by rule: setup and
test runs (``sh .ci/setup``, ``python -m venv`` or ``pip``, ``python -m pytest``), which set
up or check the project rather than use it.

Checked: ``gmr SUBCOMMAND --help`` and ``gmr-studio --help`` exit 0 and list every long
option (``--name``) the docs show with them; ``python -m MODULE`` names a module that exists,
and when the module reads its command line with argparse, ``python -m MODULE --help`` exits
0 and lists the options shown (run as ``-m`` runs them, all in one other interpreter, so that
they share their imports: a few seconds). Modules that read no options (the
benchmarks that print their figures, the mutation tools, the C3D worker process) are checked
to exist only: running them is their whole work.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import os
import re
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pytest

from gmr_studio.core.cli import COMMANDS
from gmr_studio.core.cli import main as gmr_main

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SHELL_FENCES = {"", "sh", "bash", "shell", "console"}
#: what may come before a command: settings, ``nice``, ``xvfb-run`` and its options
_WRAPPERS = re.compile(r"^(?:[A-Z_]+=\S*\s+|nice\s+|xvfb-run(?:\s+-[a-z](?:\s+\"[^\"]*\")?)*\s+)*")
_PROGRAM = re.compile(r"^(?:\.venv/bin/)?(gmr|gmr-studio|python -m|python3 -m)(?=\s|$)")
_LONG_OPTION = re.compile(r"^[\[(]*(--[A-Za-z][\w-]*)")
#: runs of the command line that only set up or test the project (skipped by rule)
SETUP = re.compile(r"^(?:sh \.ci/setup\b|(?:\.venv/bin/)?python3? -m (?:pytest|venv|pip)\b|(?:\.venv/bin/)?pytest\b)")


@dataclass(frozen=True)
class Shown:
    """One command as a document shows it: ``where`` is ``file:line``."""

    where: str
    text: str

    @property
    def words(self) -> list[str]:
        try:
            return shlex.split(self.text, comments=True)
        except ValueError:  # an unbalanced quote in a usage summary
            return self.text.split()

    @property
    def program(self) -> str:
        match = _PROGRAM.match(self.text)
        return match.group(1).replace("python3", "python") if match else ""

    @property
    def options(self) -> set[str]:
        return {m.group(1) for word in self.words if (m := _LONG_OPTION.match(word))}


def _pieces(text: str) -> list[str]:
    """The commands of a line: split at ``&&``, ``;`` and ``|`` (outside quotes), each
    stripped of the settings and wrappers before it."""
    pieces = re.split(r"\s(?:&&|;|\|)\s", " ".join(text.split()))
    return [_WRAPPERS.sub("", piece.strip()) for piece in pieces]


def _snippets(path: Path) -> list[tuple[int, str]]:
    """(line, text) of the shell blocks' lines (continuations joined) and the inline code
    spans of the prose (a span may run over a line break)."""
    out, prose, fence, pending = [], [], None, ""
    for number, line in enumerate(path.read_text().splitlines(), 1):
        opening = re.match(r"^\s*```\s*(\S*)", line)
        if opening:
            fence = None if fence is not None else opening.group(1)
            prose.append("")
            continue
        if fence is None:
            prose.append(line)
            continue
        prose.append("")
        if fence in SHELL_FENCES:
            pending += line.strip()
            if pending.endswith("\\"):
                pending = pending[:-1] + " "
                continue
            out.append((number, pending))
            pending = ""
    text = "\n".join(prose)
    for span in re.finditer(r"`([^`]+)`", text):
        out.append((text.count("\n", 0, span.start()) + 1, span.group(1).replace("\\|", "|")))
    return out


def shown_commands() -> tuple[list[Shown], list[Shown]]:
    """(commands to check, setup and test commands skipped by rule), in document order."""
    commands, skipped = [], []
    for path in DOCUMENTS:
        for number, text in _snippets(path):
            for piece in _pieces(text):
                shown = Shown(f"{path.relative_to(ROOT)}:{number}", piece)
                if SETUP.match(piece):
                    skipped.append(shown)
                elif shown.program:
                    commands.append(shown)
    return commands, skipped


COMMANDS_SHOWN, SETUP_SHOWN = shown_commands()


def _lists(help_text: str, option: str) -> bool:
    """The help text names the option itself (``--frames`` is not ``--frames-only``)."""
    return re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", help_text) is not None


def _gmr_help(*words: str) -> tuple[int, str]:
    """Exit code and output of ``gmr [WORDS...] --help``, in this process."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as exit_:
        gmr_main([*words, "--help"])
    return exit_.value.code, out.getvalue()


def _run(argv: list[str]) -> subprocess.CompletedProcess:
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    return subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)


#: ``python -m MODULE --help`` for each MODULE of its arguments, as ``-m`` runs a module:
#: prints {module: [exit code, output]} as JSON
_HELP_OF_MODULES = """
import contextlib, io, json, runpy, sys, warnings
warnings.simplefilter("ignore", RuntimeWarning)  # a module imported by another before it runs
results = {}
for module in sys.argv[1:]:
    out, code = io.StringIO(), None
    sys.argv = [module, "--help"]
    with contextlib.redirect_stdout(out):
        try:
            runpy.run_module(module, run_name="__main__", alter_sys=True)
        except SystemExit as exit_:
            code = exit_.code
    results[module] = [code, out.getvalue()]
print(json.dumps(results))
"""


def _module(shown: Shown) -> str:
    words = shown.words
    return words[words.index("-m") + 1]


def _reads_options(module: str) -> bool:
    """The module builds an argparse command line (so ``--help`` only prints it)."""
    origin = importlib.util.find_spec(module).origin
    return "ArgumentParser(" in Path(origin).read_text()


def test_the_docs_show_commands_and_the_setup_is_skipped_by_rule():
    programs = {shown.program for shown in COMMANDS_SHOWN}
    assert programs == {"gmr", "gmr-studio", "python -m"}
    assert len(COMMANDS_SHOWN) > 200
    assert {shown.text.split()[0] for shown in SETUP_SHOWN} <= {"sh", ".venv/bin/python", "python", "python3"}
    assert any(shown.text.startswith("sh .ci/setup") for shown in SETUP_SHOWN)
    assert any("-m pytest" in shown.text for shown in SETUP_SHOWN)


def test_every_gmr_command_shown_has_its_subcommand_and_options():
    helps = {sub: _gmr_help(sub) for sub in COMMANDS}
    wrong = []
    for shown in (s for s in COMMANDS_SHOWN if s.program == "gmr"):
        words = [w for w in shown.words if w != "--help"]
        subcommand = words[1] if len(words) > 1 else None
        if subcommand is None:  # "gmr --help": the list of subcommands
            texts = [_gmr_help()[1]]
        elif subcommand == "...":  # "gmr ... --asf S": any subcommand
            texts = [text for _, text in helps.values()]
        elif subcommand not in helps:
            wrong.append(f"{shown.where}: {shown.text!r}: no subcommand {subcommand!r}")
            continue
        elif len(words) > 2 and not words[2].startswith("-"):
            # the word after the subcommand: an action with options of its own ("gmr library
            # index DIR --db F", "gmr library list|query ..."), or a file, which prints the
            # subcommand's help as it is
            answers = [_gmr_help(subcommand, action) for action in words[2].split("|")]
            assert all(code == 0 for code, _ in answers)
            texts = [text for _, text in answers]
        else:
            code, text = helps[subcommand]
            assert code == 0
            texts = [text]
        missing = sorted(o for o in shown.options if not any(_lists(t, o) for t in texts))
        if missing:
            wrong.append(f"{shown.where}: {shown.text!r}: no option {', '.join(missing)}")
    assert not wrong, "\n".join(wrong)


def test_every_gmr_studio_command_shown_has_its_options_and_the_scripts_start():
    scripts = Path(sys.executable).parent
    with ThreadPoolExecutor(2) as pool:
        gmr, studio = pool.map(_run, [[str(scripts / "gmr"), "--help"], [str(scripts / "gmr-studio"), "--help"]])
    assert gmr.returncode == 0 and all(sub in gmr.stdout for sub in COMMANDS), gmr.stderr
    assert studio.returncode == 0, studio.stderr
    wrong = [
        f"{shown.where}: {shown.text!r}: no option {option}"
        for shown in COMMANDS_SHOWN
        if shown.program == "gmr-studio"
        for option in sorted(shown.options)
        if not _lists(studio.stdout, option)
    ]
    assert not wrong, "\n".join(wrong)


def test_every_python_module_shown_exists_and_prints_its_help():
    shown_modules = [s for s in COMMANDS_SHOWN if s.program == "python -m"]
    absent = [f"{s.where}: {s.text!r}" for s in shown_modules if importlib.util.find_spec(_module(s)) is None]
    assert not absent, "no module named in:\n" + "\n".join(absent)
    modules = sorted({_module(s) for s in shown_modules if _reads_options(_module(s))})
    assert "gmr_studio.app.tools.gallery" in modules and "gmr_studio.core.rigs" in modules
    done = _run([sys.executable, "-c", _HELP_OF_MODULES, *modules])
    assert done.returncode == 0, done.stderr[-2000:]
    helps = json.loads(done.stdout)
    failed = [f"python -m {m} --help: exit {code}" for m, (code, _) in helps.items() if code != 0]
    assert not failed, "\n".join(failed) + "\n" + done.stderr[-2000:]
    wrong = [
        f"{shown.where}: {shown.text!r}: no option {option}"
        for shown in shown_modules
        if _module(shown) in helps
        for option in sorted(shown.options)
        if not _lists(helps[_module(shown)][1], option)
    ]
    assert not wrong, "\n".join(wrong)
