"""Hostile-input testing of every reader: mutations, targets, and a bounded runner.

``gmr fuzz`` runs it; ``tests/test_fuzz.py`` runs a fast subset.
"""
