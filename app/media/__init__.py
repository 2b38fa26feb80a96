"""Pictures and videos made from the scene: screenshots, the window's image, video export,
filmstrips.

May import: app.model, app.scene, Qt, PyVista. Must not import: docks, dialogs, window,
tools (ruff banned-api: app/media/ruff.toml).
"""
