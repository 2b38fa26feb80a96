"""The Library panel: the takes of the library's folders in a table (:mod:`.panel`), read
from the library's file a page at a time (:mod:`.table_model`), indexed in the background
(:mod:`.indexing`). The index itself is :mod:`core.library`; the window installs the panel
(:mod:`app.window.library`)."""
