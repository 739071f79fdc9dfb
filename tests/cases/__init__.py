"""Shared model builders and references of the tests (``pythonpath = ["tests", ...]`` makes this
package importable as ``cases``): ``models`` (the reference cases and the parametrised builders),
``small`` (closed-form systems), ``scaled`` (the badly scaled family), ``mp_reference`` (60-digit
mpmath references), ``reference_impl`` (loop-by-loop assembly), ``fuzzing`` (random models and
mutated files)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
"""The repository's root (``docs/``, ``examples/``, ``benchmarks/``), whatever the test file's depth."""
