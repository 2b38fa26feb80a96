"""``gmr edit``'s steps (``--shift-root J``, ``--split J``...) applied to the app's document
through its undoable commands, as the command line asks (:mod:`app.main`)."""

from __future__ import annotations

from gmr_studio.app.model import commands
from gmr_studio.core.edits.steps import EDIT_FLAG_OF
from gmr_studio.core.errors import OperationError


def edit_command(operation: str):
    """The app's command for one of ``gmr edit``'s operations: (state, joint index) -> pushed."""
    return {
        "shift_root": commands.shift_root_to,
        "split": commands.split_here,
        "join": commands.join_to_parent,
        "split_all": lambda state, _: commands.split_everything(state),
        "join_all": lambda state, _: commands.join_everything(state),
        "remove_dummies": lambda state, _: commands.remove_dummy_joints(state),
    }[operation]


def apply_steps(state, steps: list) -> str | None:
    """Apply ``gmr edit``'s steps ((operation, joint name) pairs, :mod:`core.edits.steps`)
    to the state's document through the app's undoable commands, in order; stops at the
    first one refused and returns its message, else None. A step with nothing to change
    (``--join-all`` on a tree) is no error, as in ``gmr edit``."""
    for operation, joint in steps:
        edit = EDIT_FLAG_OF[operation]
        flag, index = edit.flag, None
        if edit.names_joint:
            try:
                index = state.motion.joint_index(joint)
            except OperationError as exc:
                return f"{flag} {joint}: {exc}"
        messages: list[str] = []
        state.message.connect(messages.append)
        try:
            done = edit_command(operation)(state, index)
        finally:
            state.message.disconnect(messages.append)
        if not done and not (messages and messages[-1].endswith(": nothing to change")):
            return f"{flag}: {messages[-1] if messages else 'refused'}"
    return None


def make_test_edits(state, count: int) -> None:
    """Test only (``--test-edits N``): split the tree at joints 1, 2, ... of the motion as
    it is after each edit (joints that are roots already are skipped); prints their names."""
    names, joint = [], 1
    while len(names) < count and joint < state.motion.n_joints:
        name = state.motion.names[joint]
        if state.motion.parents[joint] >= 0 and commands.split_here(state, joint):
            names.append(name)
        joint += 1
    print(f"made {len(names)} edits: split at {','.join(names)}", flush=True)
