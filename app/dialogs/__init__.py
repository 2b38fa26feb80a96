"""Dialogs: marker alignment, the audit of round trips, crash recovery.

May import: Qt widgets, app.model, app.reliability, the scene's drawables (to show what the
dialog is about in the view). Must not import: PyVista, VTK, docks, window, media, tools
(ruff banned-api: app/dialogs/ruff.toml).
"""
