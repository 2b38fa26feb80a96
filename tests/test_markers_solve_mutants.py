"""Blind spots of the solver (core/markers/solve.py) that its mutation run found."""

from __future__ import annotations
