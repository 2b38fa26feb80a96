"""Many files at once: finding the motion files of a folder tree (:mod:`.files`) and running
one task per file on local processes or a Dask cluster (:mod:`.workers`), for batch
conversion, checks, ``gmr dataset`` and the motion library."""
