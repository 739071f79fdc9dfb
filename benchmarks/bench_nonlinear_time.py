"""Nonlinear time response: a shock into snubbers at 600 DOF, ``simulate`` against ``solve_ivp`` of the full
first-order state, both against an event-driven reference, in one run.

Model: ``chain_model(100, zeta=0.01)`` (600 DOF); 8 of its ground mounts get a snubber on their local z
axis (stop rate 10 times the mount's z rate, clearance half the mount's linear peak z deflection under
the shock, so that every snubber engages). Input: a 30 g, 11 ms half-sine ground acceleration in z.
Record 0 .. 0.05 s every 0.1 ms; the figure of merit is the peak z deflection of the 8 snubbered mounts
(between the samples too).

- **reference**: ``solve_ivp(DOP853, rtol=1e-11)`` of the full first-order state ``[q, q']`` with the stop
  forces, restarted at every clearance crossing (terminal events, the regime carried) and at the pulse's
  end; its peaks from its dense output on a 1 us grid (and its own events).
- **vibss**: ``simulate(..., rtol=...)`` (``auto``: ``nonlinear_modal``, rerun with shorter steps until its
  step-doubling check passes), cold: the model is built into a plant, eigen-solved and integrated in the
  call; ``bound`` is the check's estimate.
- **solve_ivp**: the same first-order system as the reference (DOP853 and Radau with the dense Jacobian,
  events and restarts as the reference) at looser tolerances: the speed-accuracy table.
- **stop stiffness**: a 10 kg mass on 1e4 N/m with a 1 mm stop under a 300 N, 20 ms half-sine, stop rate
  1e5 .. 1e9 N/m: vibss's internal step, steps and error against the event-driven DOP853 at rtol 1e-12,
  beside DOP853's and Radau's function evaluations at rtol 1e-8 (stability against the stop: the explicit
  solver's steps grow as the square root of the stop rate, vibss's too, Radau's barely), and
  DOP853, Radau and LSODA at rtol 1e-8 *without* events (the stop force in the right-hand side, as a
  user would write it): their steps and peak error, where the kink inside a step costs them.

Figures (full run): ``docs/figures/nonlinear_shock_pareto.png`` (peak error against CPU time per solver
and tolerance, DOP853/LSODA/Radau at several rtol) and ``docs/figures/stability_stops.png`` (work and
error against the stop rate).

``--quick``: a 20-body chain, 0.03 s, one tolerance each, no Radau. Results go to
benchmarks/results/nonlinear_time.json. Run: ``python benchmarks/bench_nonlinear_time.py [--quick]``.
"""

from __future__ import annotations

import dataclasses
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402
from vibss import Body, Model, Mount, MountType  # noqa: E402
from vibss.errors import VibssWarning  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402
from vibss.model.excitation import Excitation  # noqa: E402
from vibss.model.timefunctions import HalfSine  # noqa: E402

G0 = 9.80665
PULSE = 0.011
AMP = 30 * G0


