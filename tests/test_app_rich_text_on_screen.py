"""RichText on screen (app/docks/rich_text.py): slots written only when their line is seen or
the text is read, stale slots taking the owner's fresh text, and a rewritten line's repaint
asked for that line, the screen showing what a whole repaint draws. The slots themselves, layout,
selection and menu are in tests/test_app_rich_text.py."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtGui import QTextCursor

from gmr_studio.app.docks.rich_text import RichText, slot, slot_lines
from tests.test_app_rich_text import shown

pytestmark = pytest.mark.gui


def _scrolled(qtbot, rows: int = 40, height: int = 120):
    """A RichText of ``rows`` one-slot lines in a scroll area showing its first lines only."""
    from PyQt6.QtWidgets import QScrollArea

    area = QScrollArea()
    qtbot.addWidget(area)
    label = RichText()
    area.setWidget(label)
    area.setWidgetResizable(True)
    area.resize(300, height)
    label.setText(lines_page([f"row {k} value 0" for k in range(rows)]))
    area.show()
    qtbot.waitExposed(area)
    return area, label


def lines_page(rows: list[str]) -> str:
    return f"<pre style='margin:0'>{slot_lines(chr(10).join(rows))}</pre>"


def _block_texts(label: RichText) -> list[str]:
    block, texts = label.document.firstBlock(), []
    while block.isValid():
        texts.append(block.text())
        block = block.next()
    return texts


def test_a_slot_off_screen_is_written_when_its_line_is_painted_or_the_text_read(qtbot):

    area, label = _scrolled(qtbot)
    line = label.document.documentLayout().blockBoundingRect(label.document.firstBlock()).height()
    seen = int((area.viewport().height() - RichText.MARGIN) // line)  # lines wholly on screen
    assert 3 <= seen < 20
    label.setText(lines_page([f"row {k} value 1" for k in range(40)]))
    texts = _block_texts(label)
    assert texts[:seen] == [f"row {k} value 1" for k in range(seen)]  # on screen: written
    assert texts[seen + 2 :] == [f"row {k} value 0" for k in range(seen + 2, 40)]  # off screen: not yet
    assert label.slots_pending == 40 - len([t for t in texts if t.endswith("1")])
    area.verticalScrollBar().setValue(area.verticalScrollBar().maximum())  # the last lines into sight
    last = [f"row {k} value 1" for k in range(40 - seen, 40)]
    qtbot.waitUntil(lambda: _block_texts(label)[-seen:] == last, timeout=5000)  # painted: written first
    assert 0 < label.slots_pending < 40 - 2 * seen
    assert label.plain_text().split("\n") == [f"row {k} value 1" for k in range(40)]  # read: all of them
    assert label.slots_pending == 0 and _block_texts(label) == [f"row {k} value 1" for k in range(40)]


def test_a_hidden_text_writes_nothing_until_read(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    label.setText(lines_page(["a", "b"]))
    label.setText(lines_page(["c", "d"]))
    assert label.slots_pending == 2 and _block_texts(label) == ["a", "b"]
    assert label.plain_text() == "c\nd" and label.slots_pending == 0


def assert_screen_shows_a_whole_repaint(area, label) -> None:
    """The screen shows the text as a whole repaint draws it. (Another test's window on the
    same X display may cover this one for a moment: raised and grabbed again.)"""
    import time

    from PyQt6.QtCore import QPoint
    from PyQt6.QtGui import QGuiApplication
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.media.video import image_pixels

    QApplication.processEvents()
    whole = image_pixels(label.grab().toImage())  # a grab paints the whole widget afresh
    origin = label.mapTo(area, QPoint(0, 0))
    for _attempt in range(20):
        area.raise_()
        QApplication.processEvents()
        shown = QGuiApplication.primaryScreen().grabWindow(
            int(area.winId()), origin.x(), origin.y(), label.width(), label.height()
        )
        if np.array_equal(image_pixels(shown.toImage()), whole):
            return
        time.sleep(0.05)
    pytest.fail("the screen never showed what a whole repaint draws")


def test_a_line_rewritten_or_grown_shows_on_screen_as_a_whole_repaint_draws_it(qtbot):
    from PyQt6.QtWidgets import QApplication

    area, label = _scrolled(qtbot, rows=6, height=400)  # every line on screen
    QApplication.processEvents()
    rows = [f"row {k} value 0" for k in range(6)]
    rows[3] = "row 3 value 2"
    label.setText(lines_page(rows))
    assert_screen_shows_a_whole_repaint(area, label)
    label.setText(lines_page(rows))  # nothing changed
    assert_screen_shows_a_whole_repaint(area, label)
    paragraphs = "".join(f"<p style='margin:0'>{slot(row)}</p>" for row in rows)
    label.setText(paragraphs)  # another text: parsed whole
    assert_screen_shows_a_whole_repaint(area, label)
    rows[1] = "a long value " * 12  # wraps: every line after it moves
    label.setText("".join(f"<p style='margin:0'>{slot(row.strip())}</p>" for row in rows))
    assert label.slots_held == 6 and label.slots_pending == 0  # written in place, and it grew
    assert_screen_shows_a_whole_repaint(area, label)
    assert label.minimumHeight() == round(label.document.size().height()) + 2 * RichText.MARGIN


def test_stale_slots_take_the_owners_fresh_text_when_seen_or_read(qtbot):
    from PyQt6.QtWidgets import QApplication

    area, label = _scrolled(qtbot)
    now = {"value": 1}
    asked = []

    def fresh() -> str:
        asked.append(now["value"])
        return lines_page([f"row {k} value {now['value']}" for k in range(40)])

    label.fill = fresh
    seen = label.slots_on_screen()
    assert seen[0] and not seen[-1]
    off = [k for k in range(40) if not seen[k]]
    # the lines off screen keep their old values in the text given, marked stale
    given = [f"row {k} value {0 if k in off else 1}" for k in range(40)]
    label.setText(lines_page(given), stale=off)
    assert asked == [] and label.slots_pending == len(off)
    assert _block_texts(label)[0] == "row 0 value 1" and _block_texts(label)[-1] == "row 39 value 0"
    area.verticalScrollBar().setValue(area.verticalScrollBar().maximum())  # a stale line into sight
    QApplication.processEvents()
    assert asked == [1] and _block_texts(label)[-1] == "row 39 value 1"
    now["value"] = 2
    label.setText(lines_page([f"row {k} value 2" if seen[k] else given[k] for k in range(40)]), stale=off)
    assert label.plain_text().split("\n") == [f"row {k} value 2" for k in range(40)]  # read: fresh
    assert asked == [1, 2] and label.slots_pending == 0
    assert label.text() == fresh()  # the text as it is now


def test_stale_slots_in_a_text_of_another_template_are_parsed_from_the_fresh_text(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    label.fill = lambda: "<p>fresh " + slot("9") + "</p><p>" + slot("8") + "</p>"
    label.setText("<p>a " + slot("1") + "</p>")
    label.setText("<p>old " + slot("1") + "</p><p>" + slot("2") + "</p>", stale=[1])  # another template
    assert label.plain_text() == "fresh 9\n8" and label.slots_held == 2
    # a fill whose template differs from the text shown: parsed whole when the slot is read
    label.setText("<p>fresh " + slot("3") + "</p><p>" + slot("2") + "</p>", stale=[1])
    label.fill = lambda: "<p>other " + slot("5") + "</p>"
    assert label.plain_text() == "other 5" and label.slots_held == 1 and label.slots_pending == 0


def test_two_lines_rewritten_far_apart_show_on_screen_as_a_whole_repaint_draws_them(qtbot):
    from PyQt6.QtWidgets import QApplication

    area, label = _scrolled(qtbot, rows=8, height=400)  # every line on screen

    def page(first: str, second: str, rows: list[str]) -> str:  # a first line of two slots
        return f"<p style='margin:0'>Frame {slot(first)} at {slot(second)} s</p>" + lines_page(rows)

    rows = [f"row {k} value 0" for k in range(8)]
    label.setText(page("1", "0.1", rows))
    QApplication.processEvents()
    rows[1], rows[6] = "row 1 value 12345", "row 6 value 9"
    label.setText(page("2", "0.2", rows))  # the first line asked for twice
    assert_screen_shows_a_whole_repaint(area, label)


def test_a_line_rewritten_asks_for_a_repaint_of_its_whole_line_and_at_most_two_rows_beyond(qtbot):
    """The part a rewritten line asks to be repainted covers its block (whole pixels) and
    reaches at most two rows past it: the rows of its glyphs, none of the next lines'."""
    from PyQt6.QtWidgets import QApplication

    _area, label = _scrolled(qtbot, rows=6, height=400)
    QApplication.processEvents()
    layout = label.document.documentLayout()
    asked = []
    update = label.update
    label.update = lambda *rect: asked.append(rect) or update(*rect)  # QWidget.update, noted
    for k in (0, 3, 5):
        rows = [f"row {j} value 0" for j in range(6)]
        rows[k] = f"row {k} value {k + 10}"
        asked.clear()
        label.setText(lines_page(rows))
        ((rect,),) = asked
        block = label.document.findBlockByNumber(k)
        assert block.text() == rows[k]
        box = layout.blockBoundingRect(block)
        top, bottom = RichText.MARGIN + box.top(), RichText.MARGIN + box.bottom()
        assert rect.top() <= top and rect.top() + rect.height() >= bottom, k  # the whole line
        assert rect.top() > top - 1 and rect.top() + rect.height() <= bottom + 2, k
        assert rect.left() == 0 and rect.width() == label.width()
        QApplication.processEvents()
        label.setText(lines_page([f"row {j} value 0" for j in range(6)]))
        QApplication.processEvents()


