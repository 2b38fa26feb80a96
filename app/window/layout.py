"""The window's layout: a view that takes the room, docks beside it, analysis on request.

The default layout is made for looking at motion:

- the 3D view in the centre, with at least :data:`VIEW_AREA_SHARE` of the window's area at
  1280x800 and at 1920x1080 (:func:`view_share` measures it);
- the timeline as a strip under it (its height fixed to what its widgets need);
- Forest above Inspector in one column beside the view, :func:`side_width` wide (Layers,
  Teach and History are tabs of that column when shown);
- Curves, Foot contacts and Error in one tabbed area between the view and the timeline,
  hidden until asked for (View menu) and tabbed together whenever more than one is shown
  (:func:`tab_when_shown`).

A layout saved by the window is restored only when it carries :data:`LAYOUT_VERSION`: older
layouts (the view stacked under three bottom docks) are replaced by the default, and a
restored layout that leaves the view less than :data:`RESTORED_MINIMUM_SHARE` of the window
is replaced too (:func:`restore_layout`), so nobody is left with a tiny view.
"""

from __future__ import annotations

from PyQt6.QtCore import QEvent, QObject, QSettings, Qt
from PyQt6.QtWidgets import QDockWidget, QMainWindow, QSizePolicy

LAYOUT_VERSION = 2
VIEW_AREA_SHARE = 0.6  # of the window's area, in the default layout
RESTORED_MINIMUM_SHARE = 0.35  # a restored layout with less is replaced by the default
SIDE_SHARE = 0.2  # of the window's width for the Forest/Inspector column
SIDE_LIMITS = (230, 360)  # pixels: the column's width is kept within these
DOCK_MINIMUM = 100  # pixels: the least a side dock's content may be squeezed to
VIEW_MINIMUM = (200, 150)
SLIDER_MINIMUM = 120
BOTTOM_HEIGHT = 240  # the analysis area's height when first shown


def side_width(window_width: int) -> int:
    """The Forest/Inspector column's width for a window ``window_width`` pixels wide."""
    low, high = SIDE_LIMITS
    return int(min(max(SIDE_SHARE * window_width, low), high))


def view_share(window: QMainWindow, view) -> float:
    """The view's share of the window's area (0 to 1)."""
    area = window.width() * window.height()
    return view.width() * view.height() / area if area else 0.0


def make_strip(dock: QDockWidget) -> None:
    """Keep ``dock`` (the timeline) as tall as its widgets need, no taller."""
    widget = dock.widget()
    widget.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Fixed)
    widget.setMaximumHeight(widget.sizeHint().height())


def tab_when_shown(window: QMainWindow, docks: list[QDockWidget]) -> None:
    """Whenever one of ``docks`` is shown while another is, put it in the other's tabs and
    in front. Tabbing is done at show time: tabbing hidden docks before the window is shown
    leaves stray tab bars behind in Qt's layout.

    "Shown" is the dock's show event, not its ``visibilityChanged``: Qt sends that one too
    when a tab is brought to front or the tab in front is hidden, and tabbing the dock then
    (inside Qt's own tab switch) moved docks a user had put apart and crashed Qt."""
    TabWhenShown(window, docks)


