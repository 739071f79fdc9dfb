"""Mount identification, measured: ``fit_rheology`` on data from each law, clean and with noise.

Data: 40 log-spaced frequencies from 1 Hz to 10 kHz of a Zener (k_0 1e5, k_inf 3e5 N/m, tau 1 ms),
a fractional Zener (1e5, 5e5 N/m, 2 ms, alpha 0.4) and a 3-term Prony law, on one axis; seeded
complex noise of relative size 0, 0.1 % and 1 %. For each, its own law fitted: the time, the RMS log
error, and the largest relative error of the parameters (the Prony law: the fit error only).
The stock path in the same run: a ``table`` rheology of the same data (PCHIP of k' and eta, the
Maxwell ladder vibss fits by NNLS on fixed relaxation times), its ladder's largest error against
the clean law over the band.

Run: ``python benchmarks/bench_fit.py``; results in ``benchmarks/results/fit.json``.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.machine import machine, timed  # noqa: E402
from vibss import MountType, fit_rheology  # noqa: E402
from vibss.model.rheology import FractionalZener, Prony, Zener  # noqa: E402

F = np.geomspace(1.0, 1e4, 40)
LAWS = {"zener": (Zener(1e5, 3e5, 1e-3), ("k_0", "k_inf", "tau")),
        "fractional": (FractionalZener(1e5, 5e5, 2e-3, 0.4), ("k_0", "k_inf", "tau", "alpha")),
        "prony": (Prony(1e5, [5e4, 1e5, 2e5], [1e-1, 3e-3, 1e-4]), ())}


def bench(quick: bool) -> dict:
    """One size: three laws by three noise levels."""
    rng = np.random.default_rng(32)
    rows: dict = {}
    for kind, (law, keys) in LAWS.items():
        clean = law.dynamic_stiffness(2 * np.pi * F)[:, 0]
        for noise in (0.0, 1e-3, 1e-2):
            data = clean * (1 + noise * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / np.sqrt(2))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                t, fit = timed(lambda: fit_rheology(F, data, kind, order=3 if kind == "prony" else None))
                table = MountType("t", rheology={"type": "table", "frequency": F.tolist(),
                                                 "stiffness": data.real.tolist(),
                                                 "loss_factor": (data.imag / data.real).tolist()})
            lad = table.ladder.stiffness(2 * np.pi * F)[:, 0]
            par = max((float(np.max(np.abs(getattr(fit.rheology, k) / getattr(law, k) - 1))) for k in keys),
                      default=float("nan"))
            rows[f"{kind}, noise {noise:g}"] = {"fit_s": t, "rms_log_error": float(fit.rms_error[0]),
                         "parameter_error": par, "evaluations": fit.evaluations,
                         "table_ladder_error": float(np.max(np.abs(lad / clean - 1)))}
    return {**rows, "frequencies": F.size, "machine": machine()}


if __name__ == "__main__":
    from run_all import main_one
    main_one("fit")
