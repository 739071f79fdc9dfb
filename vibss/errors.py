"""Exceptions raised by vibss.

Every exception subclasses both :class:`VibssError` (catch everything from vibss) and the
built-in it behaves like, so ``except ValueError`` keeps working for callers that do not know
about vibss.
"""

from __future__ import annotations

__all__ = ["VibssError", "ModelError", "AnalysisError", "ModelFileError", "VibssWarning"]


class VibssError(Exception):
    """Base class of every error vibss raises on purpose."""


class ModelError(ValueError, VibssError):
    """Invalid model data: the message names the entity, the key and what was wrong."""


class ModelFileError(ModelError):
    """Invalid model file: the message also names the file (and line, for syntax errors)."""


class AnalysisError(RuntimeError, VibssError):
    """An analysis cannot give a meaningful answer (e.g. a load the mounts do not restrain)."""


class VibssWarning(UserWarning):
    """A method is expected to lose accuracy or fail here; the message names the cause and the fix."""
