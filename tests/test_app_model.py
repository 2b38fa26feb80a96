"""Model-based test of the app: long random sequences of user actions on a real window.

A hypothesis :class:`RuleBasedStateMachine` drives one main window through everything a
user does to a document: open a real file (the CMU BVH files of ``../shared/data``, or the
demo walk), select joints and markers, Shift root, Split here, Join to parent, Split all,
Join all, Remove dummy joints, undo, redo, jump in the history, change frame, toggle
overlays, add markers, save as GMR and reload, export BVH and reopen. After every step:

- every joint's world position at every frame equals the first opened file's (joints
  matched by name; a BVH export adds dummy joints and a ``World`` root, which are left out)
  to 1e-9 of the skeleton's size, in the document's cache and computed from its motion;
- the first command of the history holds the document's opening snapshot, and undoing to
  the start gives back those very arrays (checked exactly by a rule that undoes all);
- the forest dock, the view's actors and the inspector agree with the state: the same
  trees, roots, parents, soft links and tree colours, the joints drawn where the cache
  says at the current frame, the selected joint and frame in the inspector;
- a saved file reloads to the same positions;
- nothing reached the crash log.

Two harnesses run the same machine: the whole window (3D view included), and a light one
with the same state, file controller, autosaver, forest dock, inspector and history but no
3D view (whose actor rebuild costs ~0.1 s an edit), for long runs. Reading, saving and
exporting (0.1 to 0.5 s each) are allowed every ``IO_EVERY`` steps, so that most steps are
edits, history moves, selection and viewing. CI runs ``CI_STEPS`` steps in each harness
(derandomised: the same sequences each run). The long run (docs/reliability.md) sets the
number of steps and the harness::

    GMR_MODEL_STEPS=100000 GMR_MODEL_HARNESS=light GMR_REQUIRE_GUI=1 \\
        xvfb-run -a -s "-screen 0 1600x1200x24" .venv/bin/python -m pytest -q -s tests/test_app_model.py
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule
from PyQt6.QtCore import Qt

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import OVERLAYS
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.shared_data import shared_data_dir
from tests import app_fixtures

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

#: steps per sequence; steps in CI for each harness (the window's and the light one)
MODEL_STEPS = 50
CI_STEPS = {"window": 500, "light": 1500}
#: steps a sequence has on average (hypothesis ends some early); measured 37 to 42
SEQUENCE_STEPS = 30
#: reading, saving or exporting a file is allowed once every this many steps
IO_EVERY = 6
#: positions against the first opened file, relative to its size (measured below 1e-12:
#: operations are exact to rounding; GMR and BVH text hold 15 digits)
POSITION_TOLERANCE = 1e-9
#: files a sequence opens (real files first; the demo always exists)
SHARED_FILES = ("bvh/cmu_cgspeed_npybvh_example_75f.bvh", "cmu/subject01/01_01.bvh")


def source_files() -> list[Path]:
    data = shared_data_dir()
    found = [data / name for name in SHARED_FILES if (data / name).exists()]
    return [*found, demo_folder() / MOTION_FILE]


class LightStudio:
    """The window's parts without the 3D view (or the window itself): what the model drives."""

    def __init__(self, settings_path: Path) -> None:
        from PyQt6.QtCore import QSettings
        from PyQt6.QtWidgets import QUndoView, QWidget

        from gmr_studio.app.docks.forest import ForestTree
        from gmr_studio.app.docks.inspector import Inspector
        from gmr_studio.app.docks.layers_dock import LayersDock
        from gmr_studio.app.model.layers import Layers
        from gmr_studio.app.model.state import StudioState
        from gmr_studio.app.reliability.autosave import Autosaver
        from gmr_studio.app.window.exports import Exports
        from gmr_studio.app.window.files import FileController

        self.host = QWidget()
        self.state = StudioState(self.host)
        settings = QSettings(str(settings_path), QSettings.Format.IniFormat)
        self.files = FileController(self.state, lambda: None, settings, self.host)
        self.files.quiet = True
        self.exports = Exports(self.files)
        self.autosave = Autosaver(self.state, self.host)
        self.forest = ForestTree(self.state, self.host)
        self.inspector = Inspector(self.state, self.host)
        self.layers = Layers(self.state, self.host)
        self.files.layers = self.layers
        self.layers_panel = LayersDock(self.layers, self.host)
        self.history = QUndoView(self.state.undo_stack, self.host)
        self.status = type("Status", (), {"text": lambda _self: ""})()
        self.state.message.connect(lambda text: setattr(self, "last_message", text))

    def close(self) -> None:
        self.state.undo_stack.setClean()
        self.autosave.shutdown()
        self.host.deleteLater()


