"""Where a loss factor cannot follow: the time domain and the damped modes say so, by mount.

A constant loss factor ``eta`` (complex stiffness ``k (1 + i eta)``, :class:`vibss.MountType`) is
a frequency-domain idealisation: it has no causal time-domain counterpart (its impulse response
is non-causal), so the time response, the python-control system and the damped modes leave it
out. Silently doing so would give one mount two physics (damped in an FRF, ringing undamped in a
transient); :func:`dropped_hysteresis` makes it explicit: a :class:`~vibss.errors.VibssWarning`
naming the mounts and a sentence for the result's ``note``.

Examples
--------
>>> import warnings
>>> from ... import Body, Model, Mount, MountType
>>> m = Model([Body("b", 1.0, [1, 1, 1])], [Mount("m", MountType("t", [1e4] * 3, loss_factor=0.1), "b")])
>>> hysteretic_mounts(m)
('m',)
>>> with warnings.catch_warnings(record=True) as w:
...     warnings.simplefilter("always")
...     note = dropped_hysteresis(m, "simulate")
>>> note.startswith("loss factor of mount(s) ['m'] left out")
True
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ...errors import VibssWarning
from ...model.model import Model
from .memo import remembered

__all__ = ["hysteretic_mounts", "dropped_hysteresis"]


def hysteretic_mounts(model: Model) -> tuple[str, ...]:
    """Names of the mounts of ``model`` whose type has a nonzero loss factor.

    Parameters
    ----------
    model : Model

    Returns
    -------
    tuple of str
        In the model's order.
    """
    return remembered(model, "hysteretic mounts", lambda: tuple(
        m.name for m in model.mounts if np.any(np.asarray(m.type.loss_factor) * m.type.stiffness)))


def _plant_has_hysteresis(plant: Any) -> bool:
    parts = [getattr(plant, key, None) for key in ("H", "Hz", "Oh", "Ph")]
    return any(p is not None and (p.count_nonzero() if hasattr(p, "count_nonzero") and not isinstance(p, np.ndarray)
                                  else np.any(p)) for p in parts)


def dropped_hysteresis(source: Any, where: str, stacklevel: int = 3) -> str:
    """Warn that the loss factors of ``source`` are left out of an analysis; the note to record.

    Parameters
    ----------
    source : Model, Assembly or Plant
        What the analysis works on; a Model (or an Assembly, through its model) names the mounts,
        a Plant only says it has hysteretic stiffness.
    where : str
        The analysis (``"simulate"``, ``"statespace"``, ``"damped_modes"``), for the message.
    stacklevel : int
        Passed to :func:`warnings.warn` (3: the caller of the analysis).

    Returns
    -------
    str
        ``""`` when nothing is left out, else the sentence for the result's ``note``.
    """
    model = source if isinstance(source, Model) else getattr(source, "model", None)
    if isinstance(model, Model):
        names = hysteretic_mounts(model)
        if not names:
            return ""
        what = f"mount(s) {list(names)}"
    elif _plant_has_hysteresis(source):
        what = "the plant's hysteretic stiffness H"
    else:
        return ""
    note = (f"loss factor of {what} left out (a constant loss factor has no causal time-domain form; "
            "it adds no damping here)")
    warnings.warn(f"{where}: {note}; it is used by frequency responses only. For the same damping in "
                  "every analysis use its causal approximation: vibss.causal_loss(model) (a Maxwell "
                  "ladder fitted over the frequency band, the fit error stated; simulate(..., "
                  "hysteresis='causal') does it for you), or give viscous damping (c = eta k / w at the "
                  "frequency of interest)", VibssWarning,
                  stacklevel=stacklevel)
    return note
