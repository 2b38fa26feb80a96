"""The edit flags ``gmr edit`` and ``gmr-studio`` share: ``--shift-root J``, ``--split J``,
``--join J``, ``--split-all``, ``--join-all``, ``--remove-dummies``.

The flags are collected in command-line order as ``args.steps``: a list of
``(operation, argument)`` pairs, ``operation`` a :attr:`EditFlag.operation` (``"shift_root"``)
and ``argument`` the joint name the flag was given, or None. ``gmr edit`` applies the steps
to the motion with :mod:`core.edits.operations` before writing it; the app applies them to its
document through its undoable commands. Other commands add their own steps to the same
list with :class:`AppendStep` (``gmr edit --frames A:B``).

Only :mod:`argparse` is imported here, so a command line that takes these flags prints its
usage without loading the numerical code.
"""

from __future__ import annotations

import argparse
import dataclasses


@dataclasses.dataclass(frozen=True)
class EditFlag:
    """One structural edit flag: ``--shift-root J`` is ``EditFlag("shift_root", "J", ...)``."""

    operation: str
    #: "J" for a flag that names a joint, None for one that takes no value
    metavar: str | None
    help: str

    @property
    def flag(self) -> str:
        """The option string: ``"--shift-root"``."""
        return "--" + self.operation.replace("_", "-")

    @property
    def names_joint(self) -> bool:
        return self.metavar is not None


#: the structural edits, in the order ``--help`` lists them
EDIT_FLAGS = (
    EditFlag("shift_root", "J", "make J its tree's root"),
    EditFlag("split", "J", "make J a root (soft link kept)"),
    EditFlag("join", "J", "join split root J to its parent"),
    EditFlag("split_all", None, "make every joint a root"),
    EditFlag("join_all", None, "join every soft link"),
    EditFlag("remove_dummies", None, "fold zero-offset dummy joints"),
)
#: operation -> its flag
EDIT_FLAG_OF = {f.operation: f for f in EDIT_FLAGS}


class AppendStep(argparse.Action):
    """Appends ``(const, value)`` to ``args.steps``, keeping the command line's order."""

    def __call__(self, parser, namespace, values, option_string=None):
        steps = list(getattr(namespace, "steps", None) or [])
        steps.append((self.const, values))
        namespace.steps = steps


def add_edit_arguments(parser: argparse.ArgumentParser) -> None:
    """Add :data:`EDIT_FLAGS` to ``parser``, collected as ``args.steps`` (empty by default)."""
    for edit in EDIT_FLAGS:
        extra = {"metavar": edit.metavar} if edit.names_joint else {"nargs": 0}
        parser.add_argument(edit.flag, action=AppendStep, const=edit.operation, help=edit.help, **extra)
    parser.set_defaults(steps=[])
