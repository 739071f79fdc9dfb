"""Control benchmark: building the synthesis plant and closing a loop at 600 DOF, vibss against the
hand-written python-control route, same run; and the 6-DOF platform's design + analysis time.

Model: ``chain_model(100, zeta=0.01)`` (600 DOF) with 10 actuators (in parallel with the ground mounts
of bodies 0, 10, ..., 90, along their local axis 3) and a collocated geophone each; disturbance
``ground.z.vel``, performance the z velocity of 6 bodies.

- vibss: ``vibss.control.plant`` (modal realization, no integrator states), ``skyhook``, ``close``
  with ``margins=False`` (the hand route has none) and with margins.
- hand-written: the route a python-control user writes today: ``vibss.assemble`` for M, C, K,
  ``scipy.linalg.eigh`` for the modes, the modal state space by hand (absolute coordinates: the ground
  velocity through ``C_g`` plus a ground-displacement integrator state through ``K_g``), ``control.ss``
  and ``StateSpace.lft`` with the static skyhook gain.

Accuracy: the closed loops' ``ground.z.vel -> b0.z.vel`` response at 20 frequencies, against each
other (relative difference). One BLAS thread. Run: ``python benchmarks/bench_control.py [--quick]``
(``--quick``: a 40-body chain, 240 DOF, with 4 loops).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import control
import numpy as np
import scipy.linalg as sl
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.models import chain_model  # noqa: E402
import vibss  # noqa: E402
import vibss.control as vc  # noqa: E402
from vibss import Actuator, Sensor  # noqa: E402
from vibss.frequency.statespace_response import evaluate  # noqa: E402
from vibss.linear.plant.build import build_plant  # noqa: E402

GAIN = 2000.0


def outputs(m: vibss.Model) -> list[str]:
    """The performance outputs: the z velocity of 6 bodies spread along the chain (0, 20, ..., 99 of 100)."""
    n = len(m.bodies)
    return [f"b{round(i * (n - 1) / 99)}.z.vel" for i in (0, 20, 40, 60, 80, 99)]


def model(n: int = 100) -> vibss.Model:
    m = chain_model(n, zeta=0.01)
    ground = [x for x in m.mounts if x.to == "ground"]
    picks = [next(x for x in ground if x.body == f"b{i}") for i in range(0, n, 10)]
    acts = [Actuator(f"a{i}", mount=x.name, axis=3) for i, x in enumerate(picks)]
    sens = []
    for i, x in enumerate(picks):
        d = x.orientation.matrix[:, 2]
        sens.append(Sensor(f"g{i}", "velocity", body=x.body, at=x.at, frame=x.frame, direction=d))
    return m.replace(actuators=acts, sensors=sens)


def vibss_route(m: vibss.Model, margins: bool) -> tuple[object, float]:
    t = time.perf_counter()
    P = vc.plant(m, ["ground.z.vel"], performance=outputs(m))
    K = vc.skyhook(P, GAIN)
    cl = vc.close(P, K, margins=margins)
    return cl.system, time.perf_counter() - t


def hand_route(m: vibss.Model, check: bool = False) -> tuple[object, float]:
    t = time.perf_counter()
    u = [a.signal for a in m.actuators]
    p = build_plant(m, ["ground.z.disp", *u], outputs(m) + [s.signal for s in m.sensors])
    w2, phi = sl.eigh(p.K, p.M)
    n = p.n
    # states [eta; eta_dot; z_ground]; input [v_ground, f_1..f_k]; M q'' + C q' + K q = F f - Kz z - Cz v
    A = np.zeros((2 * n + 1, 2 * n + 1))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -np.diag(w2)
    A[n:2 * n, n:2 * n] = -phi.T @ p.C @ phi
    A[n:2 * n, 2 * n] = -(phi.T @ p.Kz[:, 0])
    B = np.zeros((2 * n + 1, 1 + len(u)))
    B[n:2 * n, 0] = -(phi.T @ p.Cz[:, 0])
    B[2 * n, 0] = 1.0
    B[n:2 * n, 1:] = phi.T @ p.F[:, 1:]
    C = np.hstack([np.zeros((len(p.outputs), n)), p.Ov @ phi, np.zeros((len(p.outputs), 1))])
    P = control.ss(A, B, C, np.zeros((len(p.outputs), 1 + len(u))))
    k = len(u)
    K = control.ss(np.zeros((0, 0)), np.zeros((0, k)), np.zeros((k, 0)), -GAIN * np.eye(k))
    cl = P.lft(K, k, k)                  # u = K y on the last k inputs and outputs
    if check:                            # what close() does first: is the closed loop stable?
        assert np.linalg.eigvals(cl.A).real.max() < 1e-9 * np.abs(cl.A).max()
    return cl, time.perf_counter() - t


def main(quick: bool = False) -> dict:
    n = 40 if quick else 100
    with threadpool_limits(1):
        m = model(n)
        vibss_route(m, False)                       # warm caches and imports
        hand_route(m)
        tv = min(vibss_route(m, False)[1] for _ in range(3))
        tm = min(vibss_route(m, True)[1] for _ in range(1 if quick else 2))
        th = min(hand_route(m)[1] for _ in range(3))
        thc = min(hand_route(m, True)[1] for _ in range(3))
        t = time.perf_counter()
        P = vc.plant(m, ["ground.z.vel"], performance=outputs(m))
        tp = time.perf_counter() - t
        sv, _ = vibss_route(m, False)
        sh, _ = hand_route(m)
        f = np.geomspace(1.0, 200.0, 20)
        hv = evaluate(sv, 2 * np.pi * f)[0, 0]
        hh = evaluate(sh, 2 * np.pi * f)[0, 0]
        diff = float(np.max(np.abs(hv - hh) / np.abs(hh)))
        # the platform: design + closed-loop analysis
        pm = vibss.load_example("platform")
        cs = pm.settings["control"]
        t = time.perf_counter()
        P = vc.plant(pm, cs["disturbances"], performance=cs["performance"])
        vc.close(P, vc.skyhook(P, cs["gain"]))
        t_platform = time.perf_counter() - t
    out = {"vibss_s": tv, "vibss_plant_s": tp, "vibss_with_margins_s": tm, "hand_s": th,
           "hand_with_stability_check_s": thc, "ratio_hand_over_vibss": th / tv, "ratio_checked": thc / tv,
           "closed_loop_difference": diff, "states_vibss": sv.nstates, "states_hand": sh.nstates,
           "platform_design_and_analysis_s": t_platform}
    print(f"{6 * n} DOF, {len(m.actuators)} skyhook loops: plant + close")
    print(f"  vibss plant only              {tp:8.3f} s")
    print(f"  vibss plant+close (no margins){tv:8.3f} s   states {sv.nstates}  (close checks stability: eigvals)")
    print(f"  vibss plant+close ({len(m.actuators)} margins){tm:8.3f} s")
    print(f"  hand-written, no check        {th:8.3f} s   states {sh.nstates}   ratio hand/vibss {th / tv:.2f}")
    print(f"  hand-written + stability check{thc:8.3f} s   ratio hand/vibss {thc / tv:.2f}")
    print(f"  closed loops agree to {diff:.1e} (relative, 20 frequencies)")
    print(f"platform (6 DOF, 12 loops): design + poles + margins {t_platform:.3f} s")
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    main(ap.parse_args().quick)
