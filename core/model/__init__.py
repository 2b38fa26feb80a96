"""The motion model: the skeleton forest and its per-frame arrays (:mod:`.motion`), and a
file's own rotation channels (:mod:`.channels`)."""