#: what the Edit menu's actions do, for the light harness
EDITS = {
    "shift_root": lambda state: commands.shift_root_to(state, state.selected),
    "split": lambda state: commands.split_here(state, state.selected),
    "join": lambda state: commands.join_to_parent(state, state.selected),
}


class StudioModel(RuleBasedStateMachine):
    """The app under random use; ``window`` (a MainWindow or a LightStudio) and ``folder``
    are set by the test."""

    window = None
    folder: Path = Path()
    steps = 0
    #: steps at which a comparison with the first file was checked for zero error
    zero_checks = 0

    def __init__(self) -> None:
        super().__init__()
        self.since_io = 0

    @property
    def full(self) -> bool:
        """The harness is the whole window (3D view, actions)."""
        return not isinstance(self.window, LightStudio)

    def io_allowed(self) -> bool:
        return self.since_io >= IO_EVERY

    # ------------------------------------------------------------------ documents
    @initialize(path=st.sampled_from(source_files()))
    def open_first(self, path: Path) -> None:
        while len(self.window.layers):  # each sequence starts without comparisons (replayable)
            self.window.layers.remove(0)
        self.load_document(path)
        motion = self.state.motion
        self.reference_names = list(motion.names)
        self.reference = self.state.positions
        self.size = max(motion.size, 1e-12)
        self.saves = 0
        self.reference_path = Path(path)
        self.foreign: set[str] = set()  # names that left the document with other trees

    @property
    def state(self):
        return self.window.state

    def load_document(self, path: Path) -> None:
        self.since_io = 0
        self.window.files.open_path(str(path), ask=False, wait=True)
        assert self.state.path == Path(path), self.window.status.text()
        self.start = self.state.snapshot

    @precondition(io_allowed)
    @rule(path=st.sampled_from(source_files()))
    def open_another(self, path: Path) -> None:
        self.window.state.undo_stack.setClean()  # the user chose Discard
        self.open_first(path)

    @precondition(io_allowed)
    @rule()
    def save_gmr_and_reload(self) -> None:
        self.saves += 1
        target = self.folder / f"saved{self.saves % 3}.gmr"
        before_names, before = list(self.state.motion.names), self.state.positions
        assert self.window.files.save_to(target), self.window.status.text()
        assert not self.state.modified
        self.load_document(target)
        order = [before_names.index(name) for name in self.state.motion.names]
        assert np.abs(self.state.positions - before[:, order]).max() <= POSITION_TOLERANCE * self.size

    @precondition(io_allowed)
    @rule(per_tree=st.booleans())
    def export_bvh_and_reopen(self, per_tree: bool) -> None:
        self.saves += 1
        target = self.folder / f"export{self.saves % 3}.bvh"
        roots = [self.state.motion.names[r] for r in self.state.motion.roots]
        assert self.window.exports.export_bvh(target, per_tree=per_tree), self.window.status.text()
        if per_tree:  # reopen the tree holding most of the first file's joints
            from gmr_studio.core.formats.bvh_export import tree_file_name

            motion = self.state.motion
            known = np.isin(motion.names, self.reference_names)
            root = max(motion.roots, key=lambda r: int(known[motion.tree_roots == r].sum()))
            target = tree_file_name(target, motion.names[root])
            # a joint of another tree can come back only as the zero-offset End Site of its
            # former parent, left a leaf by the split, which readers name <parent>_End (CMU's
            # LFingers_End split off: the file's LFingers_End sits at LFingers); not compared
            self.foreign |= {motion.names[j] for j in range(motion.n_joints) if motion.tree_roots[j] != root}
        self.state.undo_stack.setClean()  # exported, not saved: the user discards the edits
        self.load_document(target)
        if not per_tree:
            assert all(name in self.state.motion.names for name in roots)

    # ---------------------------------------------------------------- selection
    @rule(data=st.data())
    def select_joint(self, data) -> None:
        joint = data.draw(st.integers(-1, self.state.motion.n_joints - 1))
        self.state.select(None if joint < 0 else joint)

    @precondition(lambda self: self.state.marker_overlay is not None)
    @rule(data=st.data())
    def select_marker(self, data) -> None:
        marker = data.draw(st.integers(-1, self.state.marker_overlay.markers.n_markers - 1))
        self.state.select_marker(None if marker < 0 else marker)

    @precondition(lambda self: self.state.marker_overlay is None and self.io_allowed())
    @rule()
    def add_markers(self) -> None:
        self.window.files.add_markers_path(demo_folder() / MARKERS_FILE, wait=True)
        assert self.state.marker_overlay is not None, self.window.status.text()

    # --------------------------------------------------------------- comparison
    @precondition(lambda self: len(self.window.layers) < 2 and self.io_allowed())
    @rule()
    def compare_with_the_first_file(self) -> None:
        """File > Compare with... the file first opened, on the same clock (offset 0)."""
        self.since_io = 0
        layers = self.window.layers
        count = len(layers)
        self.window.files.compare_path(self.reference_path, wait=True)
        assert len(layers) == count + 1, self.window.status.text()
        # the offset given, not found (a periodic walk agrees at other lags too), as the dock does
        assert layers.set_alignment(count, offset=0)

    @precondition(lambda self: len(self.window.layers) > 0)
    @rule(data=st.data())
    def remove_a_comparison(self, data) -> None:
        layers = self.window.layers
        count = len(layers)
        layers.remove(data.draw(st.integers(0, count - 1)))
        assert len(layers) == count - 1

    @rule(action=st.sampled_from(["shift_root", "split", "join"]))
    def joint_edit(self, action: str) -> None:
        if self.state.selected is None:
            self.state.select(0)
        if not self.full:
            EDITS[action](self.state)
            return
        count = self.state.undo_stack.count()
        enabled = self.window.actions[action].isEnabled()
        self.window.actions[action].trigger()  # as the menu does (nothing when disabled)
        if not enabled:
            assert self.state.undo_stack.count() == count

    @rule(action=st.sampled_from(["split_all", "join_all", "remove_dummies"]))
    def motion_edit(self, action: str) -> None:
        handler = {
            "split_all": commands.split_everything,
            "join_all": commands.join_everything,
            "remove_dummies": commands.remove_dummy_joints,
        }[action]
        handler(self.state)

    @rule()
    def undo(self) -> None:
        self.window.actions["undo"].trigger() if self.full else self.state.undo_stack.undo()

    @rule()
    def redo(self) -> None:
        self.window.actions["redo"].trigger() if self.full else self.state.undo_stack.redo()

    @rule(data=st.data())
    def jump_in_history(self, data) -> None:
        index = data.draw(st.integers(0, self.state.undo_stack.count()))
        history = self.window.history
        history.setCurrentIndex(history.model().index(index, 0))  # a click in Edit > History
        assert self.state.undo_stack.index() == index

    @precondition(lambda self: self.state.undo_stack.count() > 0)
    @rule()
    def undo_everything_restores_the_opened_arrays(self) -> None:
        stack = self.state.undo_stack
        top = stack.index()
        stack.setIndex(0)
        assert self.state.snapshot is self.start
        assert self.state.positions is self.start.positions and self.state.rotations is self.start.rotations
        assert not self.state.modified
        stack.setIndex(top)

    # ------------------------------------------------------------------- viewing
    @rule(data=st.data())
    def change_frame(self, data) -> None:
        self.state.set_frame(data.draw(st.integers(0, self.state.n_frames - 1)))

    @rule(name=st.sampled_from(sorted(OVERLAYS)))
    def toggle_overlay(self, name: str) -> None:
        if self.full:
            self.window.actions[f"overlay_{name}"].trigger()
        else:
            self.state.set_overlay(name, not self.state.overlays[name])

    # ---------------------------------------------------------------- invariants
    @invariant()
    def positions_are_the_first_files(self) -> None:
        StudioModel.steps += 1
        self.since_io += 1
        if StudioModel.steps % 5000 == 0:  # the long run's progress
            print(
                f"model-based run: {StudioModel.steps} steps, {StudioModel.zero_checks} zero-error checks, no failure",
                file=sys.stderr,
                flush=True,
            )
        motion = self.state.motion
        kept = [j for j, name in enumerate(motion.names) if name in self.reference_names and name not in self.foreign]
        assert kept  # (a tree exported on its own holds only that tree's joints)
        order = [self.reference_names.index(motion.names[j]) for j in kept]
        error = np.abs(self.state.positions[:, kept] - self.reference[:, order]).max()
        assert error <= POSITION_TOLERANCE * self.size, error / self.size
        # the cache an edit carries over is the motion's own forward kinematics
        error = np.abs(world_positions(motion)[:, kept] - self.reference[:, order]).max()
        assert error <= POSITION_TOLERANCE * self.size, error / self.size

    @invariant()
    def history_starts_at_the_opened_document(self) -> None:
        stack = self.state.undo_stack
        if stack.count():
            assert stack.command(0).before is self.start
        elif stack.index() == 0:
            assert self.state.snapshot is self.start
        assert self.state.modified == (not stack.isClean())
        assert not self.full or self.window.isWindowModified() == self.state.modified

    @invariant()
    def forest_view_and_inspector_agree_with_the_state(self) -> None:
        state, snapshot = self.state, self.state.snapshot
        motion = snapshot.motion
        # the colour book the forest and the view share (app.tree_colors): one colour per tree
        colors = self.window.forest.tree_colors.colors(motion)
        np.testing.assert_array_equal(colors, colors[motion.tree_roots])
        forest = self.window.forest
        roots = [forest.topLevelItem(i).data(0, Qt.ItemDataRole.UserRole) for i in range(forest.topLevelItemCount())]
        assert sorted(roots) == sorted(motion.roots.tolist())
        for j in range(motion.n_joints):
            item = forest.item_for(j)
            parent = item.parent()
            assert (parent.data(0, Qt.ItemDataRole.UserRole) if parent else -1) == motion.parents[j]
            link = motion.soft_parents[j]
            assert item.text(1).endswith(motion.names[link]) if link >= 0 else item.text(1) == ""
        for root in motion.roots:
            swatch = forest.item_for(root).icon(0).pixmap(12, 12).toImage().pixelColor(6, 6)
            drawn = np.array([swatch.redF(), swatch.greenF(), swatch.blueF()])
            assert np.abs(drawn - colors[root]).max() < 1 / 255 + 1e-9
        text = self.window.inspector.text()
        assert f"Frame {state.frame} of 0-{motion.n_frames - 1}" in text
        if state.selected is not None:
            assert motion.names[state.selected] in text
        if not self.full:
            return
        scene = self.window.view.scene
        assert scene.snapshot is snapshot and scene.frame == state.frame and scene.selected == state.selected
        joints = scene.parts["joints"]
        np.testing.assert_array_equal(joints.mesh.points, snapshot.positions[state.frame])
        drawn_colors = np.asarray(joints.mesh.point_data["colors"])
        expected = np.round(colors * 255)
        ghosts = self.window.ghosts  # the error view draws the compared joints in its colours
        if ghosts.visible and ghosts.error_joints is not None:
            comparison = self.window.layers.active.comparison
            row = comparison.row_of_frame(state.frame)
            grey = np.full((len(ghosts.error_joints), 3), 128)
            expected[ghosts.error_joints] = grey if row is None else ghosts.error_rgb[row]
        else:
            assert scene.figure.tint is None
        np.testing.assert_array_equal(drawn_colors[:, :3], expected)
        assert scene.parts["roots"].n_points == len(motion.roots)
        for name, shown in state.overlays.items():
            action = self.window.actions[f"overlay_{name}"]  # a switch with nothing to show is off
            assert action.isChecked() == (shown and action.isEnabled())
            if name in ("axes", "labels", "ground"):
                assert scene.is_shown(name) == shown

    @invariant()
    def comparisons_with_the_first_file_are_zero(self) -> None:
        """A layer of the first opened file, on the same clock, matches every joint the
        document still has from it with zero error (positions are invariant under the edits);
        every layer is compared with the document as it now is; the Layers dock lists them."""
        state = self.state
        panel = self.window.layers_panel
        assert panel.table.rowCount() == 1 + len(self.window.layers)
        for layer in self.window.layers:
            c = layer.comparison
            assert layer.ghost.shape == (state.n_frames, layer.snapshot.motion.n_joints, 3)
            assert c.position_error.shape == (state.n_frames, len(c.index_a))
            assert [state.motion.names[j] for j in c.index_a] == list(c.names_a)
            if layer.name != self.reference_path.name or c.alignment.offset_frames != 0:
                continue  # another file, or a reopened document's offset found again
            assert c.alignment.kind == "none"
            assert len(c.index_a) == int(np.isin(state.motion.names, self.reference_names).sum())
            own = [k for k, name in enumerate(c.names_a) if name not in self.foreign]
            assert np.nanmax(c.position_error[:, own]) <= POSITION_TOLERANCE * self.size
            StudioModel.zero_checks += 1

    @invariant()
    def nothing_reached_the_crash_log(self) -> None:
        log = Path(os.environ["GMR_STUDIO_CONFIG"]) / "crash.log"
        assert not log.exists(), log.read_text()[-3000:]


