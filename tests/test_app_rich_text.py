"""RichText's slots (app/docks/rich_text.py): a text that differs from the shown one in its
slots only is written slot by slot, and shows exactly what parsing it whole would show."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtGui import QFont, QTextCursor, QTextDocument

from gmr_studio.app.docks.rich_text import SLOT_CLOSE, SLOT_OPEN, RichText, slot, slot_lines

pytestmark = pytest.mark.gui


def parsed(html_text: str) -> str:
    """The plain text of ``html_text`` parsed whole, marks taken out."""
    document = QTextDocument()
    document.setHtml(html_text.replace(SLOT_OPEN, "").replace(SLOT_CLOSE, ""))
    return document.toPlainText()


def page(frame: int, angles: str, rows: list[str]) -> str:
    """A text like the inspector's: a bold slot, slots in a paragraph, a <pre> of slot lines."""
    return (
        f"<p><b>Frame {slot(str(frame))}</b> of 120 &nbsp; (a &lt;test&gt;)</p>"
        f"<p>Euler ZYX: {slot(angles)} deg, then the rest</p>"
        f"<pre style='margin:0'>{slot_lines(chr(10).join(rows))}</pre><p>The end</p>"
    )


def test_a_slot_is_escaped_text_between_two_marks_and_lines_are_slots_each():
    assert slot("a<b & c") == f"{SLOT_OPEN}a&lt;b &amp; c{SLOT_CLOSE}"
    assert slot_lines("1 2\n 3") == f"{SLOT_OPEN}1 2{SLOT_CLOSE}\n{SLOT_OPEN} 3{SLOT_CLOSE}"


