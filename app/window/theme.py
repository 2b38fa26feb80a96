"""The app's icon and style sheet, from ``resources/icons`` and ``resources/styles``."""

from __future__ import annotations

from PyQt6.QtGui import QIcon
from PyQt6.QtWidgets import QApplication

from gmr_studio.resources import resource_path

RESOURCES = resource_path()
ICON = RESOURCES / "icons" / "gmr-studio.svg"
STYLE = RESOURCES / "styles" / "studio.qss"


def apply_theme(app: QApplication) -> None:
    """Set the window icon and the style sheet (quietly skipped if a file is missing)."""
    if ICON.exists():
        app.setWindowIcon(QIcon(str(ICON)))
    if STYLE.exists():
        app.setStyleSheet(STYLE.read_text(encoding="utf-8"))
