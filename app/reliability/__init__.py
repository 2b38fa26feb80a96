"""Not losing work: autosave of unsaved edits, recovery after a crash, the crash log.

May import: Qt core, app.model, core. Must not import: widgets, PyVista, VTK or any other app
package (ruff banned-api: app/reliability/ruff.toml); the recovery dialog is in app.dialogs.
"""