def test_new_values_are_written_in_place_as_parsing_would_show_them(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    first = page(7, "1.000, 2.000, 3.000", ["    0.5   -0.25", "  1 | 2"])
    label.setText(first)
    assert label.slots_held == 4 and label.plain_text() == parsed(first)
    assert SLOT_OPEN not in label.document.toRawText() and SLOT_CLOSE not in label.document.toRawText()
    blocks = label.document.blockCount()
    # longer, shorter, empty, escaped and non-BMP values, each slot moved by those before it
    for frame, angles, rows in (
        (1234, "-179.999, 0.000, 12.500", ["  -10.5    0.25", "1 | 2 | 3"]),
        (3, "0, 0, 0", ["0", "x"]),
        (99, "a<b & c \U0001f600", ["\U0001f600  1", "  2  "]),
        (7, "1.000, 2.000, 3.000", ["    0.5   -0.25", "  1 | 2"]),
    ):
        text = page(frame, angles, rows)
        label.setText(text)
        assert label.plain_text() == parsed(text), (frame, label.plain_text())
        assert label.slots_held == 4 and label.document.blockCount() == blocks
        assert label.text() == text
    assert not label.document.isUndoAvailable()  # written every frame: no history kept


def test_a_rewritten_slot_keeps_its_format_and_the_users_selection_stays(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    label.setText(page(7, "1, 2, 3", ["a", "b"]))
    end = label.plain_text().index("The end")
    label.cursor.setPosition(end)
    label.cursor.setPosition(end + 7, QTextCursor.MoveMode.KeepAnchor)
    assert label.selected_text() == "The end"
    label.setText(page(123456, "4.5, 5.5, 6.5", ["aaaa", "bbbb"]))
    assert label.selected_text() == "The end"  # moved with the text before it, not reset
    start = label.plain_text().index("123456")
    cursor = QTextCursor(label.document)
    cursor.setPosition(start + 1)
    assert cursor.charFormat().fontWeight() == QFont.Weight.Bold  # the frame's number stays bold
    cursor.setPosition(label.plain_text().index("4.5") + 1)
    assert cursor.charFormat().fontWeight() != QFont.Weight.Bold
    # another text around the slots: parsed whole, the selection gone
    other = page(1, "1, 2, 3", ["a", "b"]).replace("The end", "Another end")
    label.setText(other)
    assert label.plain_text() == parsed(other) and not label.cursor.hasSelection()
    assert label.slots_held == 4


def test_slots_the_parser_does_not_give_back_as_written_make_the_text_parsed_whole(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    folded = "<p>Offset: {}</p>"  # outside a <pre> the parser folds runs of spaces
    label.setText(folded.format(slot("1   2")))
    assert label.slots_held == 0 and label.plain_text() == "Offset: 1 2"
    label.setText(folded.format(slot("3   4")))
    assert label.slots_held == 0 and label.plain_text() == "Offset: 3 4"
    label.setText("<p>no slot at all</p>")
    assert label.slots_held == 0 and label.plain_text() == "no slot at all"
    label.setText(folded.format(slot("5 6")))  # a slot as parsed: held again
    assert label.slots_held == 1 and label.plain_text() == "Offset: 5 6"
    assert SLOT_OPEN not in label.document.toRawText()


def shown(qtbot, html_text: str, width: int = 300) -> RichText:
    label = RichText()
    qtbot.addWidget(label)
    label.resize(width, 50)
    label.setText(html_text)
    label.show()
    qtbot.waitExposed(label)
    return label


def test_the_text_is_laid_out_to_the_width_and_asks_for_its_height(qtbot):
    label = shown(qtbot, "<p>" + " ".join(["word"] * 60) + "</p>", width=300)
    margin = RichText.MARGIN
    assert label.document.textWidth() == 300 - 2 * margin
    tall = label.minimumHeight()
    assert tall == round(label.document.size().height()) + 2 * margin and tall > 3 * label.fontMetrics().height()
    hint = label.sizeHint()
    assert hint.width() == round(label.document.idealWidth()) + 2 * margin and hint.height() == tall
    label.resize(600, tall)  # wider: fewer lines, a lower minimum
    assert label.document.textWidth() == 600 - 2 * margin and label.minimumHeight() < tall
    label.resize(600, tall + 40)  # only taller: the text is not laid out again
    assert label.document.textWidth() == 600 - 2 * margin


def test_the_text_is_drawn_inside_the_margin_and_a_selection_in_the_highlight(qtbot):
    from PyQt6.QtGui import QColor, QPalette

    label = shown(qtbot, "<p>MMMM MMMM MMMM</p>")
    palette = label.palette()
    palette.setColor(QPalette.ColorRole.Window, QColor("white"))
    palette.setColor(QPalette.ColorRole.WindowText, QColor("black"))
    palette.setColor(QPalette.ColorRole.Highlight, QColor(0, 0, 255))
    label.setPalette(palette)
    label.setAutoFillBackground(True)
    image = label.grab().toImage()
    dark = [
        (x, y) for y in range(image.height()) for x in range(image.width()) if image.pixelColor(x, y).lightness() < 100
    ]
    xs, ys = [x for x, _ in dark], [y for _, y in dark]
    margin = RichText.MARGIN
    assert dark and min(xs) >= margin and min(ys) >= margin and min(xs) <= margin + 3
    assert not any(image.pixelColor(x, y).blue() > 200 > image.pixelColor(x, y).red() for x, y in dark)
    label.select_all()
    image = label.grab().toImage()
    blue = sum(
        1
        for y in range(image.height())
        for x in range(image.width())
        if image.pixelColor(x, y).blue() > 200 and image.pixelColor(x, y).red() < 60
    )
    assert blue > 200  # the selected text on the highlight colour


def _mouse(kind, x: float, y: float, button, buttons):
    from PyQt6.QtCore import QPointF
    from PyQt6.QtGui import QMouseEvent

    point = QPointF(x, y)
    return QMouseEvent(kind, point, point, button, buttons, Qt.KeyboardModifier.NoModifier)


def test_dragging_with_the_left_button_selects_and_the_copy_key_copies(qtbot):
    from PyQt6.QtCore import QEvent
    from PyQt6.QtGui import QGuiApplication, QKeySequence
    from PyQt6.QtWidgets import QApplication

    label = shown(qtbot, "<p>alpha beta gamma</p>")
    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton
    y = RichText.MARGIN + label.fontMetrics().height() / 2
    end_of_alpha = RichText.MARGIN + label.fontMetrics().horizontalAdvance("alpha")
    label.mousePressEvent(_mouse(QEvent.Type.MouseButtonPress, RichText.MARGIN, y, left, left))
    label.mouseMoveEvent(_mouse(QEvent.Type.MouseMove, end_of_alpha + 1, y, none, none))  # no button held
    assert not label.cursor.hasSelection()
    label.mouseMoveEvent(_mouse(QEvent.Type.MouseMove, end_of_alpha + 1, y, none, left))
    assert label.selected_text() == "alpha"
    label.mousePressEvent(_mouse(QEvent.Type.MouseButtonPress, 200, y, Qt.MouseButton.RightButton, none))
    assert label.selected_text() == "alpha"  # another button leaves the selection
    QGuiApplication.clipboard().setText("before")
    qtbot.keyClick(label, Qt.Key.Key_X, Qt.KeyboardModifier.ControlModifier)  # another key: nothing
    assert QGuiApplication.clipboard().text() == "before"
    copy = QKeySequence(QKeySequence.StandardKey.Copy)[0]
    qtbot.keyClick(label, copy.key(), copy.keyboardModifiers())
    assert QGuiApplication.clipboard().text() == "alpha"
    every = QKeySequence(QKeySequence.StandardKey.SelectAll)[0]
    qtbot.keyClick(label, every.key(), every.keyboardModifiers())
    assert label.selected_text() == "alpha beta gamma"
    label.mousePressEvent(_mouse(QEvent.Type.MouseButtonPress, RichText.MARGIN, y, left, left))
    assert not label.cursor.hasSelection()
    QGuiApplication.clipboard().setText("kept")
    label.copy()  # nothing selected: the clipboard is left alone
    assert QApplication.clipboard().text() == "kept"


def test_the_context_menu_copies_when_there_is_a_selection_and_selects_all(qtbot, monkeypatch):
    from PyQt6.QtCore import QPoint
    from PyQt6.QtGui import QContextMenuEvent
    from PyQt6.QtWidgets import QMenu

    label = shown(qtbot, "<p>alpha beta</p>")
    offered = []
    monkeypatch.setattr(
        QMenu, "exec", lambda menu, *_: offered.append([(a.text(), a.isEnabled()) for a in menu.actions()])
    )
    event = QContextMenuEvent(QContextMenuEvent.Reason.Mouse, QPoint(5, 5), QPoint(5, 5))
    label.contextMenuEvent(event)
    label.select_all()
    label.contextMenuEvent(event)
    assert offered == [[("&Copy", False), ("Select &All", True)], [("&Copy", True), ("Select &All", True)]]


def test_only_the_slots_that_changed_are_written_and_each_in_its_own_format(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    text = "<p>x<b>{}</b>y {} z <i>{}</i></p>"  # a bold slot right after plain text, an italic one
    label.setText(text.format(slot("1"), slot("2"), slot("3")))
    assert label.plain_text() == "x1y 2 z 3"
    label.setText(text.format(slot("1"), slot("2"), slot("345")))  # the first two unchanged, the last one longer
    assert label.plain_text() == "x1y 2 z 345" and label.slots_held == 3
    label.setText(text.format(slot("1"), slot("22"), slot("345")))  # one in the middle
    assert label.plain_text() == "x1y 22 z 345"
    label.setText(text.format(slot("10"), slot("22"), slot("6")))
    assert label.plain_text() == "x10y 22 z 6"
    cursor = QTextCursor(label.document)
    weights = []
    for position in range(1, len("x10y 22 z 6") + 1):
        cursor.setPosition(position)  # the format of the character before the position
        weights.append((cursor.charFormat().fontWeight() == QFont.Weight.Bold, cursor.charFormat().fontItalic()))
    assert [bold for bold, _ in weights] == [False, True, True] + [False] * 8  # only "10" bold
    assert [italic for _, italic in weights] == [False] * 10 + [True]  # only "6" italic


def test_positions_count_a_character_beyond_16_bits_as_two(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    text = "<p>\U0001f600\U00010000 {} <b>\uffff</b> {} {}</p>"  # U+10000: the first of them
    label.setText(text.format(slot("\U0001f642"), slot("a"), slot("b")))
    assert label.slots_held == 3 and label.plain_text() == "\U0001f600\U00010000 \U0001f642 \uffff a b"
    label.setText(text.format(slot("\U0001f642\U0001f642"), slot("cc"), slot("d")))
    assert label.plain_text() == "\U0001f600\U00010000 \U0001f642\U0001f642 \uffff cc d"


def test_stray_marks_in_the_text_around_the_slots_make_it_parsed_whole(qtbot):
    label = RichText()
    qtbot.addWidget(label)
    for text in (slot("1") + SLOT_OPEN, SLOT_CLOSE + slot("1"), slot("1") + SLOT_OPEN + " " + SLOT_OPEN):
        label.setText(f"<p>{text}</p>")
        assert label.slots_held == 0 and label.plain_text().strip() == "1"  # every mark taken out
    label.setText(f"<p>{slot('2')}</p>")
    assert label.slots_held == 1 and label.plain_text() == "2"


def test_the_margin_is_six_pixels_and_the_document_has_none(qtbot):
    label = shown(qtbot, "<p>M</p>", width=100)
    assert RichText.MARGIN == 6 and label.document.documentMargin() == 0
    assert label.minimumHeight() == round(label.document.size().height()) + 12
    line = label.document.documentLayout().blockBoundingRect(label.document.firstBlock())
    assert line.top() == 0 and line.left() == 0
    label.resize(5, 40)  # narrower than the margins: the text keeps a width of one pixel
    assert label.document.textWidth() == 1


def test_an_exposed_strip_draws_the_line_it_crosses(qtbot):
    """Eight one-line paragraphs of full blocks; a strip 4 pixels high through the middle of
    line k is painted alone: the layout draws the blocks that meet the exposed part, taken
    to the document's coordinates (the margin off), so line k shows in it."""
    from PyQt6.QtCore import QRect

    label = shown(qtbot, "".join(["<p style='margin:0'>\u2588\u2588\u2588\u2588</p>"] * 8), width=200)
    line = label.document.documentLayout().blockBoundingRect(label.document.firstBlock()).height()
    assert line >= 13
    for k in (2, 6):
        top = round(RichText.MARGIN + k * line + line - 10)  # 10 to 6 pixels above the line's bottom
        image = label.grab(QRect(0, top, 200, 4)).toImage()
        dark = sum(
            1 for y in range(image.height()) for x in range(image.width()) if image.pixelColor(x, y).lightness() < 100
        )
        assert dark > 20, k


def test_dragging_back_to_the_start_selects_from_it(qtbot):
    from PyQt6.QtCore import QEvent

    label = shown(qtbot, "<p>alpha beta</p>")
    left = Qt.MouseButton.LeftButton
    y = RichText.MARGIN + label.fontMetrics().height() / 2
    end_of_alpha = RichText.MARGIN + label.fontMetrics().horizontalAdvance("alpha")
    label.mousePressEvent(_mouse(QEvent.Type.MouseButtonPress, end_of_alpha + 1, y, left, left))
    label.mouseMoveEvent(_mouse(QEvent.Type.MouseMove, 0, y, Qt.MouseButton.NoButton, left))  # position 0
    assert label.selected_text() == "alpha" and label.cursor.position() == 0