def run_model(window, folder: Path, steps: int) -> int:
    """Run the machine on ``window`` for about ``steps`` steps; the steps checked."""
    from hypothesis.stateful import run_state_machine_as_test

    StudioModel.window, StudioModel.folder, StudioModel.steps = window, folder, 0
    StudioModel.zero_checks = 0
    examples = max(1, math.ceil(steps / SEQUENCE_STEPS))
    started = time.perf_counter()
    run_state_machine_as_test(
        StudioModel,
        settings=settings(
            max_examples=examples,
            stateful_step_count=MODEL_STEPS,
            # GMR_MODEL_RANDOM=1: fresh random sequences (parallel long runs), else the same every run
            derandomize=os.environ.get("GMR_MODEL_RANDOM") != "1",
            deadline=None,
            database=None,
            suppress_health_check=list(HealthCheck),
            phases=[Phase.generate, *([Phase.shrink] if os.environ.get("GMR_MODEL_SHRINK") else [])],
        ),
    )
    elapsed = time.perf_counter() - started
    kind = "window" if StudioModel().full else "light"
    print(
        f"\nmodel-based run ({kind}): {StudioModel.steps} steps checked in {elapsed:.1f} s ({examples} sequences, "
        f"{StudioModel.zero_checks} comparisons checked for zero error)"
    )
    assert StudioModel.zero_checks > 0  # the comparison invariant was exercised
    return StudioModel.steps


def wanted(harness: str) -> int:
    """Steps for a harness: CI's, or the long run's (GMR_MODEL_STEPS, GMR_MODEL_HARNESS)."""
    if "GMR_MODEL_STEPS" not in os.environ:
        return CI_STEPS[harness]
    chosen = os.environ.get("GMR_MODEL_HARNESS", "light")
    return int(os.environ["GMR_MODEL_STEPS"]) if chosen == harness else 0


@pytest.fixture
def model_folders(tmp_path, monkeypatch):
    monkeypatch.setenv("GMR_STUDIO_CONFIG", str(tmp_path / "config"))  # the crash log
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))  # autosave copies
    return tmp_path


def test_random_use_of_the_window(qtbot, studio, model_folders):
    steps = wanted("window")
    if steps:
        # derandomised: the same sequences, so the same number of steps, every run
        assert run_model(studio, model_folders, steps) >= steps


def test_random_use_of_state_commands_and_docks(qtbot, model_folders):
    steps = wanted("light")
    if steps:
        light = LightStudio(model_folders / "settings.ini")
        try:
            assert run_model(light, model_folders, steps) >= steps
        finally:
            light.close()
