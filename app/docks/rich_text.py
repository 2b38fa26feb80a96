"""Rich text for the docks: laid out once per change, selectable, and rewritten slot by slot.

:class:`RichText` draws HTML wrapped to its width as a word-wrapped ``QLabel`` would, with
one layout per change. The inspector shows the selected joint's numbers at every frame: it
marks each number as a *slot* (:func:`slot`), and a new frame, whose text differs from the
shown one in slots only, rewrites the changed slots in place instead of parsing and laying
out the whole text again.

A slot costs only when seen, as a dock does (:mod:`app.docks.frame_follow`): a changed
value is written into the document only if its line is in the part of the widget on screen
(the scroll area shows a third of the inspector's text at the default layout), and only
the lines written are repainted; a value off screen is written when its line is painted
(scrolled, resized or shown into sight) or the text is read. Its owner need not even
compute it: a text may come with *stale* slots (:meth:`RichText.setText`), values left from
an earlier text; when one of them must be written or read, the widget asks the owner for
the whole text as it is now (:attr:`RichText.fill`) and takes its values.
"""

from __future__ import annotations

import html
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
from PyQt6.QtCore import QPointF, QRect, QRectF, QSize, Qt
from PyQt6.QtGui import (
    QAbstractTextDocumentLayout,
    QGuiApplication,
    QKeySequence,
    QPainter,
    QRegion,
    QTextCharFormat,
    QTextCursor,
    QTextDocument,
)
from PyQt6.QtWidgets import QMenu, QSizePolicy, QWidget

OVERHANG = 4  # pixels a line's glyphs may reach beyond its block (accents, descenders)
SLOT_OPEN, SLOT_CLOSE = "\ue000", "\ue001"  # private-use characters: never in a shown text
_SLOT = re.compile(f"{SLOT_OPEN}([^{SLOT_CLOSE}]*){SLOT_CLOSE}")


def slot(text: str) -> str:
    """``text`` (plain: escaped here) marked as a slot of :meth:`RichText.setText`'s HTML: a
    value that changes while the text around it stays (a frame's number). One line, no
    runs of spaces unless inside a ``<pre>`` (else the whole text is parsed every time)."""
    return f"{SLOT_OPEN}{html.escape(text)}{SLOT_CLOSE}"


def slot_lines(text: str) -> str:
    """Each line of ``text`` as its own slot (the lines of a ``<pre>`` are blocks)."""
    return "\n".join(slot(line) for line in text.split("\n"))


def _split(html_text: str) -> tuple[str, list[str]]:
    """(template, values): ``html_text`` with every slot emptied, and the slots' values."""
    return _SLOT.sub(SLOT_OPEN + SLOT_CLOSE, html_text), [html.unescape(v) for v in _SLOT.findall(html_text)]


def _utf16_length(text: str) -> int:
    """The length of ``text`` in document positions (UTF-16 code units)."""
    return len(text.encode("utf-16-le")) // 2


@dataclass
class _Slot:
    """Where a slot's value is in the document: first position, length, its format, the
    value written there, and the top and bottom of its line (document coordinates)."""

    start: int
    length: int
    format: QTextCharFormat
    value: str
    top: float = 0.0
    bottom: float = 0.0


