"""python-control's ``interconnect`` and ``feedback`` with vibss signal names in and out.

python-control reserves ``.`` (``system.signal``), so vibss systems carry ``engine:z``; these wrappers
accept either spelling (``engine.z`` too) wherever a signal is named and return a
:class:`~vibss.linear.statespace.NamedStateSpace`, whose signals keep their names.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..linear.plant.names import control_name
from ..linear.statespace import NamedStateSpace

__all__ = ["interconnect", "feedback"]


def _named(sys: Any, name: str | None = None) -> NamedStateSpace:
    return NamedStateSpace(sys.A, sys.B, sys.C, sys.D, sys.dt, inputs=sys.input_labels,
                           outputs=sys.output_labels, states=sys.state_labels, name=name or sys.name)


def _spell(item: Any, labels: set[str], systems: set[str]) -> Any:
    """One signal spec in python-control's spelling (lists, tuples and signs kept)."""
    if isinstance(item, (list, tuple)):
        return type(item)(_spell(x, labels, systems) for x in item)
    if not isinstance(item, str):
        return item
    sign, body = ("-", item[1:]) if item.startswith("-") else ("", item)
    if control_name(body) in labels:
        return sign + control_name(body)
    head, _, rest = body.partition(".")
    if head in systems and control_name(rest) in labels:
        return f"{sign}{head}.{control_name(rest)}"
    return item


def interconnect(syslist: Sequence[Any], connections: Any = None, inplist: Any = None, outlist: Any = None,
                 *, inputs: Any = None, outputs: Any = None, name: str | None = None, **kwargs: Any) -> NamedStateSpace:
    """``control.interconnect`` accepting vibss signal names (``table.z.acc``) anywhere a signal is named.

    Parameters
    ----------
    syslist : sequence of StateSpace
        The systems (vibss plants and controllers, or any python-control systems).
    connections, inplist, outlist, inputs, outputs, **kwargs
        As ``control.interconnect``; signal names in either spelling.
    name : str or None
        Name of the result.

    Returns
    -------
    NamedStateSpace
    """
    import control

    labels = {lab for s in syslist for lab in [*s.input_labels, *s.output_labels]}
    systems = {s.name for s in syslist}
    args = {key: _spell(val, labels, systems) for key, val in
            (("connections", connections), ("inplist", inplist), ("outlist", outlist),
             ("inputs", inputs), ("outputs", outputs)) if val is not None}
    if isinstance(args.get("inputs"), str):
        args["inputs"] = [args["inputs"]]
    if isinstance(args.get("outputs"), str):
        args["outputs"] = [args["outputs"]]
    out = control.interconnect(list(syslist), **args, **kwargs)
    return _named(out, name)


def feedback(sys1: Any, sys2: Any = 1, sign: float = -1) -> NamedStateSpace:
    """``control.feedback`` keeping ``sys1``'s signal names; ``sys2``'s signals are matched to
    ``sys1``'s by name when they carry names (either spelling), by position otherwise.

    Parameters
    ----------
    sys1 : StateSpace
        Forward path.
    sys2 : StateSpace or float
        Feedback path.
    sign : float
        -1 for negative feedback (default), +1 for positive.
    """
    import control

    if not isinstance(sys1, NamedStateSpace):
        sys1 = _named(control.ss(sys1))
    return sys1.feedback(sys2, sign)