class TabWhenShown(QObject):
    """The event filter of :func:`tab_when_shown` (owned by the window): a dock shown by the
    app or the user is placed; the docks shown with the window (a restored layout) or again
    with it after it was minimised (a spontaneous show) keep their restored tab in front."""

    def __init__(self, window: QMainWindow, docks: list[QDockWidget]) -> None:
        super().__init__(window)
        self.window, self.docks = window, list(docks)
        self.window_shown = window.isVisible()  # the docks' show events come before the window's own
        window.installEventFilter(self)
        for dock in self.docks:
            dock.installEventFilter(self)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if event.type() == QEvent.Type.Show and not event.spontaneous():
            if watched is self.window:
                self.window_shown = True
            elif any(watched is d for d in self.docks):
                self.place(watched)
        return False

    def place(self, dock: QDockWidget) -> None:
        """A tab of the first other dock shown, in front; else the area at a usable height."""
        if dock.isFloating():
            return
        others = [d for d in self.docks if d is not dock and d.isVisible() and not d.isFloating()]
        if others and dock not in self.window.tabifiedDockWidgets(others[0]):
            self.window.tabifyDockWidget(others[0], dock)
            dock.raise_()
            # a dock shown beside the others before it is tabbed squeezes the area to its
            # size hint (the Error dock took the Curves' 240 pixels down to 175): the tabs are
            # laid out at once, and the area given its usable height again
            self.window.layout().activate()
            self.usable_height(dock)
        elif others and self.window_shown:
            dock.raise_()  # shown again among its old tabs: in front too
        elif not others and dock.height() < BOTTOM_HEIGHT:  # the first: the area opens at a usable height
            self.window.resizeDocks([dock], [BOTTOM_HEIGHT], Qt.Orientation.Vertical)

    def usable_height(self, dock: QDockWidget) -> None:
        """The tabs holding ``dock`` (with their tab bar) at least :data:`BOTTOM_HEIGHT` high,
        in the bottom area (the side column's docks keep the column's split)."""
        bottom = self.window.dockWidgetArea(dock) == Qt.DockWidgetArea.BottomDockWidgetArea
        if bottom and dock.isVisible() and not dock.isFloating() and dock.height() < BOTTOM_HEIGHT:
            self.window.resizeDocks([dock], [BOTTOM_HEIGHT], Qt.Orientation.Vertical)


def fit_docks(window: QMainWindow, view, side: list[QDockWidget], bottom: list[QDockWidget]) -> None:
    """Keep the view its share at any window size: the side column gets :func:`side_width`
    when the view keeps :data:`VIEW_AREA_SHARE` of the area with it, else gives way (down to
    :data:`DOCK_MINIMUM`); a column a user made wider is left alone while the view keeps
    its share. Bottom docks that leave the view less than :data:`RESTORED_MINIMUM_SHARE`
    (a layout restored from a smaller screen) go back to :data:`BOTTOM_HEIGHT`."""
    low = [d for d in bottom if d.isVisible() and not d.isFloating() and d.height() > BOTTOM_HEIGHT]
    if low and view_share(window, view) < RESTORED_MINIMUM_SHARE:
        window.resizeDocks(low, [BOTTOM_HEIGHT] * len(low), Qt.Orientation.Vertical)
    docks = [d for d in side if d.isVisible() and not d.isFloating()]
    if not docks:
        return
    target = side_width(window.width())
    width = max(d.width() for d in docks)
    if view_share(window, view) < VIEW_AREA_SHARE - 0.01 and width > target:
        window.resizeDocks(docks, [target] * len(docks), Qt.Orientation.Horizontal)
    elif width < min(target, DOCK_MINIMUM * 2) - 1 and view.width() - target > VIEW_MINIMUM[0]:
        window.resizeDocks(docks, [target] * len(docks), Qt.Orientation.Horizontal)


def restore_layout(window: QMainWindow, settings: QSettings) -> bool:
    """Restore the saved dock layout if it is of this :data:`LAYOUT_VERSION`; returns whether
    it was (else the default stays). A restored layout that squeezes the view is fixed by
    :func:`fit_docks` once the window has its size."""
    saved = settings.value("window/state")
    version = settings.value("window/layout_version")
    if saved is None or str(version) != str(LAYOUT_VERSION):
        return False
    return bool(window.restoreState(saved, LAYOUT_VERSION))


def save_layout(window: QMainWindow, settings: QSettings) -> None:
    settings.setValue("window/state", window.saveState(LAYOUT_VERSION))
    settings.setValue("window/layout_version", LAYOUT_VERSION)
