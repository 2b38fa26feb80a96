"""Everything drawn in the 3D view: the scene and its drawables (the figure, overlays, ghosts,
onion poses, the classroom's overlay, highlights), the VTK parts they are made of, picking,
the render widget and the view widget that shows the scene.

May import: app.model, pyvista, VTK, pyvistaqt (only in render_widget), Qt for the view
widget. Must not import: app docks, dialogs, window, media, tools, reliability
(ruff banned-api: app/scene/ruff.toml).
"""
