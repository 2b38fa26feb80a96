"""The window's docks: forest, inspector, timeline, curves, foot contacts, error plot,
layers, teaching panel; each follows the state and edits only through app.model
(frame changes reach a dock only while it is seen: frame_follow).

May import: Qt widgets, pyqtgraph, app.model, core. Must not import: PyVista, VTK, the
scene, dialogs, window, media, tools (ruff banned-api: app/docks/ruff.toml).
"""
