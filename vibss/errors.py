"""Exceptions raised by vibss.

Every exception subclasses both :class:`VibssError` (catch everything from vibss) and the
built-in it behaves like, so ``except ValueError`` keeps working for callers that do not know
about vibss.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from typing import Any

__all__ = ["VibssError", "ModelError", "AnalysisError", "DefectiveModesError", "ModelFileError",
           "VibssWarning", "did_you_mean"]


class VibssError(Exception):
    """Base class of every error vibss raises on purpose."""


class ModelError(ValueError, VibssError):
    """Invalid model data: the message names the entity, the key and what was wrong."""


class ModelFileError(ModelError):
    """Invalid model file: the message also names the file (and line, for syntax errors)."""


class AnalysisError(RuntimeError, VibssError):
    """An analysis cannot give a meaningful answer (e.g. a load the mounts do not restrain)."""


class DefectiveModesError(AnalysisError):
    """Complex modes refused: the eigenvectors are nearly dependent (critically damped or defective
    modes), so a modal sum would lose accuracy. ``method="auto"`` then uses a direct method."""


class VibssWarning(UserWarning):
    """A method is expected to lose accuracy or fail here; the message names the cause and the fix."""


def did_you_mean(name: Any, options: Iterable[Any]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``options`` to ``name``, or an empty string.

    Examples
    --------
    >>> did_you_mean("engin", ["engine", "frame"])
    " (did you mean 'engine'?)"
    """
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""
