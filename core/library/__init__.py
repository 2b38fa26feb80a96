"""The motion library: every take of some folders in one SQLite file, to find, see and judge.

- :mod:`.schema`: the file, its tables and version (:func:`~.schema.open_library`);
- :mod:`.scan`: which files are new, changed, unchanged or gone;
- :mod:`.reading`: one file read, checked and drawn (what a worker process runs);
- :mod:`.index`: :class:`~.index.Library`, writing rows and indexing folders in parallel;
- :mod:`.query`: filters, sorting, rows as JSON and CSV;
- :mod:`.skeletons`: skeleton signatures, near matches, groups;
- :mod:`.thumbnails` and :mod:`.drawing`: the thumbnail, drawn as the view draws a figure.

``gmr library`` (:mod:`core.cli.library`) and the app's Library panel (:mod:`app.library`)
use these; docs/library.md says what every column means.
"""
