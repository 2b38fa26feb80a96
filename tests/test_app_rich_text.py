"""RichText's slots (app/docks/rich_text.py): a text that differs from the shown one in its
slots only is written slot by slot, and shows exactly what parsing it whole would show."""

from __future__ import annotations

import pytest
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
