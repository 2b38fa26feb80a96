"""The composition root: the main window makes the state, the view, every dock, menu, dialog
and drawable, lays them out (layout) and wires them; files, actions, the classroom, the
comparison and the onion menu are parts of that assembly. Nothing else assembles the window.

May import every other app package; none of them imports it (their ruff.toml files ban it).
"""
