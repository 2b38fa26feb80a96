"""The app's model: the state object and its signals, undoable commands calling core, the
comparison layers, playback, loading and the document's caches.

May import: Qt core and gui (signals, timers, QUndoCommand), numpy, core, and the crash
report (app.crash). Must not import: Qt widgets, PyVista, VTK, pyqtgraph, or the
app's scene, docks, dialogs, window, media and tools (ruff banned-api: app/model/ruff.toml).
"""
