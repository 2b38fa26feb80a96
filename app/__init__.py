"""GMR Studio, the desktop app (PyQt6 + pyvistaqt). All math comes from :mod:`core`."""