def test_a_line_that_grows_when_painted_into_sight_lays_the_text_out_again(qtbot):
    """A value written while its line is painted (it came into sight) that wraps the line:
    every line after it moved, so the widget asks for its new height and repaints whole."""
    from PyQt6.QtWidgets import QApplication

    def paragraphs(rows: list[str]) -> str:  # wrapped to the width, unlike a <pre>'s lines
        return "".join(f"<p style='margin:0'>{slot(row)}</p>" for row in rows)

    area, label = _scrolled(qtbot)
    rows = [f"row {k} value 0" for k in range(40)]
    label.setText(paragraphs(rows))
    QApplication.processEvents()
    before = label.minimumHeight()
    rows[39] = " ".join(["long"] * 30)  # off screen: written when painted
    label.setText(paragraphs(rows))
    assert label.slots_held == 40 and label.slots_pending == 1 and label.minimumHeight() == before
    area.verticalScrollBar().setValue(area.verticalScrollBar().maximum())
    QApplication.processEvents()
    assert label.slots_pending == 0 and _block_texts(label)[39] == rows[39]
    assert label.minimumHeight() == round(label.document.size().height()) + 2 * RichText.MARGIN > before


def test_the_same_text_with_other_stale_slots_is_taken(qtbot):
    """The same text given again with other slots marked stale: a value no longer stale is
    the text's own (the owner is not asked), a newly stale one is asked for when read."""
    label = RichText()
    qtbot.addWidget(label)
    asked = []
    label.fill = lambda: asked.append(1) or lines_page(["fresh a", "fresh b"])
    text = lines_page(["old a", "old b"])
    label.setText(lines_page(["x", "y"]))
    label.setText(text, stale=[1])
    label.setText(text)  # the same text, its values now all its own
    assert label.plain_text() == "old a\nold b" and asked == []
    label.setText(text, stale=[0])  # the same text again, a value stale
    assert label.plain_text() == "fresh a\nfresh b" and asked == [1]


