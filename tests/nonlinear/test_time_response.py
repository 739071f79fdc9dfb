"""The nonlinear time response (stops located, curves) against independent answers: the closed form of a
bilinear oscillator's free vibration (contact times, contact duration, peak), an event-driven
``solve_ivp`` written here (piecewise linear, rtol 1e-12), the linear simulate where no stop engages,
and the refusals."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator

import vibss
from vibss import Body, Model, Mount, MountType
from vibss.errors import ModelError, VibssWarning
from vibss.model.excitation import Excitation
from vibss.model.timefunctions import HalfSine

M, K, KS, CLEAR = 10.0, 1e4, 1e6, 1e-3
G = 9.81


def _sdof(t: MountType, gravity: bool = False) -> Model:
    return Model([Body("b", M, [1.0, 1.0, 1.0])], [Mount("m", t, "b", at=[0.0, 0.0, 0.0])],
                 gravity=[0.0, 0.0, -G] if gravity else None)


def _stop_force(x: float, regime: int, lo: float = CLEAR, hi: float = CLEAR) -> float:
    return KS * (x - hi) if regime > 0 else (KS * (x + lo) if regime < 0 else 0.0)


def _event_driven(rhs, y0: np.ndarray, t_end: float, edges: list[float], lo: float | None = None,
                  hi: float | None = None, regime: int = 0, knots: tuple[float, ...] = (), rtol: float = 1e-12,
                  max_step: float = np.inf):
    """solve_ivp (DOP853, ``rtol``) restarted at every pulse edge, at every crossing of a clearance
    ``-lo`` or ``hi`` (terminal events, the direction of the crossing out of the current regime; the
    regime, not the sign of the deflection, picks the stop force) and of a curve's ``knots`` (where its
    second derivative jumps): a dense solution as a list of pieces. ``rhs(t, y, regime)``. solve_ivp
    sees an event only where it changes sign between two steps: ``max_step`` for a grazing contact."""
    pieces, t, y = [], 0.0, np.asarray(y0, float)
    back: dict[float, float] = {}
    stops = sorted(set([e for e in edges if 0 < e < t_end] + [t_end]))
    for stop in stops:
        while t < stop:
            events = []
            if hi is not None and regime >= 0:
                events.append((lambda tt, yy: yy[0] - hi, 1.0 if regime == 0 else -1.0, 1 if regime == 0 else 0))
            if lo is not None and regime <= 0:
                events.append((lambda tt, yy: yy[0] + lo, -1.0 if regime == 0 else 1.0, -1 if regime == 0 else 0))
            for k in knots:                  # a restart, the regime kept; the knot just crossed only back
                events.append((lambda tt, yy, k=k: yy[0] - k, back.get(k, 0.0), ("knot", k)))
            fns = []
            for fn, direction, _ in events:
                fn.terminal, fn.direction = True, direction
                fns.append(fn)
            sol = solve_ivp(lambda tt, yy: rhs(tt, yy, regime), (t, stop), y, method="DOP853", rtol=rtol,
                            atol=1e-16, dense_output=True, events=fns or None, max_step=max_step)
            pieces.append((t, sol.t[-1], sol.sol))
            t, y = float(sol.t[-1]), sol.y[:, -1]
            back = {}
            if sol.status == 1:
                what = events[[i for i, te in enumerate(sol.t_events) if te.size][0]][2]
                if isinstance(what, tuple):
                    back[what[1]] = -float(np.sign(y[1]))
                else:
                    regime = what
    return pieces


def _evaluate(pieces, ts: np.ndarray) -> np.ndarray:
    out = np.empty((2, ts.size))
    for a, b, sol in pieces:
        sel = (ts >= a) & (ts <= b)
        if not sel.any():                    # a piece between two of the times (a short contact)
            continue
        out[:, sel] = sol(ts[sel])
    return out


def test_free_bilinear_oscillator_matches_its_closed_form() -> None:
    """From d = 0 at speed v0: free flight at w1 = sqrt(k/m) to the clearance at t1 = asin(c w1 / v0) / w1,
    then the stop at w2 = sqrt((k + ks)/m) about d* = ks c / (k + ks); peak d* + sqrt((c - d*)^2 + (v1/w2)^2),
    contact lasting 2 atan2(v1 / w2, c - d*) / w2; the contacts alternate sides every 2 t1 + tc."""
    t = MountType("snub", [K, K, K], stops={"z": (CLEAR, KS)})
    v0 = 0.2
    r = vibss.simulate(_sdof(t), outputs=["b.z"], t_end=0.1, dt=1e-3,
                       initial={"b": {"velocity": [0, 0, v0, 0, 0, 0]}})
    w1, w2 = np.sqrt(K / M), np.sqrt((K + KS) / M)
    t1 = np.arcsin(CLEAR * w1 / v0) / w1
    v1 = v0 * np.cos(w1 * t1)
    ds = KS * CLEAR / (K + KS)
    peak = ds + np.hypot(CLEAR - ds, v1 / w2)
    tc = 2 * np.arctan2(v1 / w2, CLEAR - ds) / w2
    c = r.contacts
    assert c.first[0] == pytest.approx(t1, rel=1e-9) and c.side[0] == "+"
    assert c.peak[0] == pytest.approx(peak, rel=1e-6)             # the claim at rtol = 1e-6
    period = 4 * t1 + 2 * tc
    starts = [s for s, _ in c.intervals[0]]
    assert np.allclose(starts, t1 + period * np.arange(len(starts)), rtol=1e-6, atol=0)
    assert c.duration[0] == pytest.approx(len(starts) * tc, rel=1e-6)
    assert c.first[1] == pytest.approx(t1 + tc + 2 * t1, rel=1e-6) and c.side[1] == "-"
    assert c.peak[1] == pytest.approx(-peak, rel=1e-6)
    assert c.force[0] == pytest.approx(KS * (peak - CLEAR), rel=1e-6)
    assert "stop contacts" in r.report() and "m.z+" in repr(c)


def test_half_sine_into_a_stop_matches_an_event_driven_solve_ivp() -> None:
    t = MountType("snub", [K, K, K], damping=[20.0] * 3, stops={"z": ((0.5 * CLEAR, CLEAR), KS)})
    F0, T = 300.0, 0.02
    exc = Excitation("p", "force", "b", HalfSine(F0, 0.0, T), dof="z")
    r = vibss.simulate(_sdof(t), [exc], outputs=["b.z", "mount.m.f3"], t_end=0.15, dt=1e-3, rtol=1e-8)

    def rhs(tt, y, regime):
        f = F0 * np.sin(np.pi * tt / T) if tt < T else 0.0
        return [y[1], (f - K * y[0] - 20.0 * y[1] - _stop_force(y[0], regime, 0.5 * CLEAR, CLEAR)) / M]

    pieces = _event_driven(rhs, [0.0, 0.0], 0.15, [T], lo=0.5 * CLEAR, hi=CLEAR)
    ref = _evaluate(pieces, r.time)
    scale = np.abs(ref[0]).max()
    assert np.abs(r["b.z"] - ref[0]).max() <= 1e-7 * scale
    force = K * ref[0] + 20.0 * ref[1] + KS * (np.maximum(ref[0] - CLEAR, 0) + np.minimum(ref[0] + 0.5 * CLEAR, 0))
    assert np.abs(r["mount.m.f3"] - force).max() <= 1e-6 * np.abs(force).max()
    # the peaks between the samples: the reference's own extrema
    fine = np.linspace(0, 0.15, 300001)
    dense = _evaluate(pieces, fine)[0]
    c = r.contacts
    hi = c.peak[list(c.side).index("+")]
    assert hi == pytest.approx(dense.max(), rel=1e-7)
    assert c.first[0] == pytest.approx(fine[np.argmax(dense > CLEAR)], abs=2 * (fine[1] - fine[0]))
    assert "checked" in r.note


def test_gravity_starts_at_the_operating_point_on_the_stop() -> None:
    """Under its weight the mass already rests on the stop (sag past the clearance, the bilinear closed
    form); a half-sine lifts it off and drops it back: against solve_ivp with gravity from that rest."""
    t = MountType("snub", [K, K, K], stops={"z": (CLEAR, KS)})
    sag = CLEAR + (M * G - K * CLEAR) / (K + KS)          # weight 98.1 N > k c = 10 N: on the stop
    F0, T = 400.0, 0.01
    exc = Excitation("p", "force", "b", HalfSine(F0, 0.0, T), dof="z")
    r = vibss.simulate(_sdof(t, gravity=True), [exc], outputs=["b.z"], t_end=0.08, dt=5e-4, rtol=1e-8)

    def rhs(tt, y, regime):
        f = F0 * np.sin(np.pi * tt / T) if tt < T else 0.0
        return [y[1], (f - M * G - K * y[0] - _stop_force(y[0], regime)) / M]

    pieces = _event_driven(rhs, [-sag, 0.0], 0.08, [T], lo=CLEAR, hi=CLEAR, regime=-1)
    ref = _evaluate(pieces, r.time)[0] + sag                 # the motion from the operating point
    assert np.abs(r["b.z"] - ref).max() <= 1e-7 * np.abs(ref).max()
    c = r.contacts
    assert c.first[0] == 0.0 and c.side[0] == "-"           # in contact at the operating point
    assert len(c.intervals[0]) >= 2                          # lifted off and landed again
    assert "operating point" in r.note


def test_curve_matches_solve_ivp_with_the_same_pchip() -> None:
    pts = [(-4e-3, -80.0), (-1e-3, -10.0), (0.0, 0.0), (1e-3, 10.0), (4e-3, 80.0)]
    t = MountType("soft", [K, K, K], curve={"z": pts})
    curve = PchipInterpolator(*np.array(pts).T, extrapolate=False)
    k_end = float(curve(4e-3, 1))

    def law(x: float) -> float:
        if x > 4e-3:
            return 80.0 + k_end * (x - 4e-3)
        if x < -4e-3:
            return -80.0 + k_end * (x + 4e-3)
        return float(curve(x))

    F0, T = 150.0, 0.02
    exc = Excitation("p", "force", "b", HalfSine(F0, 0.0, T), dof="z")
    r = vibss.simulate(_sdof(t), [exc], outputs=["b.z"], t_end=0.1, dt=1e-3, rtol=1e-8)

    def rhs(tt, y, regime):
        f = F0 * np.sin(np.pi * tt / T) if tt < T else 0.0
        return [y[1], (f - law(y[0])) / M]

    ref = _evaluate(_event_driven(rhs, [0.0, 0.0], 0.1, [T]), r.time)[0]
    assert np.abs(r["b.z"] - ref).max() <= 1e-6 * np.abs(ref).max()
    assert len(r.contacts) == 0 and "no stop hit" in r.contacts.table.render()


def test_no_stop_engaged_equals_the_linear_simulate() -> None:
    """Stops far away: the response from the operating point (gravity on) is the linear one to 1e-10."""
    t = MountType("snub", [2e4, 3e4, 5e4], damping=[30.0, 40.0, 50.0], stops={"z": (0.5, 1e6), "x": (0.5, 1e6)})
    lin_t = MountType("lin", [2e4, 3e4, 5e4], damping=[30.0, 40.0, 50.0])
    body = Body("b", 20.0, [0.4, 0.5, 0.6])
    mounts = [Mount(f"m{i}", t, "b", at=at) for i, at in enumerate([[0.3, 0.2, 0], [-0.3, 0.2, 0], [0, -0.3, 0.1]])]
    nl = Model([body], mounts, gravity=[0, 0, -G])
    lin = dataclasses.replace(nl, mounts=tuple(dataclasses.replace(m, type=lin_t) for m in mounts))
    exc = Excitation("s", "acceleration", "ground", HalfSine(3 * G, 0.0, 0.011), dof="z")
    outs = ["b.z", "b.rx", "mount.m0.d3", "mount.m1.f3"]
    a = vibss.simulate(nl, [exc], outputs=outs, t_end=0.1, dt=1e-3)
    b = vibss.simulate(lin, [exc], outputs=outs, t_end=0.1, dt=1e-3, method="modal")
    assert a.method == "nonlinear_modal" and len(a.contacts) == 0
    scale = np.abs(b.outputs).max(axis=1, keepdims=True)
    assert np.abs(a.outputs - b.outputs).max() <= 1e-10 * scale.max()
    assert np.all(np.abs(a.outputs - b.outputs) <= 1e-10 * scale)


def test_bad_methods_and_models_are_refused_by_name() -> None:
    t = MountType("snub", [K, K, K], stops={"z": (CLEAR, KS)})
    model = _sdof(t)
    exc = Excitation("p", "force", "b", HalfSine(100.0, 0.0, 0.01), dof="z")
    for method in ("modal", "forced_response", "newmark"):
        with pytest.raises(ModelError, match=r"is linear, and mounts \['m'\] have stops"):
            vibss.simulate(model, [exc], t_end=0.05, dt=1e-3, method=method)
    lin = _sdof(MountType("lin", [K, K, K]))
    plant = vibss.linear.plant.build.build_plant(lin, ["b.fz"], ["b.z"])
    with pytest.raises(ModelError, match="simulates a Model .* not a Plant"):
        vibss.simulate(plant, inputs={"b.fz": lambda t: 0 * t + 1.0}, t_end=0.05, dt=1e-3, method="nonlinear_modal")
    with pytest.raises(ModelError, match="nothing drives the response"):
        vibss.simulate(model, t_end=0.05, dt=1e-3)
    with pytest.raises(ModelError, match="nonlinear_moda"):
        vibss.simulate(model, [exc], t_end=0.05, dt=1e-3, method="nonlinear_modl")


def test_a_step_too_long_for_the_stop_warns_with_the_bound(monkeypatch: pytest.MonkeyPatch) -> None:
    """With the internal step 40 times too long for the stop, the step-doubling check misses rtol:
    a VibssWarning, and the note carries the bound, which covers the error against the reference."""
    import vibss.time.nonlinear as nl

    t = MountType("snub", [K, K, K], stops={"z": (CLEAR, KS)})
    exc = Excitation("p", "force", "b", HalfSine(300.0, 0.0, 0.02), dof="z")
    ref = vibss.simulate(_sdof(t), [exc], outputs=["b.z"], t_end=0.05, dt=1e-3, rtol=1e-10)
    monkeypatch.setattr(nl, "THETA", 40 * nl.THETA)
    with pytest.warns(vibss.errors.VibssWarning, match="missed its claim"):
        r = vibss.simulate(_sdof(t), [exc], outputs=["b.z"], t_end=0.05, dt=1e-3, method="nonlinear_modal")
    assert "check failed" in r.note
    bound = float(r.note.split("check failed: error ")[1].split()[0])
    error = np.abs(r["b.z"] - ref["b.z"]).max() / np.abs(ref["b.z"]).max()
    assert error <= bound                               # the stated bound covers the error
    # auto halves the step until the check passes
    a = vibss.simulate(_sdof(t), [exc], outputs=["b.z"], t_end=0.05, dt=1e-3)
    assert "the step refined" in a.note and "checked" in a.note
    assert np.abs(a["b.z"] - ref["b.z"]).max() <= 1e-6 * np.abs(ref["b.z"]).max()


def test_two_bodies_general_damping_ground_shock_match_solve_ivp_of_the_full_state() -> None:
    """Two bodies, non-proportional damping (complex modes), a ground acceleration half-sine, a stop on one
    ground mount: against solve_ivp (DOP853, rtol 1e-11) of the full first-order state built from the
    linear part's matrices, restarted at every crossing of the clearance."""
    from vibss.linear.plant.build import build_plant

    stop = MountType("snub", [2e4, 2e4, 3e4], damping=[5.0, 5.0, 60.0], stops={"z": (2e-3, 3e5)})
    soft = MountType("soft", [1e4, 1e4, 1e4], damping=[30.0, 30.0, 2.0])
    bodies = [Body("a", 8.0, [0.2, 0.3, 0.25]), Body("c", 3.0, [0.05, 0.04, 0.06], cog=[0.5, 0.0, 0.2])]
    mounts = [Mount("s", stop, "a", at=[0.1, 0.05, 0.0]), Mount("g", soft, "a", at=[-0.2, 0.1, 0.0]),
              Mount("h", soft, "a", at=[0.0, -0.2, 0.0]), Mount("l", soft, "c", at=[0.5, 0.0, 0.1], to="a")]
    model = Model(bodies, mounts)
    amp, T, t_end = 3 * G, 0.011, 0.06
    exc = Excitation("shock", "acceleration", "ground", HalfSine(amp, 0.0, T), dof="z")
    r = vibss.simulate(model, [exc], outputs=["mount.s.d3", "c.z"], t_end=t_end, dt=5e-4, rtol=1e-8)
    lin = dataclasses.replace(model, mounts=tuple(dataclasses.replace(m, type=MountType(
        m.type.name, m.type.stiffness, damping=m.type.damping)) for m in mounts))
    p = build_plant(lin, ["ground.z.disp"], ["mount.s.d3", "c.z"])
    M, K, C = (np.asarray(a, float) for a in (p.M, p.K, p.C))
    Minv = np.linalg.inv(M)
    kz, cz = np.asarray(p.Kz)[:, 0], np.asarray(p.Cz)[:, 0]
    R, Rz = np.asarray(p.Oq)[0], float(np.asarray(p.Pz)[0, 0])
    Y, Yz = np.asarray(p.Oq), np.asarray(p.Pz)[:, 0]
    w, n = np.pi / T, M.shape[0]

    def ground(t: float) -> tuple[float, float]:
        if t < T:
            return amp / w * (t - np.sin(w * t) / w), amp / w * (1 - np.cos(w * t))
        return amp / w * T + 2 * amp / w * (t - T), 2 * amp / w

    def rhs(t, x, regime):
        z, dz = ground(t)
        d = R @ x[:n] + Rz * z
        g = 3e5 * (d - 2e-3 if regime > 0 else d + 2e-3 if regime < 0 else 0.0)
        return np.concatenate([x[n:], Minv @ (-K @ x[:n] - C @ x[n:] - kz * z - cz * dz - R * g)])

    t, x, regime, pieces = 0.0, np.zeros(2 * n), 0, []
    for end in (T, t_end):
        while t < end:
            events = [(s_, c_) for s_, c_ in ((1, 2e-3), (-1, -2e-3)) if regime in (0, s_)]
            fns = []
            for s_, c_ in events:
                fn = (lambda tt, xx, c_=c_: R @ xx[:n] + Rz * ground(tt)[0] - c_)
                fn.terminal, fn.direction = True, s_ if regime == 0 else -s_
                fns.append(fn)
            sol = solve_ivp(lambda tt, xx: rhs(tt, xx, regime), (t, end), x, method="DOP853", rtol=1e-11,
                            atol=1e-17, dense_output=True, events=fns)
            pieces.append((t, float(sol.t[-1]), sol.sol))
            t, x = float(sol.t[-1]), sol.y[:, -1]
            if sol.status == 1:
                s_ = events[[i for i, te in enumerate(sol.t_events) if te.size][0]][0]
                regime = s_ if regime == 0 else 0
    ref = np.zeros((2, r.time.size))
    for a, b, sol in pieces:
        sel = (r.time >= a) & (r.time <= b * (1 + 1e-12))
        tt = np.minimum(r.time[sel], b)
        ref[:, sel] = Y @ sol(tt)[:n] + Yz[:, None] * np.array([ground(s)[0] for s in tt])
    assert "complex modes" in r.note and len(r.contacts) >= 1
    scale = np.abs(ref).max(axis=1, keepdims=True)
    assert np.abs(r.outputs - ref).max() <= 1e-7 * scale.max()
    assert np.all(np.abs(r.outputs - ref) <= 1e-7 * scale)