def _model(n_bodies: int) -> tuple[Model, list[str], Excitation]:
    model = chain_model(n_bodies, "classical", 1e-2)
    ground = [i for i, m in enumerate(model.mounts) if m.to == "ground"]
    pick = ground[::max(1, len(ground) // 8)][:8]
    exc = Excitation("shock", "acceleration", "ground", HalfSine(AMP, 0.0, PULSE), dof="z")
    outs = [f"mount.{model.mounts[i].name}.d3" for i in pick]
    lin = vibss.simulate(model, [exc], outputs=outs, t_end=0.05, dt=1e-4)
    mounts = list(model.mounts)
    for j, i in enumerate(pick):
        t = mounts[i].type
        gap = 0.5 * float(np.abs(lin.outputs[j]).max())
        mounts[i] = dataclasses.replace(mounts[i], type=MountType(
            t.name + "_snub", t.stiffness, damping=t.damping, stops={"z": (gap, 10 * float(t.stiffness[2]))}))
    return dataclasses.replace(model, mounts=tuple(mounts)), outs, exc


@dataclasses.dataclass
class _FirstOrder:
    """The full first-order state ``[q, q']`` of the linear part plus the stop forces (the reference's
    and the stock solver's system)."""

    Minv: np.ndarray
    K: np.ndarray
    C: np.ndarray
    kz: np.ndarray
    cz: np.ndarray
    R: np.ndarray       # (r, n) local z deflections
    Rz: np.ndarray      # (r,) per ground displacement
    ks: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    @classmethod
    def of(cls, model: Model, outs: list[str]) -> _FirstOrder:
        lin = dataclasses.replace(model, mounts=tuple(dataclasses.replace(m, type=MountType(
            m.type.name, m.type.stiffness, damping=m.type.damping)) for m in model.mounts))
        p = build_plant(lin, ["ground.z.disp"], outs)
        laws = [next(m for m in model.mounts if m.name == o.split(".")[1]).type.laws[2] for o in outs]
        return cls(np.linalg.inv(np.asarray(p.M)), np.asarray(p.K), np.asarray(p.C), np.asarray(p.Kz)[:, 0],
                   np.asarray(p.Cz)[:, 0], np.asarray(p.Oq), np.asarray(p.Pz)[:, 0],
                   np.array([w.stop for w in laws]), np.array([w.clearance[0] for w in laws]),
                   np.array([w.clearance[1] for w in laws]))

    def ground(self, t: float) -> tuple[float, float]:
        """Ground displacement [m] and velocity [m/s] under the half-sine acceleration."""
        w = np.pi / PULSE
        if t < PULSE:
            return AMP / w * (t - np.sin(w * t) / w), AMP / w * (1 - np.cos(w * t))
        return AMP / w * PULSE + 2 * AMP / w * (t - PULSE), 2 * AMP / w

    def rhs(self, regime: np.ndarray) -> Any:
        n = self.K.shape[0]

        def f(t: float, x: np.ndarray) -> np.ndarray:
            z, dz = self.ground(t)
            q, v = x[:n], x[n:]
            d = self.R @ q + self.Rz * z
            g = self.ks * np.where(regime > 0, d - self.hi, np.where(regime < 0, d + self.lo, 0.0))
            return np.concatenate([v, self.Minv @ (-self.K @ q - self.C @ v - self.kz * z - self.cz * dz
                                                   - self.R.T @ g)])
        return f

    def jac(self, regime: np.ndarray) -> np.ndarray:
        n = self.K.shape[0]
        Kt = self.K + self.R.T @ ((self.ks * (regime != 0))[:, None] * self.R)
        return np.block([[np.zeros((n, n)), np.eye(n)], [-self.Minv @ Kt, -self.Minv @ self.C]])


def _event_driven(sys_: _FirstOrder, t_end: float, method: str, rtol: float) -> dict[str, Any]:
    """solve_ivp restarted at every clearance crossing (terminal events in the crossing's direction, the
    regime carried: the stop force never has a kink inside a step) and at the pulse's end."""
    n, r = sys_.K.shape[0], sys_.R.shape[0]
    x, t, regime = np.zeros(2 * n), 0.0, np.zeros(r, int)
    pieces, nfev, events = [], 0, 0
    t0 = time.perf_counter()
    for stop in (PULSE, t_end):
        while t < stop:
            fns, what = [], []
            for a in range(r):
                for side, c in ((1, sys_.hi[a]), (-1, -sys_.lo[a])):
                    if regime[a] not in (0, side):
                        continue
                    fn = (lambda tt, xx, a=a, c=c: sys_.R[a] @ xx[:n] + sys_.Rz[a] * sys_.ground(tt)[0] - c)
                    fn.terminal = True
                    fn.direction = side if regime[a] == 0 else -side
                    fns.append(fn)
                    what.append((a, side))
            J = sys_.jac(regime)            # constant within a regime (LSODA takes it as a callable only)
            kw: dict[str, Any] = ({"jac": J} if method == "Radau" else
                                  {"jac": lambda t_, x_, J=J: J} if method == "LSODA" else {})
            sol = solve_ivp(sys_.rhs(regime.copy()), (t, stop), x, method=method, rtol=rtol,
                            atol=rtol * 1e-6, dense_output=True, events=fns, **kw)
            nfev += sol.nfev
            pieces.append((t, float(sol.t[-1]), sol.sol))
            t, x = float(sol.t[-1]), sol.y[:, -1]
            if sol.status == 1:
                a, side = what[[i for i, te in enumerate(sol.t_events) if te.size][0]]
                regime[a] = side if regime[a] == 0 else 0
                events += 1
    seconds = time.perf_counter() - t0
    return {"pieces": pieces, "seconds": seconds, "nfev": nfev, "events": events}


def _local(sys_: _FirstOrder, pieces: list, ts: np.ndarray) -> np.ndarray:
    n = sys_.K.shape[0]
    out = np.zeros((sys_.R.shape[0], ts.size))
    for a, b, sol in pieces:
        sel = (ts >= a) & (ts <= b * (1 + 1e-12))
        if sel.any():
            tt = np.minimum(ts[sel], b)
            z = np.array([sys_.ground(t)[0] for t in tt])
            out[:, sel] = sys_.R @ sol(tt)[:n] + sys_.Rz[:, None] * z
    return out


def _peaks(sys_: _FirstOrder, pieces: list, t_end: float) -> np.ndarray:
    fine = np.linspace(0.0, t_end, int(round(t_end / 1e-6)) + 1)
    d = _local(sys_, pieces, fine)
    return np.maximum(np.abs(d.max(axis=1)), np.abs(d.min(axis=1)))


def _vibss_peaks(r: Any) -> np.ndarray:
    c = r.contacts
    return np.maximum(np.abs(c.peak_hi), np.abs(c.peak_lo))


def _shock(quick: bool) -> dict[str, Any]:
    n_bodies, t_end, dt = (20, 0.03, 1e-4) if quick else (100, 0.05, 1e-4)
    model, outs, exc = _model(n_bodies)
    sys_ = _FirstOrder.of(model, outs)
    ref = _event_driven(sys_, t_end, "DOP853", 1e-9 if quick else 1e-11)
    ref_peak = _peaks(sys_, ref["pieces"], t_end)
    print(f"  reference: {ref['seconds']:.1f} s", flush=True)
    ts = dt * np.arange(int(round(t_end / dt)) + 1)
    ref_out = _local(sys_, ref["pieces"], ts)
    rows = []
    for rtol in ((1e-6,) if quick else (1e-3, 1e-4, 1e-6, 1e-8)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VibssWarning)
            t0 = time.perf_counter()
            r = vibss.simulate(model, [exc], outputs=outs, t_end=t_end, dt=dt, rtol=rtol)
            sec = time.perf_counter() - t0
        peak_err = float(np.abs(_vibss_peaks(r) - ref_peak).max() / ref_peak.max())
        out_err = float(np.abs(r.outputs - ref_out).max() / np.abs(ref_out).max())
        bound = float(r.note.split("error ")[-1].split()[0])
        tries = 1 + r.note.count("check failed (")
        rows.append({"solver": "vibss nonlinear_modal", "rtol": rtol, "seconds": sec, "peak_error": peak_err,
                     "output_error": out_err, "check_bound": bound, "events": len(r.contacts.mount),
                     "tries": tries})
        print(f"  vibss rtol {rtol:.0e}: {sec:.2f} s, peak error {peak_err:.1e}", flush=True)
    for method, tols in (("DOP853", (1e-6,) if quick else (1e-3, 1e-4, 1e-6, 1e-8)),
                         ("LSODA", () if quick else (1e-4, 1e-6, 1e-8)),
                         ("Radau", () if quick else (1e-4, 1e-6))):
        for rtol in tols:
            run = _event_driven(sys_, t_end, method, rtol)
            peak = _peaks(sys_, run["pieces"], t_end)
            out = _local(sys_, run["pieces"], ts)
            rows.append({"solver": f"solve_ivp {method}", "rtol": rtol, "seconds": run["seconds"],
                         "peak_error": float(np.abs(peak - ref_peak).max() / ref_peak.max()),
                         "output_error": float(np.abs(out - ref_out).max() / np.abs(ref_out).max()),
                         "nfev": run["nfev"]})
            print(f"  {method} rtol {rtol:.0e}: {run['seconds']:.2f} s", flush=True)
    ok = [r_ for r_ in rows if r_["peak_error"] <= 1e-6 and r_["output_error"] <= 1e-6]
    ours = min((r_["seconds"] for r_ in ok if r_["solver"].startswith("vibss")), default=np.nan)
    stock = min((r_["seconds"] for r_ in ok if r_["solver"].startswith("solve_ivp")), default=np.nan)
    print(f"{6 * n_bodies} DOF, 8 snubbers, 30 g half-sine, {t_end} s every {dt} s; reference DOP853 event-driven "
          f"({ref['seconds']:.1f} s, {ref['events']} events)")
    print(f"{'solver':<24}{'rtol':>8}{'time [s]':>10}{'peak err':>10}{'out err':>10}{'bound':>10}")
    for r_ in rows:
        print(f"{r_['solver']:<24}{r_['rtol']:>8.0e}{r_['seconds']:>10.3f}{r_['peak_error']:>10.1e}"
              f"{r_['output_error']:>10.1e}{r_.get('check_bound', np.nan):>10.1e}")
    print(f"fastest within 1e-6: vibss {ours:.3f} s, solve_ivp {stock:.2f} s: {stock / ours:.1f}x")
    return {"dof": 6 * n_bodies, "t_end": t_end, "dt": dt, "reference_seconds": ref["seconds"],
            "reference_events": ref["events"], "rows": rows, "vibss_s_at_1e-6": ours, "solve_ivp_s_at_1e-6": stock,
            "speedup_at_1e-6": stock / ours}


def _stiffness(quick: bool) -> list[dict[str, Any]]:
    """Step size and work against the stop rate on a 1-DOF shock into a stop."""
    m, k, c, F0, T, t_end = 10.0, 1e4, 1e-3, 300.0, 0.02, 0.06
    rows = []
    for ks in ((1e6, 1e8) if quick else (1e5, 1e6, 1e7, 1e8, 1e9)):
        model = Model([Body("b", m, [1.0, 1.0, 1.0])],
                      [Mount("m", MountType("s", [k, k, k], stops={"z": (c, ks)}), "b", at=[0.0, 0.0, 0.0])])
        exc = Excitation("p", "force", "b", HalfSine(F0, 0.0, T), dof="z")

        def rhs(regime: int) -> Any:
            return lambda t, y: [y[1], ((F0 * np.sin(np.pi * t / T) if t < T else 0.0) - k * y[0]
                                        - (ks * (y[0] - c) if regime > 0 else ks * (y[0] + c) if regime < 0 else 0.0)) / m]

        def driven(method: str, rtol: float) -> tuple[list, int, float]:
            t, y, regime, pieces, nfev = 0.0, np.zeros(2), 0, [], 0
            t0 = time.perf_counter()
            for stop in (T, t_end):
                while t < stop:
                    fns = []
                    for side in (1, -1):
                        if regime in (0, side):
                            fn = (lambda tt, yy, side=side: yy[0] - side * c)
                            fn.terminal, fn.direction = True, side if regime == 0 else -side
                            fns.append((fn, side))
                    sol = solve_ivp(rhs(regime), (t, stop), y, method=method, rtol=rtol, atol=rtol * 1e-6,
                                    dense_output=True, events=[f for f, _ in fns])
                    nfev += sol.nfev
                    pieces.append((t, float(sol.t[-1]), sol.sol))
                    t, y = float(sol.t[-1]), sol.y[:, -1]
                    if sol.status == 1:
                        side = fns[[i for i, te in enumerate(sol.t_events) if te.size][0]][1]
                        regime = side if regime == 0 else 0
            return pieces, nfev, time.perf_counter() - t0

        def plain(method: str, rtol: float) -> tuple[float, int, int, float, float]:
            """solve_ivp as a user would write it: the stop force in the right-hand side, no events (the
            kinks inside steps), split at the pulse's end only. Peak [m], evaluations, steps, seconds,
            smallest step [s]."""
            def f(t: float, y: np.ndarray) -> list[float]:
                z = y[0]
                stop = ks * (z - c) if z > c else (ks * (z + c) if z < -c else 0.0)
                return [y[1], ((F0 * np.sin(np.pi * t / T) if t < T else 0.0) - k * z - stop) / m]

            def jac(t: float, y: np.ndarray) -> np.ndarray:
                return np.array([[0.0, 1.0], [-(k + (ks if abs(y[0]) > c else 0.0)) / m, 0.0]])

            y, peak, nfev, steps, hmin = np.zeros(2), 0.0, 0, 0, np.inf
            t0 = time.perf_counter()
            for a, b in ((0.0, T), (T, t_end)):
                kw: dict[str, Any] = {"jac": jac} if method != "DOP853" else {}
                sol = solve_ivp(f, (a, b), y, method=method, rtol=rtol, atol=rtol * 1e-6, dense_output=True, **kw)
                nfev, steps, y = nfev + sol.nfev, steps + sol.t.size - 1, sol.y[:, -1]
                hmin = min(hmin, float(np.diff(sol.t)[3:].min()))     # past the start-up steps
                peak = max(peak, float(sol.sol(np.linspace(a, b, 200001))[0].max()))
            return peak, nfev, steps, time.perf_counter() - t0, hmin

        ref, _, _ = driven("DOP853", 1e-12)
        fine = np.linspace(0, t_end, 600001)
        dense = np.zeros(fine.size)
        for a, b, sol in ref:
            sel = (fine >= a) & (fine <= b)
            dense[sel] = sol(fine[sel])[0]
        t0 = time.perf_counter()
        r = vibss.simulate(model, [exc], outputs=["b.z"], t_end=t_end, dt=1e-3)
        sec = time.perf_counter() - t0
        peak = float(r.contacts.peak_hi[0])
        h = float(r.note.split("(h = ")[-1].split(" s)")[0])
        _, n_dop, s_dop = driven("DOP853", 1e-8)
        _, n_rad, s_rad = driven("Radau", 1e-8)
        w = np.sqrt((k + ks) / m)
        row = {"stop_rate": ks, "contact_hz": w / 2 / np.pi, "vibss_step": h, "vibss_w_h": w * h,
               "vibss_steps": int(round(t_end / h)), "vibss_seconds": sec,
               "vibss_peak_error": abs(peak - dense.max()) / dense.max(),
               "dop853_nfev": n_dop, "dop853_seconds": s_dop, "radau_nfev": n_rad, "radau_seconds": s_rad}
        for method in ("DOP853", "Radau", "LSODA"):       # no events: the kinks inside the steps
            p_, n_, st_, s_, h_ = plain(method, 1e-8)
            key = f"plain_{method.lower()}"
            row.update({f"{key}_nfev": n_, f"{key}_steps": st_, f"{key}_seconds": s_, f"{key}_min_step": h_,
                        f"{key}_peak_error": abs(p_ - dense.max()) / dense.max()})
        rows.append(row)
    print(f"{'stop rate':>10}{'contact Hz':>11}{'vibss h':>10}{'w h':>7}{'vibss s':>9}{'peak err':>10}"
          f"{'DOP853 nfev':>12}{'Radau nfev':>11}")
    for r_ in rows:
        print(f"{r_['stop_rate']:>10.0e}{r_['contact_hz']:>11.4g}{r_['vibss_step']:>10.2e}{r_['vibss_w_h']:>7.3f}"
              f"{r_['vibss_seconds']:>9.3f}{r_['vibss_peak_error']:>10.1e}{r_['dop853_nfev']:>12d}{r_['radau_nfev']:>11d}")
    print("solve_ivp without events (the stop force in the right-hand side), rtol 1e-8:")
    print(f"{'stop rate':>10}" + "".join(f"{m_ + ' ' + q:>16}" for m_ in ("DOP853", "Radau", "LSODA")
                                         for q in ("steps", "peak err")))
    for r_ in rows:
        print(f"{r_['stop_rate']:>10.0e}" + "".join(
            f"{r_[f'plain_{m_}_steps']:>16d}{r_[f'plain_{m_}_peak_error']:>16.1e}" for m_ in ("dop853", "radau", "lsoda")))
    return rows


FIG = Path(__file__).resolve().parent.parent / "docs" / "figures"


def _figure_shock(shock: dict[str, Any]) -> None:
    """Speed-accuracy chart: peak-deflection error against CPU time, one line per solver (its rtols)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 6.2))
    styles = {"vibss nonlinear_modal": ("o-", "C0"), "solve_ivp DOP853": ("s-", "C1"),
              "solve_ivp LSODA": ("^-", "C2"), "solve_ivp Radau": ("D-", "C3")}
    floor = 1e-13
    for name, (style, colour) in styles.items():
        rows = [r for r in shock["rows"] if r["solver"] == name]
        if not rows:
            continue
        x = [r["seconds"] for r in rows]
        y = [max(r["peak_error"], floor) for r in rows]
        ax.loglog(x, y, style, color=colour, label=name + (" (cold: plant, modes, check)" if "vibss" in name
                                                            else " (event-driven, 1,200 states)"))
        for i, (xi, yi, r) in enumerate(zip(x, y, rows)):      # alternate sides: equal errors stay legible
            ax.annotate(f"{r['rtol']:.0e}", (xi, yi), textcoords="offset points", xytext=(6, 4 if i % 2 else -11),
                        fontsize=7, color=colour)
    ax.axhline(1e-6, color="0.5", lw=0.8, ls=":")
    ax.text(ax.get_xlim()[0] * 1.1, 1.3e-6, "1e-6 (the issue's target)", fontsize=7, color="0.4")
    ax.set_xlabel("CPU time [s] (one BLAS thread)")
    ax.set_ylabel("error of the peak mount deflection [-]\n(relative to the largest, vs event-driven DOP853 1e-11)")
    ax.set_title(f"Shock into 8 snubbers, {shock['dof']} DOF, 30 g half-sine, 0..{shock['t_end']} s "
                 "(labels: rtol)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)     # below: off the data
    fig.tight_layout()
    fig.savefig(FIG / "nonlinear_shock_pareto.png", dpi=110)
    plt.close(fig)


def _figure_stops(rows: list[dict[str, Any]]) -> None:
    """Step size, work and error against the stop rate: vibss and solve_ivp without events."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ks = np.array([r["stop_rate"] for r in rows])
    wc = np.array([2 * np.pi * r["contact_hz"] for r in rows])
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(14.0, 6.0))
    plain = (("dop853", "DOP853", "s-", "C1"), ("radau", "Radau", "D-", "C3"), ("lsoda", "LSODA", "^-", "C2"))
    a.loglog(ks, [r["vibss_step"] for r in rows], "o-", color="C0", label="vibss nonlinear_modal: its step h")
    for key, name, st, colour in plain:
        a.loglog(ks, [r[f"plain_{key}_min_step"] for r in rows], st, color=colour, label=f"{name}: smallest step")
        b.loglog(ks, [r[f"plain_{key}_steps"] for r in rows], st, color=colour, label=f"{name} without events")
        c.loglog(ks, [max(r[f"plain_{key}_peak_error"], 1e-16) for r in rows], st, color=colour,
                 label=f"{name} without events, rtol 1e-8")
    a.loglog(ks, 2 / wc, "k:", label="2 / omega_contact (explicit limit)")
    b.loglog(ks, [r["vibss_steps"] for r in rows], "o-", color="C0", label="vibss (fixed internal step)")
    b.loglog(ks, [r["dop853_nfev"] / 12 for r in rows], "s--", color="C1", label="DOP853 event-driven (nfev / 12)")
    b.loglog(ks, [r["radau_nfev"] / 4 for r in rows], "D--", color="C3", label="Radau event-driven (nfev / 4)")
    c.loglog(ks, [max(r["vibss_peak_error"], 1e-16) for r in rows], "o-", color="C0",
             label="vibss, rtol 1e-6 (contacts located)")
    a.set_ylabel("step size [s]")
    b.set_ylabel("steps over the record")
    c.set_ylabel("error of the peak deflection [-]")
    for ax in (a, b, c):
        ax.set_xlabel("stop rate [N/m] (mount 1e4 N/m)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16))     # below: off the data
    fig.suptitle("10 kg on 1e4 N/m into a 1 mm stop, 300 N 20 ms half-sine, 0..0.06 s: "
                 "step size, work and error against the stop's stiffness (solve_ivp at rtol 1e-8)", fontsize=9)
    fig.tight_layout()
    fig.savefig(FIG / "stability_stops.png", dpi=110)
    plt.close(fig)


def bench(quick: bool) -> dict:
    out = {"shock": _shock(quick), "stop_stiffness": _stiffness(quick)}
    if not quick:
        FIG.mkdir(parents=True, exist_ok=True)
        _figure_shock(out["shock"])
        _figure_stops(out["stop_stiffness"])
    return out


if __name__ == "__main__":
    from run_all import main_one

    main_one("nonlinear_time")