class RichText(QWidget):
    """Rich text wrapped to the widget's width, as a word-wrapped ``QLabel`` draws it, but
    laid out once per change: a label lays its document out three to four times per
    ``setText`` (size hint, height for width, paint), which during playback is a large part
    of every frame under software rendering. Text is selectable by mouse and copied
    with the copy key or the context menu, as in a selectable label.

    A text whose values are marked as slots (:func:`slot`) and whose rest is the text shown
    already is not parsed again: only the slots whose values changed are written into the
    document (its layout redoes their blocks only), and a selection made by the user stays.
    A slot is plain text within one block (one line of a ``<pre>``: :func:`slot_lines`).
    """

    MARGIN = 6  # pixels around the text, as the label's margin

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.document = QTextDocument(self)
        self.document.setDocumentMargin(0)
        self.document.setDefaultFont(self.font())
        self.document.setUndoRedoEnabled(False)  # slots are rewritten every frame: keep no history
        self._html = ""
        self._template = ""  # the text with every slot emptied: what must stay for slots to be written alone
        self._slots: list[_Slot] = []
        self._wanted: list[str] = []  # the latest value of every slot (written or not yet)
        self._stale: set[int] = set()  # slots whose values in the text are left from an earlier one
        #: the owner's whole text as it is now, every value fresh: asked for when a stale slot
        #: must be written or the text is read (None: no text is given with stale slots)
        self.fill: Callable[[], str] | None = None
        self.cursor = QTextCursor(self.document)  # the selection
        self._asked: list[QRect] = []  # the lines asked to be repainted since the last paint
        #: the parts of the widget the last paint drew the text in (for tests)
        self.painted: list[QRect] = []
        self.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Minimum)
        self.setFocusPolicy(Qt.FocusPolicy.ClickFocus)
        self.setCursor(Qt.CursorShape.IBeamCursor)
        self.setContextMenuPolicy(Qt.ContextMenuPolicy.DefaultContextMenu)

    def text(self) -> str:
        """The text shown, every value in it fresh."""
        if self._stale:
            self._take_fresh()
        return self._html

    def setText(self, html_text: str, stale: Iterable[int] = ()) -> None:  # noqa: N802 (QLabel's name)
        """Show ``html_text``. ``stale``: indices of slots whose values in it are left from an
        earlier text (not computed for this one); :attr:`fill` gives them when needed."""
        stale = set(stale)
        if html_text == self._html and stale == self._stale:
            return
        self._html = html_text
        template, values = _split(html_text)
        if self._slots and template == self._template:
            self._wanted, self._stale = values, stale
            self._fit(self._write_slots(self._on_screen()))
            return
        if stale:  # parsed whole: every value must be this text's
            self._html = self.fill()
            template, values = _split(self._html)
        self._parse(template, values)

    def _parse(self, template: str, values: list[str]) -> None:
        """Parse :attr:`_html` whole (its template and values given)."""
        self._template = template
        self._stale = set()
        self.document.setHtml(self._html)
        self._slots = self._find_slots(values)  # none held: the next text is parsed whole
        self._wanted = values if self._slots else []
        self.cursor = QTextCursor(self.document)
        self._fit(None)

    def _take_fresh(self) -> bool:
        """Take the owner's text as it is now (:attr:`fill`): its values for every slot, or,
        when its template differs, the text parsed whole (False)."""
        self._html = self.fill()
        template, values = _split(self._html)
        if self._slots and template == self._template:
            self._wanted, self._stale = values, set()
            return True
        self._parse(template, values)
        return False

    @property
    def slots_held(self) -> int:
        """How many slots a text of the same template would have rewritten in place (0: the
        next text is parsed whole)."""
        return len(self._slots)

    @property
    def slots_pending(self) -> int:
        """How many slots hold an older value than the text's, or a stale one, their lines
        not on screen."""
        pairs = enumerate(zip(self._slots, self._wanted, strict=True))
        return len(self._stale.union(i for i, (held, value) in pairs if held.value != value))

    def slots_on_screen(self) -> list[bool]:
        """For each slot, whether its line is in the part of the widget on screen."""
        return self._lines_meeting(self._on_screen())

    def _lines_meeting(self, within: QRectF | None) -> list[bool]:
        """For each slot, whether its line meets ``within`` (document coordinates; None: none)."""
        if within is None:
            return [False] * len(self._slots)
        top, bottom = within.top(), within.bottom()
        return [held.bottom >= top and held.top <= bottom for held in self._slots]

    def plain_text(self) -> str:
        """The text without markup, every slot's latest value in it."""
        self._write_pending()
        return self.document.toPlainText()

    def _find_slots(self, values: list[str]) -> list[_Slot]:
        """Take the slot marks out of the parsed document and note where each slot is (its
        start, length and character format). [] when there is none, or when a slot did not
        come out of the HTML parser as its value (white space folded outside a ``<pre>``,
        a slot across blocks): such a text is always parsed whole."""
        raw = self.document.toRawText()  # a character a document position (a UTF-16 pair: two)
        where = np.cumsum([0] + [2 if ord(c) > 0xFFFF else 1 for c in raw])  # code point -> position
        marks = [i for i, c in enumerate(raw) if c in (SLOT_OPEN, SLOT_CLOSE)]
        cursor = QTextCursor(self.document)
        cursor.beginEditBlock()
        for index in reversed(marks):
            cursor.setPosition(int(where[index]))
            cursor.deleteChar()
        cursor.endEditBlock()
        pairs = [(marks[k], marks[k + 1]) for k in range(0, len(marks) - 1, 2)]
        if not values or len(marks) != 2 * len(values) or any(raw[a] != SLOT_OPEN for a, _ in pairs):
            return []
        slots = []
        for k, ((first, last), value) in enumerate(zip(pairs, values, strict=True)):
            if raw[first + 1 : last] != value:
                return []
            start, length = int(where[first]) - 2 * k, int(where[last] - where[first]) - 1
            cursor.setPosition(start + 1 if length else start)
            slots.append(_Slot(start, length, cursor.charFormat(), value))
        self._measure(slots)
        return slots

    def _measure(self, slots: list[_Slot]) -> None:
        """Note the top and bottom of each slot's line (its block: a slot is within one)."""
        layout = self.document.documentLayout()
        for held in slots:
            rect = layout.blockBoundingRect(self.document.findBlock(held.start))
            held.top, held.bottom = rect.top(), rect.bottom()

    def _on_screen(self) -> QRectF | None:
        """The part of the document on screen (document coordinates), None when none is."""
        seen = self.visibleRegion().boundingRect()
        return None if seen.isEmpty() else self._document_rect(seen)

    def _write_slots(self, within: QRectF | None) -> list[QRectF] | None:
        """Write each slot whose value changed and whose line meets ``within`` (document
        coordinates; None: no line) over its old value, in its format, in one edit (the layout
        redoes the changed blocks once, at its end, rather than once per slot). The
        lines written, to repaint (document coordinates), or None when a line changed height
        (every line after it moved: everything is repainted)."""
        seen = self._lines_meeting(within)
        if any(seen[i] for i in self._stale) and not self._take_fresh():
            return None  # the text as it is now has another template: parsed whole
        chosen = [on and value != held.value for on, held, value in zip(seen, self._slots, self._wanted, strict=True)]
        if not any(chosen):
            return []
        cursor = QTextCursor(self.document)
        cursor.beginEditBlock()
        shift = 0  # how far the slots after a rewritten one moved
        for held, value, write in zip(self._slots, self._wanted, chosen, strict=True):
            held.start += shift
            if not write:
                continue
            cursor.setPosition(held.start)
            cursor.setPosition(held.start + held.length, QTextCursor.MoveMode.KeepAnchor)
            cursor.insertText(value, held.format)
            length = _utf16_length(value)
            shift += length - held.length
            held.length, held.value = length, value
        cursor.endEditBlock()
        layout = self.document.documentLayout()
        lines = []
        for held, write in zip(self._slots, chosen, strict=True):
            if write:
                rect = layout.blockBoundingRect(self.document.findBlock(held.start))
                if (rect.top(), rect.bottom()) != (held.top, held.bottom):
                    self._measure(self._slots)
                    return None
                lines.append(rect)
        return lines

    def _write_pending(self) -> None:
        """Write every slot not written yet (the text is read)."""
        if self._stale and not self._take_fresh():
            return  # parsed whole
        if self.slots_pending:
            self._fit(self._write_slots(QRectF(0, -1, 1, self.document.size().height() + 2)))

    def _document_rect(self, rect) -> QRectF:
        """A rectangle of the widget in document coordinates (the margin off)."""
        return QRectF(rect).translated(-self.MARGIN, -self.MARGIN)

    def _fit(self, lines: list[QRectF] | None) -> None:
        """Lay the text out to the width, ask for its height, and repaint ``lines`` (document
        coordinates; None: everything)."""
        width = max(1, self.width() - 2 * self.MARGIN)
        if width != self.document.textWidth():  # a new text keeps the width; setting it again lays out twice
            self.document.setTextWidth(width)
            self._measure(self._slots)
            lines = None
        height = round(self.document.size().height()) + 2 * self.MARGIN
        if height != self.minimumHeight():
            self.setMinimumHeight(height)
        if lines is None:
            self.update()
            return
        for line in lines:  # the whole width: a shorter value leaves the end of a longer one
            rect = QRect(0, int(line.top()) + self.MARGIN, self.width(), int(line.height()) + 2)
            self._asked.append(rect)
            self.update(rect)

    def sizeHint(self) -> QSize:  # noqa: N802 (Qt's name)
        return QSize(round(self.document.idealWidth()) + 2 * self.MARGIN, self.minimumHeight())

    def resizeEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        if event.size().width() != event.oldSize().width():
            self._fit(None)
        super().resizeEvent(event)

    def paintEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        # lines coming into sight get their slots' latest values first (painted now; a line
        # that changed height moved the rest: everything again, at the next paint)
        if self.slots_pending and self._write_slots(self._document_rect(event.rect())) is None:
            self._fit(None)
        painter = QPainter(self)
        painter.translate(self.MARGIN, self.MARGIN)
        context = QAbstractTextDocumentLayout.PaintContext()
        context.palette = self.palette()
        context.palette.setColor(context.palette.ColorRole.Text, self.palette().color(self.foregroundRole()))
        if self.cursor.hasSelection():
            selection = QAbstractTextDocumentLayout.Selection()
            selection.cursor = self.cursor
            selection.format.setBackground(self.palette().highlight())
            selection.format.setForeground(self.palette().highlightedText())
            context.selections = [selection]
        # only the exposed part (what the scroll area shows, the lines rewritten): the layout
        # skips the blocks outside it (about half the text's drawing time at the default
        # size); when the exposed part is just lines rewritten, each alone, not the lines
        # between them (the inspector's frame number and angles have its table between them)
        self.painted = self._parts_to_paint(event)
        for rect in self.painted:
            # each part drawn within itself, once (the painter otherwise keeps to the whole
            # exposed region); the layout's clip grown by a few pixels, so that a
            # neighbouring line's glyphs that reach into the part are drawn too
            area = self._document_rect(rect)
            painter.setClipRect(area)
            context.clip = area.adjusted(0, -OVERHANG, 0, OVERHANG)
            self.document.documentLayout().draw(painter, context)
        painter.end()

    def _parts_to_paint(self, event) -> list[QRect]:
        """The rectangles to draw the text in for ``event``: the lines asked for when the
        exposed region is only those, else the region's bounding rectangle."""
        region = event.region()
        asked = sorted((rect for rect in self._asked if region.intersects(rect)), key=QRect.top)
        self._asked = []
        merged: list[QRect] = []  # each line once (two slots of a line, or a line asked twice)
        for rect in asked:
            if merged and rect.top() <= merged[-1].bottom() + 1:
                merged[-1] = merged[-1].united(rect)
            else:
                merged.append(QRect(rect))
        if merged:
            covered = QRegion()
            for rect in merged:
                covered = covered.united(QRegion(rect))
            if region.subtracted(covered).isEmpty():
                return [rect.intersected(event.rect()) for rect in merged]
        return [event.rect()]

    def selected_text(self) -> str:
        self._write_pending()
        return self.cursor.selection().toPlainText()

    def _position_at(self, point: QPointF) -> int:
        layout = self.document.documentLayout()
        return layout.hitTest(point - QPointF(self.MARGIN, self.MARGIN), Qt.HitTestAccuracy.FuzzyHit)

    def mousePressEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        if event.button() == Qt.MouseButton.LeftButton:
            self.cursor.setPosition(max(self._position_at(event.position()), 0))
            self.update()
        super().mousePressEvent(event)

    def mouseMoveEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        if event.buttons() & Qt.MouseButton.LeftButton:
            position = self._position_at(event.position())
            if position >= 0:
                self.cursor.setPosition(position, QTextCursor.MoveMode.KeepAnchor)
                self.update()

    def keyPressEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        if event.matches(QKeySequence.StandardKey.Copy):
            self.copy()
        elif event.matches(QKeySequence.StandardKey.SelectAll):
            self.select_all()
        else:
            super().keyPressEvent(event)

    def contextMenuEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        menu = QMenu(self)
        menu.addAction("&Copy", self.copy).setEnabled(self.cursor.hasSelection())
        menu.addAction("Select &All", self.select_all)
        menu.exec(event.globalPos())

    def copy(self) -> None:
        if self.cursor.hasSelection():
            QGuiApplication.clipboard().setText(self.selected_text())

    def select_all(self) -> None:
        self.cursor.select(QTextCursor.SelectionType.Document)
        self.update()
