"""Signal names as python-control spells them: vibss writes ``engine.z``, python-control ``engine:z``.

At the bottom of the layers: results, state spaces and controllers all name their signals with it.
"""

from __future__ import annotations

__all__ = ["control_name"]


def control_name(name: str) -> str:
    """The python-control spelling of a vibss signal name (``.`` -> ``:``).

    Examples
    --------
    >>> control_name("mount.front.xz.f3")
    'mount:front:xz:f3'
    """
    return name.replace(".", ":")
