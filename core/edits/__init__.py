"""Edits of a motion: the GMR operations (:mod:`.operations`), dummy joints, clip edits over time, mirror."""
