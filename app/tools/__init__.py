"""Developer tools run as modules: the benches (python -m gmr_studio.app.tools.bench) and the
gallery of pictures. They may import anything in the app; nothing in the app imports them
but the gallery's helpers used by tests.
"""
