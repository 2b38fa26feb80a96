"""The Library panel in the real window, driven by Qt events under Xvfb: filter, sort,
keyboard, open (unsaved edits asked about), compare two, drag a take onto the view, index in
the background with progress and cancel, libraries remembered; and its picture. Its table
over a library of thousands of rows, read a block at a time."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from PyQt6.QtCore import QMimeData, QPoint, QPointF, Qt, QTimer, QUrl
from PyQt6.QtGui import QDragEnterEvent, QDropEvent, QImage
from PyQt6.QtWidgets import QApplication, QMessageBox

from gmr_studio.app.library.table_model import COLUMNS, DURATION, NAME, PATH_ROLE, THUMBNAIL, LibraryModel
from gmr_studio.app.model import commands
from gmr_studio.core.library.drawing import BACKGROUND, PALETTE
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import Query, select_rows
from gmr_studio.resources import resource_path
from tests import app_fixtures
from tests.library_fixtures import made_up_records, make_takes, write_records

studio = app_fixtures.studio
pytestmark = pytest.mark.gui
DEMO = resource_path("demo") / "walk.gmr"


@pytest.fixture(scope="module")
def indexed(tmp_path_factory):
    """(folder, library file) of the takes, indexed once."""
    root = tmp_path_factory.mktemp("panel")
    folder = make_takes(root / "takes")
    shutil.copyfile(folder / "cmu/clip_75f.bvh", folder / "cmu/clip_again.bvh")
    db = root / "library.sqlite"
    with Library(db) as library:
        library.index([folder], jobs=1)
    return folder, db


@pytest.fixture
def panel(studio, indexed, qtbot, tmp_path):
    """The window's Library panel showing a copy of the indexed takes' library (indexing in
    this process)."""
    _folder, indexed_db = indexed
    db = tmp_path / "library.sqlite"
    shutil.copyfile(indexed_db, db)
    studio.settings.setValue("library/files", [str(db)])
    studio.library_panel.jobs = 1
    studio.library_dock.show()
    studio.library_dock.raise_()
    panel = studio.library_panel
    qtbot.waitUntil(lambda: panel.library is not None and panel.model.rowCount() == 10)
    return panel


def shown_names(panel) -> list[str]:
    model = panel.model
    return [model.data(model.index(r, NAME)) for r in range(model.rowCount())]


def click_row(qtbot, panel, row: int, modifier=Qt.KeyboardModifier.NoModifier) -> None:
    table = panel.table
    table.scrollTo(panel.model.index(row, NAME))
    rect = table.visualRect(panel.model.index(row, NAME))
    qtbot.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, modifier, rect.center())


def row_named(panel, name: str) -> int:
    return shown_names(panel).index(name)


def test_the_filter_box_finds_takes_by_name_and_by_filters(panel, qtbot):
    qtbot.keyClicks(panel.filter, "clip")
    qtbot.waitUntil(lambda: sorted(shown_names(panel)) == ["clip_75f.bvh", "clip_again.bvh"])
    panel.filter.clear()
    qtbot.keyClicks(panel.filter, "format:bvh,amc min:1")
    qtbot.waitUntil(lambda: sorted(shown_names(panel)) == ["02_01.amc", "mocapbank.bvh"])
    panel.filter.clear()
    qtbot.keyClicks(panel.filter, "failed")
    qtbot.waitUntil(lambda: sorted(shown_names(panel)) == ["not_a.c3d", "truncated.bvh", "walk_poses.npz"])
    assert "cannot be read" in panel.model.data(panel.model.index(0, len(COLUMNS) - 1))
    panel.filter.clear()
    qtbot.keyClicks(panel.filter, "joints:many")  # a bad value: said, the table left as it was
    qtbot.waitUntil(lambda: "joints:many" in panel.filter.toolTip())
    assert panel.model.rowCount() == 3 and "3 of 10 takes" in panel.status.text()
    panel.filter.clear()
    qtbot.waitUntil(lambda: panel.model.rowCount() == 10)
    assert "10 takes in 1 folder" in panel.status.text()


def test_clicking_a_header_sorts_by_that_column(panel, qtbot):
    header = panel.table.horizontalHeader()
    x = header.sectionViewportPosition(DURATION) + header.sectionSize(DURATION) // 2
    qtbot.mouseClick(header.viewport(), Qt.MouseButton.LeftButton, pos=QPoint(x, header.height() // 2))
    durations = [panel.model.row_of(r)["duration"] for r in range(panel.model.rowCount())]
    qtbot.mouseClick(header.viewport(), Qt.MouseButton.LeftButton, pos=QPoint(x, header.height() // 2))
    again = [panel.model.row_of(r)["duration"] for r in range(panel.model.rowCount())]
    # the files not read have no duration: first going up, last going down
    assert durations[:3] == again[7:] == [None] * 3
    assert durations[3:] == sorted(durations[3:]) and again[:7] == sorted(again[:7], reverse=True)


def test_keys_move_through_the_table_and_enter_opens_the_take(panel, studio, indexed, qtbot):
    folder, _db = indexed
    click_row(qtbot, panel, 0)
    target = row_named(panel, "mocapbank.bvh")
    for _ in range(target):
        qtbot.keyClick(panel.table, Qt.Key.Key_Down)
    assert panel.selected_paths() == [str(folder / "mocapbank.bvh")]
    with qtbot.waitSignal(studio.files.load_finished, timeout=20000):
        qtbot.keyClick(panel.table, Qt.Key.Key_Return)
    assert studio.state.path == folder / "mocapbank.bvh" and studio.state.motion.n_frames == 455


def test_a_double_click_opens_and_unsaved_edits_are_asked_about(panel, studio, indexed, qtbot):
    folder, _db = indexed
    app_fixtures.open_file(studio, folder / "cmu/clip_75f.bvh")
    commands.split_here(studio.state, studio.state.motion.joint_index("LeftUpLeg"))
    assert studio.state.modified
    edited = studio.state.snapshot
    studio.files.quiet = False  # the question is asked as it is to a user

    def answer(button):
        def press():
            box = QApplication.activeModalWidget()
            assert isinstance(box, QMessageBox) and "Save the changes" in box.text()
            box.button(button).click()

        QTimer.singleShot(200, press)

    answer(QMessageBox.StandardButton.Cancel)
    index = panel.model.index(row_named(panel, "mocapbank.bvh"), NAME)
    panel.table.scrollTo(index)
    rect = panel.table.visualRect(index)
    double_click(qtbot, panel.table.viewport(), rect.center())
    QApplication.processEvents()
    assert studio.state.snapshot is edited and studio.state.modified  # kept as it was
    answer(QMessageBox.StandardButton.Discard)
    with qtbot.waitSignal(studio.files.load_finished, timeout=20000):
        double_click(qtbot, panel.table.viewport(), rect.center())
    assert studio.state.path == folder / "mocapbank.bvh" and not studio.state.modified


def double_click(qtbot, widget, position: QPoint) -> None:
    """A user's double click: a press and release, then the second press (QTest sends the
    first click's events apart from the double click's)."""
    qtbot.mouseClick(widget, Qt.MouseButton.LeftButton, pos=position)
    qtbot.mouseDClick(widget, Qt.MouseButton.LeftButton, pos=position)


def test_two_selected_takes_open_as_a_comparison(panel, studio, indexed, qtbot):
    folder, _db = indexed
    click_row(qtbot, panel, row_named(panel, "02_01.amc"))
    click_row(qtbot, panel, row_named(panel, "clip_75f.bvh"), Qt.KeyboardModifier.ControlModifier)
    with qtbot.waitSignals([studio.files.load_finished, studio.files.load_finished], timeout=30000):
        qtbot.keyClick(panel.table, Qt.Key.Key_Return)
    qtbot.waitUntil(lambda: len(studio.layers) == 1, timeout=10000)
    assert studio.state.path == folder / "cmu/clip_75f.bvh"  # the row the user is on opens
    layer = studio.layers[0]
    assert layer.name == "02_01.amc" and layer.joint_map == "cmu"  # CMU's BVH and AMC: the CMU map pairs them
    assert layer.comparison is not None and layer.comparison.n_pairs == 24


def test_a_take_dragged_onto_the_view_becomes_a_comparison_layer(panel, studio, indexed, qtbot):
    folder, _db = indexed
    app_fixtures.open_file(studio, folder / "mocapbank.bvh")
    row = row_named(panel, "clip_again.bvh")
    mime = panel.model.mimeData([panel.model.index(row, NAME)])
    assert [u.toLocalFile() for u in mime.urls()] == [str(folder / "cmu/clip_again.bvh")]
    centre = studio.view.mapTo(studio, studio.view.rect().center())
    drop(studio, mime, centre)
    qtbot.waitUntil(lambda: len(studio.layers) == 1, timeout=20000)
    assert studio.state.path == folder / "mocapbank.bvh"  # the document stays
    assert studio.layers[0].name == "clip_again.bvh" and studio.layers[0].joint_map is None  # by name


def drop(widget, mime: QMimeData, position: QPoint) -> None:
    """A drag entering ``widget`` at ``position`` and dropped there, as Qt delivers them."""
    buttons, modifiers = Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier
    enter = QDragEnterEvent(position, Qt.DropAction.CopyAction, mime, buttons, modifiers)
    QApplication.sendEvent(widget, enter)
    assert enter.isAccepted()
    QApplication.sendEvent(widget, QDropEvent(QPointF(position), Qt.DropAction.CopyAction, mime, buttons, modifiers))


def test_a_folder_dropped_on_the_window_is_indexed_in_the_background(panel, studio, tmp_path, qtbot):
    folder = tmp_path / "more"
    folder.mkdir()
    for k in range(6):
        shutil.copyfile(DEMO, folder / f"w{k}.gmr")
    mime = QMimeData()
    mime.setUrls([QUrl.fromLocalFile(str(folder))])
    values = []
    panel.progress.valueChanged.connect(values.append)
    drop(studio, mime, QPoint(200, 200))
    assert panel.indexing() and panel.progress.isVisible() and panel.cancel_button.isVisible()
    qtbot.waitUntil(lambda: not panel.indexing(), timeout=60000)
    assert panel.model.rowCount() == 16 and not panel.progress.isVisible()
    assert values[-1] == 6 and len(set(values)) >= 3  # the bar moved as files were read
    assert str(folder.resolve()) in panel.library.folders()


def test_indexing_can_be_cancelled_and_goes_on_when_asked_again(panel, tmp_path, qtbot):
    folder = tmp_path / "many"
    folder.mkdir()
    for k in range(40):
        shutil.copyfile(DEMO, folder / f"w{k:02}.gmr")
    panel.add_folders([str(folder)])
    qtbot.waitUntil(lambda: panel.progress.value() >= 2, timeout=60000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not panel.indexing(), timeout=60000)
    with Library(panel.library.path) as library:
        written = library.count() - 10
    assert 0 < written < 40 and panel.model.rowCount() == 10 + written
    qtbot.mouseClick(panel.again_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not panel.indexing() and panel.model.rowCount() == 50, timeout=60000)


def test_the_libraries_opened_are_remembered(panel, studio, tmp_path):
    db = tmp_path / "library.sqlite"
    other = tmp_path / "other.sqlite"
    assert panel.open_library(other) and panel.model.rowCount() == 0
    assert studio.settings.value("library/files")[:2] == [str(other), str(db)]
    assert [panel.libraries.itemData(i) for i in range(2)] == [str(other), str(db)]
    panel.libraries.activated.emit(1)
    assert panel.model.rowCount() == 10 and studio.settings.value("library/files")[0] == str(db)


def test_the_panel_shows_each_takes_thumbnail(panel, studio, qtbot):
    """The picture as a user sees it: the table's thumbnail cells hold the take's poses
    on the view's background, in the first tree's blue."""
    studio.resizeDocks([studio.library_dock], [420], Qt.Orientation.Vertical)
    qtbot.waitUntil(lambda: panel.table.viewport().height() > 3 * panel.table.rowHeight(0))
    model, table = panel.model, panel.table

    def all_shown_have_pictures() -> bool:  # the rows in view asked for, their pictures read
        height = table.viewport().height()
        shown = [r for r in range(model.rowCount()) if 0 <= table.visualRect(model.index(r, 0)).bottom() < height]
        wanted = [r for r in shown if model.row_of(r)["thumbnail"]]
        return len(shown) >= 4 and all(model.data(model.index(r, 0), Qt.ItemDataRole.DecorationRole) for r in wanted)

    qtbot.waitUntil(all_shown_have_pictures)
    table.viewport().repaint()
    image = panel.table.viewport().grab().toImage().convertToFormat(QImage.Format.Format_RGB888)
    rows = np.frombuffer(image.constBits().asstring(image.sizeInBytes()), np.uint8)
    pixels = rows.reshape(image.height(), image.bytesPerLine())[:, : image.width() * 3]
    pixels = pixels.reshape(image.height(), image.width(), 3)
    seen = 0
    for row in range(panel.model.rowCount()):
        rect = panel.table.visualRect(panel.model.index(row, THUMBNAIL))
        if rect.top() < 0 or rect.bottom() >= image.height() or not panel.model.row_of(row)["thumbnail"]:
            continue
        cell = pixels[rect.top() + 4 : rect.bottom() - 4, rect.left() + 8 : rect.right() - 8]
        background = (np.abs(cell.astype(int) - np.rint(np.array(BACKGROUND) * 255)).max(axis=-1) < 12).mean()
        figure = (np.abs(cell.astype(int) - np.rint(PALETTE[0] * 255)).max(axis=-1) < 60).sum()
        white = (cell.min(axis=-1) > 160).sum()  # markers are drawn white
        assert background > 0.5 and (figure > 20 or white > 10)
        seen += 1
    assert seen >= 3


def test_a_large_librarys_table_holds_the_querys_rows_in_order_read_a_block_at_a_time(qtbot, tmp_path):
    db = tmp_path / "large.sqlite"
    with Library(db) as library:
        write_records(library, made_up_records(1500))
    with Library(db) as library:
        model = LibraryModel()
        model.id_block = 64  # several blocks of ids (a page each), read as rows are asked for
        model.set_connection(library.connection)
        query = Query(formats=("bvh",), sort="duration", descending=True)
        model.set_query(query)
        expected = [row["path"] for row in select_rows(library.connection, query)]
        asked = [expected[k] for k in (0, 300, 299, len(expected) - 1)] + ["/lib/nowhere.bvh"]
        before = model.rows_with_paths(asked)  # no block read yet: found by the file
        assert model.rowCount() == len(expected) > 2 * model.id_block
        rows = list(range(model.rowCount()))[::-1]  # from the bottom up, as a jump to the end
        assert [model.data(model.index(row, NAME), PATH_ROLE) for row in rows] == expected[::-1]
        assert model.data(model.index(len(expected), NAME), PATH_ROLE) is None
        after = model.rows_with_paths(asked)  # every block in hand
        assert before == after == {path: expected.index(path) for path in asked[:-1]}
