"""A small TOML writer for model files (the standard library reads TOML but does not write it).

It writes what :func:`vibss.io.model_to_dict` produces: top-level tables (``[model]``), arrays of
tables (``[[body]]``) and, inside them, strings, booleans, numbers, arrays and inline tables.
Floats are written with ``repr`` so that reading them back gives the same bits.

Examples
--------
>>> print(dumps_toml({"model": {"name": "a"}, "body": [{"mass": 0.1, "cog": [0, 1e-3, 2.5]}]}))
[model]
name = "a"
<BLANKLINE>
[[body]]
mass = 0.1
cog = [0, 0.001, 2.5]
<BLANKLINE>
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import VibssError

__all__ = ["dumps_toml", "toml_value"]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(key: str) -> str:
    return key if _BARE_KEY.match(key) else json.dumps(key, ensure_ascii=False)


def toml_value(value: Any) -> str:
    """One value as TOML text: number, bool, string, array or inline table.

    Examples
    --------
    >>> toml_value({"euler": [0.0, 90, float("inf")], "sequence": "ZYX"})
    '{ euler = [0.0, 90, inf], sequence = "ZYX" }'
    """
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return ("-inf" if v < 0 else "inf") if math.isinf(v) else ("nan" if math.isnan(v) else repr(v))
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # JSON escapes are valid TOML basic strings
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        if not value:
            return "{}"
        return "{ " + ", ".join(f"{_key(k)} = {toml_value(v)}" for k, v in value.items()) + " }"
    raise VibssError(f"cannot write {value!r} ({type(value).__name__}) as TOML")


def dumps_toml(data: Mapping[str, Any], header: str = "") -> str:
    """A document of top-level tables and arrays of tables as TOML text.

    Parameters
    ----------
    data : mapping
        ``{name: table}`` (written ``[name]``) or ``{name: [table, ...]}`` (``[[name]]`` each);
        plain values are written first, as top-level keys.
    header : str
        Comment put at the top (``# ...``), if any.

    Returns
    -------
    str
    """
    lines = [f"# {line}" for line in header.splitlines()] + ([""] if header else [])
    tables = {k: v for k, v in data.items() if isinstance(v, Mapping)
              or (isinstance(v, list) and v and all(isinstance(i, Mapping) for i in v))}
    for k, v in data.items():
        if k not in tables:
            lines.append(f"{_key(k)} = {toml_value(v)}")
    for name, table in tables.items():
        for item in [table] if isinstance(table, Mapping) else table:
            lines.append(f"[{_key(name)}]" if isinstance(table, Mapping) else f"[[{_key(name)}]]")
            lines.extend(f"{_key(k)} = {toml_value(v)}" for k, v in item.items())
            lines.append("")
    return "\n".join(lines)
