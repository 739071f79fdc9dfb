"""What a small model's analyses derive from it, kept for the next call on the same model.

A notebook, a controller design or a parameter loop asks the same small model again and again
(``modes(model)``, ``frequency_response(model, ...)``, ``simulate(model, ...)``); the assembly, the
plant of a set of signals and what is cached on them (the stiffness factor, the modal basis, the
factorisations) depend only on the model, which is frozen (its arrays are read-only), so they are
computed once. The memo holds the last :data:`MODELS` models of at most :data:`SMALL_DOFS` DOFs
(a few kilobytes each), keyed by identity: an equal but distinct model is assembled again, and a
large model is never kept alive by it.

Everything kept is itself read-only (an :class:`~vibss.linear.plant.assemble.Assembly` and a
:class:`~vibss.linear.plant.plant.Plant` freeze their arrays in place), so a later call cannot see a
change made through a handle the first one returned.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any

__all__ = ["remembered", "forget", "SMALL_DOFS", "MODELS"]

SMALL_DOFS = 150
"""Models with at most this many DOFs (25 bodies) are remembered."""

MODELS = 8
"""How many models are remembered (least recently used dropped first)."""

PER_MODEL = 32
"""How many derived objects (assemblies, plants of different signals) are kept per model."""

_LOCK = threading.Lock()
_MEMO: OrderedDict[int, tuple[Any, OrderedDict[Hashable, Any]]] = OrderedDict()


def remembered(model: Any, key: Hashable, make: Callable[[], Any]) -> Any:
    """``make()`` for ``model`` and ``key``, computed once while the model is remembered.

    Parameters
    ----------
    model : Model
        The frozen model everything ``make`` returns is derived from; models of more than
        :data:`SMALL_DOFS` DOFs are not remembered (``make()`` is called each time).
    key : hashable
        What is derived (e.g. ``("assembly", False)``); an unhashable key is not remembered.
    make : callable
        Computes it; it must return a read-only object that depends on nothing but ``model`` and
        ``key``.
    """
    if 6 * len(model.bodies) > SMALL_DOFS:
        return make()
    try:
        hash(key)
    except TypeError:
        return make()
    with _LOCK:
        entry = _MEMO.get(id(model))
        if entry is not None and entry[0] is model:
            _MEMO.move_to_end(id(model))
            if key in entry[1]:
                entry[1].move_to_end(key)
                return entry[1][key]
    value = make()              # outside the lock: make() may ask the memo itself
    with _LOCK:
        entry = _MEMO.get(id(model))
        if entry is None or entry[0] is not model:
            entry = (model, OrderedDict())
            _MEMO[id(model)] = entry      # the model is held, so its id cannot be reused meanwhile
        _MEMO.move_to_end(id(model))
        entry[1][key] = value
        while len(entry[1]) > PER_MODEL:
            entry[1].popitem(last=False)
        while len(_MEMO) > MODELS:
            _MEMO.popitem(last=False)
    return value


def forget() -> None:
    """Drop every remembered model (tests; freeing memory)."""
    with _LOCK:
        _MEMO.clear()