def test_a_hidden_text_with_stale_slots_is_read_as_the_owner_has_it_now(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    label.fill = lambda: lines_page(["fresh a", "fresh b"])
    label.setText(lines_page(["a", "b"]))
    label.setText(lines_page(["a", "old b"]), stale=[1])
    assert _block_texts(label) == ["a", "b"]  # hidden: nothing written
    assert label.plain_text() == "fresh a\nfresh b" and label.slots_pending == 0
    assert _block_texts(label) == ["fresh a", "fresh b"] and label.slots_held == 2


def test_stale_slots_read_keep_the_users_selection(qtbot):
    """Reading a text with stale slots takes the owner's values into the slots held (the
    same template): not parsed again, so the user's selection stays."""
    label = RichText()
    qtbot.addWidget(label)
    label.fill = lambda: "<p>Frame " + slot("2") + "</p>" + lines_page(["fresh a", "fresh b"])
    label.setText("<p>Frame " + slot("1") + "</p>" + lines_page(["a", "b"]))
    label.cursor.setPosition(0)
    label.cursor.setPosition(5, QTextCursor.MoveMode.KeepAnchor)
    label.setText("<p>Frame " + slot("2") + "</p>" + lines_page(["a", "b"]), stale=[1, 2])
    assert label.plain_text() == "Frame 2\nfresh a\nfresh b"
    assert label.selected_text() == "Frame" and label.slots_held == 3


def test_a_stale_slot_on_screen_whose_fresh_text_has_other_slots_is_parsed_whole(qtbot):
    """A stale slot on screen asks the owner; its text as it is now has another template
    (here one slot more): parsed whole, and shown whole."""
    label = shown(qtbot, "<p>a " + slot("1") + "</p><p>" + slot("2") + "</p>")
    label.fill = lambda: "<p>b " + slot("3") + "</p><p>" + slot("4") + " " + slot("5") + "</p>"
    label.setText("<p>a " + slot("1") + "</p><p>" + slot("9") + "</p>", stale=[1])
    assert label.slots_held == 3 and label.slots_pending == 0
    assert label.document.toPlainText() == "b 3\n4 5"


def test_glyphs_reaching_from_a_neighbouring_line_are_drawn_when_a_line_alone_is(qtbot):
    """A line whose glyphs reach below its block (marks stacked under its letters) over the
    next line: the next line's part painted alone shows them, as a whole repaint does."""
    from PyQt6.QtCore import QRect
    from PyQt6.QtGui import QColor, QImage, QRegion

    marks = ("g" + "\u0329" * 4) * 5
    label = shown(qtbot, f"<p style='margin:0'>{marks}</p><p style='margin:0'>{slot('xxxx')}</p>")
    line = label.document.documentLayout().blockBoundingRect(label.document.firstBlock().next())

    def render(region: QRect | None) -> QImage:
        image = QImage(label.size(), QImage.Format.Format_RGB32)
        image.fill(QColor("white"))
        if region is None:
            label.render(image)
        else:
            label.render(image, region.topLeft(), QRegion(region))
        return image

    whole = render(None)
    part = QRect(0, int(line.top()) + RichText.MARGIN, label.width(), int(line.height()) + 2)
    alone = render(part)
    rows = range(part.top(), part.bottom() + 1)
    reaching = [(x, y) for y in rows[:3] for x in range(label.width()) if QColor(whole.pixel(x, y)).lightness() < 128]
    assert len(reaching) > 10  # the marks of the line above, in the next line's top rows
    assert all(whole.pixel(x, y) == alone.pixel(x, y) for y in rows for x in range(label.width()))
