"""A shock response spectrum against a specification envelope (a test tolerance band, or an allowable).

A specification is a table of (frequency [Hz], level) points, log-log interpolated as shock specs are
written (MIL-STD-810, NASA-STD-7003); the check gives, at every frequency of the spectrum inside the
spec's band, the level, the margin in dB (``20 log10(SRS / spec)``) and whether it lies inside
``[lower_db, upper_db]`` (a test's tolerance band, e.g. -3/+6 dB; ``lower_db = -inf`` for an
allowable that must not be exceeded).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as v
from ..errors import ArgumentError
from ..results import Result, TextTable

__all__ = ["EnvelopeCheck", "check_envelope", "spec_level"]


def spec_level(frequency_hz: Any, level: Any, f: Any) -> np.ndarray:
    """Log-log interpolation of a specification at ``f`` [Hz] (NaN outside its band)."""
    fp = np.asarray(frequency_hz, dtype=float)
    lp = np.asarray(level, dtype=float)
    x = np.asarray(f, dtype=float)
    out = np.full(x.shape, np.nan)
    inside = (x >= fp[0]) & (x <= fp[-1])
    out[inside] = np.exp(np.interp(np.log(x[inside]), np.log(fp), np.log(lp)))
    return out


@dataclass(frozen=True, eq=False)
class EnvelopeCheck(Result):
    """An SRS against a specification: margin [dB] and pass/fail at every spectrum frequency.

    Attributes
    ----------
    frequency_hz, srs, spec, margin_db : (n,) ndarray
        Frequencies inside the spec's band, the spectrum, the spec and ``20 log10(srs / spec)``.
    lower_db, upper_db : float
        The tolerance band.
    """

    frequency_hz: np.ndarray
    srs: np.ndarray
    spec: np.ndarray
    margin_db: np.ndarray
    lower_db: float
    upper_db: float
    name: str = "envelope check"

    @property
    def passed(self) -> bool:
        """Every frequency inside the band."""
        return bool(np.all((self.margin_db >= self.lower_db) & (self.margin_db <= self.upper_db)))

    @property
    def output_labels(self) -> tuple[str, ...]:
        """One output: the margin."""
        return ("margin_db",)

    def _item(self, i: int, j: int | None) -> np.ndarray:
        return self.margin_db

    def summary(self) -> TextTable:
        """Worst margins and the verdict."""
        lo, hi = int(np.argmin(self.margin_db)), int(np.argmax(self.margin_db))
        rows = [["verdict", "PASS" if self.passed else "FAIL"],
                ["band", f"{self.lower_db:+g} / {self.upper_db:+g} dB"],
                ["lowest margin", f"{self.margin_db[lo]:+.2f} dB at {self.frequency_hz[lo]:.4g} Hz"],
                ["highest margin", f"{self.margin_db[hi]:+.2f} dB at {self.frequency_hz[hi]:.4g} Hz"],
                ["frequencies outside", str(int(np.sum((self.margin_db < self.lower_db) | (self.margin_db > self.upper_db))))]]
        return TextTable(["check", "result"], rows, title=self.name)

    def report(self) -> str:
        """The summary and every frequency."""
        lines = [str(self.summary()), "", f"{'f [Hz]':>10} {'SRS':>12} {'spec':>12} {'margin [dB]':>12}"]
        lines += [f"{f:10.4g} {s:12.5g} {p:12.5g} {m:+12.2f}{'' if self.lower_db <= m <= self.upper_db else '  outside'}"
                  for f, s, p, m in zip(self.frequency_hz, self.srs, self.spec, self.margin_db)]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data."""
        return {"passed": self.passed, "lower_db": self.lower_db, "upper_db": self.upper_db,
                "frequency_hz": self.frequency_hz.tolist(), "srs": self.srs.tolist(), "spec": self.spec.tolist(),
                "margin_db": self.margin_db.tolist()}


def check_envelope(result: Any, frequency_hz: Any, level: Any, lower_db: float = -3.0,
                   upper_db: float = 6.0) -> EnvelopeCheck:
    """Compare a :class:`~vibss.shock.srs.ShockResponseSpectrum` with a specification.

    Parameters
    ----------
    result : ShockResponseSpectrum
        The spectrum (same unit as ``level``).
    frequency_hz, level : (k,) array_like
        The spec's breakpoints [Hz] (increasing) and levels (> 0).
    lower_db, upper_db : float
        Tolerance band [dB] (``-inf`` / ``inf`` for one-sided checks).

    Returns
    -------
    EnvelopeCheck
        Over the spectrum's frequencies inside the spec's band.

    Examples
    --------
    >>> import numpy as np
    >>> from vibss.shock import srs
    >>> t = np.arange(0, 0.05, 1e-5)
    >>> r = srs(t, np.where(t < 0.011, 30 * np.sin(np.pi * t / 0.011), 0.0), [50, 100, 200, 400])
    >>> check_envelope(r, [10, 1000], [60, 60], lower_db=-np.inf, upper_db=0.0).passed   # below 2 x 30
    True
    """
    fp = v.array(frequency_hz, "frequency_hz", (None,), who="check_envelope")
    lp = v.array(level, "level", (fp.size,), who="check_envelope")
    if fp.size < 2 or np.any(np.diff(fp) <= 0) or np.any(fp <= 0) or np.any(lp <= 0):
        raise ArgumentError("check_envelope: the spec needs >= 2 increasing frequencies > 0 [Hz] and levels > 0",
                            argument="frequency_hz", received=fp.tolist())
    if not lower_db < upper_db:
        raise ArgumentError(f"check_envelope: need lower_db < upper_db, got {lower_db}, {upper_db}",
                            argument="lower_db", received=lower_db)
    f = np.asarray(result.frequency_hz, dtype=float)
    spec = spec_level(fp, lp, f)
    keep = np.isfinite(spec)
    if not np.any(keep):
        raise ArgumentError(f"check_envelope: no spectrum frequency lies in the spec's band {fp[0]:g} .. {fp[-1]:g} Hz",
                            argument="frequency_hz", received=fp.tolist())
    s = np.abs(np.asarray(result.response, dtype=float))[keep]
    with np.errstate(divide="ignore"):
        margin = 20 * np.log10(s / spec[keep])
    return EnvelopeCheck(f[keep], s, spec[keep], margin, float(lower_db), float(upper_db))