@pytest.mark.slow
@pytest.mark.parametrize("rtol, t_end", [(1e-6, 0.1), (1e-8, 0.04)])
def test_the_stated_error_of_a_shock_into_a_curved_snubber_is_kept(rtol: float, t_end: float) -> None:
    """The snubbed cabinet example (four like isolators, a hardening PCHIP curve in z and stops 4 mm
    below and 6 mm above, a 30 g base half-sine) moves in z alone by symmetry: one DOF of the mount's
    deflection ``d`` (relative to the ground), ``m d'' + 4 c d' + 4 f(d) = -m (g + a_base(t))``. An
    event-driven solve_ivp of that (rtol 1e-13, restarted at the clearances and at the curve's points,
    scipy's own PCHIP; its sag by brentq to 1e-17 m) is the reference: the auto run's error is within
    its claim (rtol of the peak), and its check's stated error is not below a third of it. Measured
    over 0.1 s: 1.7e-7 at rtol 1e-6 (stated 2.1e-7), 1.2e-11 at 1e-8 (stated 2.1e-10); before the
    curve's points were located 1e-8 took hundreds of steps per sample, and before the sag took its
    last Newton step the error stopped at 4.5e-10 (the sag 4.8e-10 off)."""
    model = vibss.load_example("snubbed_cabinet")
    mm, n = 1e-3, 4
    pts = np.array([[-4.0, -300.0], [-3.0, -210.0], [-2.0, -125.0], [-1.0, -60.0], [0.0, 0.0], [1.0, 60.0],
                    [2.0, 120.0], [4.0, 240.0]]) * [mm, 1.0]
    curve = PchipInterpolator(pts[:, 0], pts[:, 1])
    lo_end, hi_end = pts[0, 0], pts[-1, 0]
    s_lo, s_hi = float(curve(lo_end, 1)), float(curve(hi_end, 1))
    c, ks, c_lo, c_hi = 0.08e3, 1200e3, 4.0 * mm, 6.0 * mm
    mass, g, amp, dur = 40.0, 9.81, 294199.5 * mm, 0.011

    def elastic(d: float) -> float:
        if d < lo_end:
            return float(curve(lo_end)) + s_lo * (d - lo_end)
        if d > hi_end:
            return float(curve(hi_end)) + s_hi * (d - hi_end)
        return float(curve(d))

    def rhs(t: float, y: np.ndarray, regime: int) -> list[float]:
        base = amp * np.sin(np.pi * t / dur) if t < dur else 0.0
        f = elastic(y[0]) + (ks * (y[0] - c_hi) if regime > 0 else ks * (y[0] + c_lo) if regime < 0 else 0.0)
        return [y[1], -(n * c * y[1] + n * f) / mass - g - base]

    from scipy.optimize import brentq
    d_op = brentq(lambda d: n * elastic(d) + mass * g, -4 * mm, 0.0, xtol=1e-17)     # the sag, inside the clearance
    dt = 2e-4
    ts = np.arange(0.0, t_end + dt / 2, dt)
    ref = _evaluate(_event_driven(rhs, np.array([d_op, 0.0]), t_end, [dur], lo=c_lo, hi=c_hi,
                                  knots=tuple(pts[:, 0]), rtol=1e-13), ts)[0] - d_op
    r = vibss.simulate(model, list(model.excitations), outputs=["mount.foot.dz"], t_end=t_end, dt=dt, rtol=rtol)
    assert r.method == "nonlinear_modal" and ref.min() + d_op < -c_lo    # the shock reaches the stop
    # (the output is the deflection from the operating point)
    err = float(np.abs(r["mount.foot.dz"] - ref).max() / np.abs(ref).max())
    stated = float(r.note.rsplit("checked: error ", 1)[1].split()[0])
    assert err <= rtol
    assert stated >= err / 3


