"""Solves: the exact frequency-domain solve, its back-ends, banded and certified paths."""
