"""The report's interactive 3-D mode viewer: the model's geometry and mode shapes as JSON, drawn by a
small inline script (``viewer.js``, plain JavaScript on a ``<canvas>``, no network, no library).

The geometry is the one the 2-D drawings use (:class:`vibss.plotting._scene.Scene`): one box per
body (the uniform box with the body's mass and principal moments, grown to the mount layout where
that box is much smaller), the mount points and the fixed end of each ground spring. Each mode's
body motion is scaled so that the largest displacement of any drawn point is
:data:`MOTION_FRACTION` of the model's size; the page animates it sinusoidally.

Examples
--------
>>> import vibss
>>> from vibss.report.viewer import viewer_data
>>> t = vibss.MountType("t", [1e4, 2e4, 3e4])
>>> m = vibss.Model([vibss.Body("b", 1000.0, [10, 20, 30])],
...                 vibss.symmetric(vibss.Mount("m", t, "b", at=[1, 2, 0])))
>>> d = viewer_data(vibss.modes(m))
>>> len(d["modes"]), len(d["bodies"]), len(d["mounts"])
(6, 1, 4)
"""

from __future__ import annotations

import html
import json
from importlib import resources
from typing import Any

import numpy as np

from ..modal.result import Modes
from ..model.model import GROUND

__all__ = ["viewer_data", "viewer_html", "ERROR_HOOK", "VIEWER_CSS", "MOTION_FRACTION", "MAX_VIEWER_MODES"]

MOTION_FRACTION = 0.10
"""Largest drawn displacement of a mode as a fraction of the model's size [-]."""

MAX_VIEWER_MODES = 60
"""The viewer carries at most this many modes (the lowest) and says so; the tables list them all."""

ERROR_HOOK = """<script>
window.vibssErrors = [];
(function () {
  function note(msg) { window.vibssErrors.push(String(msg));
    document.documentElement.setAttribute("data-errors", window.vibssErrors.join(" | ")); }
  window.addEventListener("error", function (e) { note(e.message || e); });
  var err = console.error;
  console.error = function () { note(Array.prototype.join.call(arguments, " ")); err.apply(console, arguments); };
})();
</script>"""
"""A script for the page's head: records uncaught errors and ``console.error`` calls into the
``data-errors`` attribute of ``<html>`` (read by the browser test from the dumped DOM)."""


def _round(a: Any, digits: int = 6) -> Any:
    """Nested lists of floats with ``digits`` significant digits (a compact JSON)."""
    arr = np.asarray(a, float)
    return [float(f"{v:.{digits}g}") for v in arr] if arr.ndim == 1 else [_round(r, digits) for r in arr]


def viewer_data(modes: Modes, fraction: float = MOTION_FRACTION,
                max_modes: int = MAX_VIEWER_MODES) -> dict[str, Any]:
    """The viewer's JSON data: geometry [m] and each mode's scaled body motion.

    Parameters
    ----------
    modes : Modes
        Undamped modes of a model (:func:`vibss.modes`).
    fraction : float
        Largest displacement of any drawn point in each mode, as a fraction of the model's size [-].
    max_modes : int
        Carry the lowest this many modes at most.

    Returns
    -------
    dict
        ``size`` (the model's size [m]), ``center`` (3,) [m]; ``bodies``: ``name``, ``cog`` (3,) [m],
        ``corners`` (8, 3) [m]; ``mounts``: ``name``, ``point`` (3,) [m], ``body`` (index), ``to``
        (index, -1 for ground), ``anchor`` (3,) [m] (the fixed end of a ground spring);
        ``modes``: ``n`` (1-based), ``hz`` [Hz], ``label``, ``q`` (nb, 6) body motion [m, rad]
        at the drawn amplitude; ``total``: the number of modes of ``modes``.

    Raises
    ------
    ImportError
        Without matplotlib (the geometry lives in :mod:`vibss.plotting`).
    """
    from ..plotting._scene import Scene     # vibss.plotting needs matplotlib, an optional dependency

    model = modes.model
    scene = Scene.of(model)
    names = model.body_names
    nb = len(names)
    lo = np.vstack([scene.corners.reshape(-1, 3), scene.anchors, scene.mount_points]).min(axis=0)
    hi = np.vstack([scene.corners.reshape(-1, 3), scene.anchors, scene.mount_points]).max(axis=0)
    out_modes = []
    for k in range(min(len(modes), max_modes)):
        q = np.asarray(modes.shapes[:6 * nb, k], float)
        worst = scene.max_displacement(q)
        scale = fraction * scene.size / worst if worst > 0 else 0.0
        out_modes.append({"n": k + 1, "hz": float(modes.frequency_hz[k]), "label": modes.labels[k],
                          "q": _round((scale * q).reshape(nb, 6))})
    return {
        "name": model.name, "size": float(scene.size), "center": _round((lo + hi) / 2), "fraction": fraction,
        "total": len(modes),
        "bodies": [{"name": n, "cog": _round(scene.cogs[i]), "corners": _round(scene.corners[i])}
                   for i, n in enumerate(names)],
        "mounts": [{"name": m.name, "point": _round(scene.mount_points[p]), "body": names.index(m.body),
                    "to": -1 if m.to == GROUND else names.index(m.to), "anchor": _round(scene.anchors[p])}
                   for p, m in enumerate(model.mounts)],
        "modes": out_modes,
    }


def viewer_html(modes: Modes) -> str:
    """The viewer as an HTML fragment: a canvas, a mode list and the inline script with its data.

    Parameters
    ----------
    modes : Modes
        Undamped modes of a model.

    Returns
    -------
    str
        ``<div class="viewer">...</div>`` with everything inline (no network access); empty
        without matplotlib (see :func:`viewer_data`).
    """
    try:
        data = viewer_data(modes)
    except ImportError:
        return ""
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    script = resources.files("vibss.report").joinpath("viewer.js").read_text(encoding="utf-8")
    title = html.escape(f"3-D mode viewer: {modes.model.name}")
    return (f'<div class="viewer" id="modes-viewer" aria-label="{title}">\n'
            '<div class="viewer-bar"><label>Mode <select id="viewer-mode"></select></label> '
            '<button type="button" id="viewer-play">pause</button> '
            '<span class="viewer-help">drag to rotate, wheel to zoom, double-click to reset</span></div>\n'
            '<canvas id="viewer-canvas" width="900" height="560"></canvas>\n'
            f'<script type="application/json" id="viewer-data">{payload}</script>\n'
            f"<script>\n{script}</script>\n</div>")


VIEWER_CSS = """
.viewer { margin: 1em 0; border: 1px solid #ccc; display: inline-block; }
.viewer-bar { padding: 0.4em; background: #eef3f8; font-size: 0.9em; }
.viewer-help { color: #666; margin-left: 1em; } #viewer-canvas { display: block; cursor: grab; }
"""
"""Style of the viewer (added to the page's CSS)."""
