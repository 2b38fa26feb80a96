"""Not losing work: autosave of unsaved edits and recovery after a crash (the crash log they
write to is :mod:`app.crash`, below the model, which reports through it too).

May import: Qt core, app.model, app.crash, core. Must not import: widgets, PyVista, VTK or any other app
package (ruff banned-api: app/reliability/ruff.toml); the recovery dialog is in app.dialogs.
"""