@pytest.mark.parametrize("f0", [25.074, 25.096, 25.112])
def test_a_grazing_contact_is_integrated_not_refused(f0: float) -> None:
    """A half-sine force whose peak just reaches the stop (contacts far shorter than the 2 ms step,
    and the return crossing within the interval of the touch) once left the stop's regime behind the
    deflection and ended in "more than 16 stop events in one step" (a review's reproducer). Reference:
    the event-driven DOP853 of the same 1-DOF equation (steps of at most 20 us: without, it steps over
    the 25.074 N touch, 35 nm deep, and misses it): within the claim. Not asserted, noticed: at 25.074 N
    the step doubling states 6.5e-13 for an error of 1.8e-6 (both runs resolve the touch alike; the
    same before this change), within rtol 1e-4 but not a bound."""
    t = MountType("snub", [K, K, K], stops={"z": (CLEAR, KS)})
    exc = Excitation("p", "force", "b", HalfSine(f0, 0.0, 0.02), dof="z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VibssWarning)
        r = vibss.simulate(_sdof(t), [exc], outputs=["b.z"], t_end=0.1, dt=2e-3, rtol=1e-4)

    def rhs(tt: float, y: np.ndarray, regime: int) -> list[float]:
        force = f0 * np.sin(np.pi * tt / 0.02) if tt < 0.02 else 0.0
        return [y[1], (force - K * y[0] - (KS * (y[0] - CLEAR) if regime > 0 else 0.0)) / M]

    ref = _evaluate(_event_driven(rhs, [0.0, 0.0], 0.1, [0.02], hi=CLEAR, max_step=2e-5), r.time)[0]
    assert r.method == "nonlinear_modal" and len(r.contacts) == 1
    assert float(np.abs(r["b.z"] - ref).max() / np.abs(ref).max()) <= 1e-4
