"""Write the example notebooks (outputs empty) from the cells below: ``python examples/make_notebooks.py``.

The notebooks are generated so that their text and code stay reviewable as plain Python; run them
in Jupyter, or let ``tests/project/test_notebooks.py`` execute them.
"""

from __future__ import annotations

from pathlib import Path

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

HERE = Path(__file__).parent

FRF = [
    ("md", """# Frequency response and transmissibility

Two questions an isolation designer asks of a mounting system:

1. **Motion transmissibility**: how much of a floor vibration reaches the machine?
2. **Force transmissibility**: how much of the machine's own excitation reaches the floor?

We first check vibss against the textbook single-degree-of-freedom isolator, then look at the
steady-state response of a car powertrain to the engine's torque fluctuation (a sine sweep in the
example file)."""),
    ("code", """%matplotlib inline
import numpy as np
import matplotlib.pyplot as plt
import vibss
from vibss.frequency.sweep import transmissibility, sweep_response"""),
    ("md", """## The single-DOF isolator

A 100 kg block on four mounts in the plane of its centre of gravity: its vertical motion is a
single-DOF oscillator with k = 4 k_z and damping ratio ζ = c / (2 √(k m)). Theory:
|T| = √(1 + (2ζr)²) / √((1 − r²)² + (2ζr)²) with r = f / f_n. Isolation (|T| < 1) starts at r = √2."""),
    ("code", """m, kz, zeta = 100.0, 2.5e4, 0.1
k = 4 * kz
c = 2 * zeta * np.sqrt(k * m) / 4          # per mount
rubber = vibss.MountType("rubber", stiffness=[kz, kz, kz], damping=[c, c, c])
block = vibss.Body("block", m, [4.0, 4.0, 6.0])
model = vibss.Model([block], vibss.symmetric(vibss.Mount("m", rubber, "block", at=[0.3, 0.3, 0.0])))
fn = np.sqrt(k / m) / (2 * np.pi)
f = np.linspace(0.0, 5 * fn, 400)
t = transmissibility(model, ["ground.z"], ["block.z"], frequencies=f)
r = f / fn
theory = np.sqrt(1 + (2 * zeta * r) ** 2) / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
print(f"f_n = {fn:.3f} Hz; largest difference from theory: {np.max(np.abs(np.abs(t.channel('block.z')) - theory)):.2e}")"""),
    ("code", """fig, ax = plt.subplots(figsize=(7, 4))
ax.semilogy(r, np.abs(t.channel("block.z")), lw=3, alpha=0.5, label="vibss")
ax.semilogy(r, theory, "k--", lw=1, label="closed form")
ax.axvline(np.sqrt(2), color="0.5", ls=":", label="r = √2")
ax.set_xlabel("frequency ratio r = f / f_n [-]")
ax.set_ylabel("motion transmissibility |T| [-]")
ax.legend(); ax.grid(True, alpha=0.3)"""),
    ("md", """## A car powertrain under the engine's torque fluctuation

The example file `powertrain` has a steady-state sine sweep (`sweep_time = 0`) of the roll moment
about the crankshaft. `sweep_response` gives the body's steady motion over the sweep's band;
`transmissibility` the forces it sends into the car body per unit roll moment."""),
    ("code", """pt = vibss.io.load_example("powertrain")
firing = [e for e in pt.excitations if e.name == "firing-torque"]   # the file also has a shock
sweep = sweep_response(pt, firing)
print(sweep.report())
sweep.plot(outputs=["powertrain.rx", "powertrain.z", "powertrain.y"])   # returns the Figure, shown inline"""),
    ("code", """ground = ["ground.fx", "ground.fy", "ground.fz"]
force = transmissibility(pt, ["powertrain.mx"], ground)
fig = force.plot()
fig.axes[0].set_ylabel("force into the car body\\nper roll moment [N / (N m)]")
print("natural frequencies [Hz]:", np.round(force.natural_hz, 2))
fig"""),
    ("md", """Above the highest mode (13 Hz) the transmitted forces fall with frequency: the mounts isolate
the second engine order at idle (26.7 Hz)."""),
]

SHOCK = [
    ("md", """# Shock study: an instrument packed in foam

The example `packaged_item` is a 12 kg instrument held in its carton by eight foam corner blocks. The
carton gets the classic shock-test pulse: a 50 g, 11 ms half-sine of vertical acceleration. Two
questions: what peak acceleration does the instrument see, and how far do the foam blocks deflect
(they must stay below ~60 % of their 50 mm thickness)?"""),
    ("code", """%matplotlib inline
import numpy as np
import matplotlib.pyplot as plt
import vibss
from vibss.model.excitation import Excitation, HalfSine
from vibss.time.api import simulate

model = vibss.io.load_example("packaged_item")
print(vibss.modes(model).frequency_table())"""),
    ("code", """outputs = ["item.z", "item.z.acc", "mount.lower.dz"]
r = simulate(model, outputs=outputs, t_end=0.1, dt=1e-4)
pk = r.peaks()
g = 9.81
for name, unit, v, t in zip(pk.outputs, pk.units, pk.value, pk.time):
    print(f"{name:16s} peak {v: .4g} {unit} at {1e3 * t:.1f} ms")
print(f"peak item acceleration: {abs(pk.value[1]) / g:.1f} g; foam deflection {1e3 * abs(pk.value[2]):.1f} mm "
      f"({100 * abs(pk.value[2]) / 0.050:.0f} % of 50 mm)")"""),
    ("code", """fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
a1.plot(1e3 * r.time, r.output("item.z.acc") / g, label="item")
a1.plot(1e3 * r.time, r.inputs[0] / g, "k--", lw=1, label="carton (input)")
a1.set_ylabel("acceleration [g]"); a1.legend(); a1.grid(True, alpha=0.3)
a2.plot(1e3 * r.time, 1e3 * r.output("mount.lower.dz"))
a2.set_ylabel("foam deflection [mm]"); a2.set_xlabel("time [ms]"); a2.grid(True, alpha=0.3)"""),
    ("md", """## How the pulse duration matters

The same 50 g peak, with durations from 2 to 40 ms. A pulse much shorter than the natural period
(1 / 15.9 Hz = 63 ms) is absorbed by the foam (the item sees less than the carton); a pulse near
half the period is amplified. This is the shock response spectrum of the packaged item."""),
    ("code", """durations = np.array([2, 4, 8, 11, 16, 24, 32, 40]) * 1e-3
peaks = []
for d in durations:
    shock = Excitation("shock", "acceleration", "ground", HalfSine(50 * g, 0.0, float(d)), dof="z")
    ri = simulate(model, [shock], outputs=["item.z.acc"], t_end=0.15, dt=1e-4)
    peaks.append(np.max(np.abs(ri.outputs[0])) / g)
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(1e3 * durations, np.array(peaks) / 50, "o-")
ax.axhline(1, color="0.5", ls=":")
ax.set_xlabel("half-sine duration [ms]"); ax.set_ylabel("item peak / input peak [-]")
ax.grid(True, alpha=0.3)"""),
]

STIFFNESS = [
    ("md", """# Mount stiffness and inclination: decoupling a powertrain's modes

A powertrain's engine mounts are usually inclined in a V. The aim is to decouple the roll mode
(about the crankshaft, x) from the lateral and vertical ones, so that the engine's torque
fluctuation excites roll alone. This notebook turns the V-angle and the mount stiffness of the
`powertrain` example and watches the six natural frequencies and the decoupling. It needs only
the core of vibss (modes and their kinetic-energy distribution)."""),
    ("code", """%matplotlib inline
import dataclasses
import numpy as np
import matplotlib.pyplot as plt
import vibss
from vibss import Orientation, symmetric
from vibss.plotting import plot_energy, plot_modes

base = vibss.io.load_example("powertrain")
engine = next(m for m in base.mounts if m.name == "engine")
others = [m for m in base.mounts if not m.name.startswith("engine")]
print("engine mount as given:", engine.orientation.describe())"""),
    ("md", """`with_mounts` rebuilds the model with the two engine mounts inclined by `angle` degrees (a rotation
about x: positive leans the compression axis 3 of the +y mount towards -y, inwards; the mirrored
mount leans the other way) and their stiffness scaled by `scale`. The *decoupling* of the roll mode
is the share of its kinetic energy in roll (100 % = pure roll)."""),
    ("code", """def with_mounts(angle, scale=1.0):
    t = dataclasses.replace(engine.type, stiffness=scale * engine.type.stiffness)
    m = dataclasses.replace(engine, type=t, orientation=Orientation.from_euler([0, 0, angle], degrees=True))
    return base.replace(mounts=[*symmetric(m, "xz"), *others])

def roll_mode(modes):
    k = int(np.argmax(modes.direction_energy[:, 3]))   # the mode with most roll (rx) energy
    return k, modes.direction_energy[k, 3]

angles = np.arange(-60, 61, 5)
steps = [vibss.modes(with_mounts(a)) for a in angles]
roll_share = [roll_mode(md)[1] for md in steps]
tracks = vibss.track_modes(steps)        # each mode followed by its shape (MAC), not by its rank
best = int(angles[int(np.argmax(roll_share))])
print(f"as given (40 deg): {100 * roll_share[list(angles).index(40)]:.0f} % roll energy in the roll mode")
print(f"purest roll mode at {best} deg: {100 * max(roll_share):.1f} %")"""),
    ("md", """Sorted by frequency, two modes that veer swap ranks, and a line per rank would jump from one
mode to the other. `vibss.track_modes` follows each mode by its shape (the mass-weighted MAC between
neighbouring angles), so each colour is one mode, named in the legend by its direction at -60 degrees."""),
    ("code", """fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4), layout="constrained")
tracks.plot(angles, "engine mount V-angle [deg]", ax=a1)
a1.set_title("the six modes, tracked by MAC")
a2.plot(angles, 100 * np.array(roll_share), "o-")
a2.axvline(40, color="0.5", ls=":")
a2.set_xlabel("engine mount V-angle [deg]"); a2.set_ylabel("roll energy in the roll mode [%]")
a2.set_title("decoupling of the roll mode"); a2.grid(True, alpha=0.3)"""),
    ("md", """Pointing the compression axes at the crankshaft (the file's 40 degrees) is a geometric rule of
thumb; the elastic optimum also depends on the shear stiffness of the mounts and on the other
mounts. Here the torque strut, high on the engine and stiff sideways, raises the lateral elastic
centre above the roll axis, and the V-angle that compensates it leans the other way.

## Stiffness scale

Scaling *all* mounts by the same factor multiplies every frequency by √scale and leaves the energy
distribution unchanged: it depends on the stiffness *ratios* and the geometry only. Scaling the
engine mounts alone changes the ratios, so it moves the decoupling too."""),
    ("code", """def all_scaled(model, scale):
    return model.replace(mounts=[dataclasses.replace(m, type=dataclasses.replace(
        m.type, stiffness=scale * m.type.stiffness)) for m in model.mounts])

ref = vibss.modes(with_mounts(best))
for scale in (0.5, 2.0):
    md = vibss.modes(all_scaled(with_mounts(best), scale))
    print(f"all mounts x{scale}: f / f_ref = {np.round(md.frequency_hz / ref.frequency_hz, 4)}, "
          f"largest energy change {np.abs(md.energy - ref.energy).max():.1e}")
for scale in (0.5, 1.0, 2.0):
    md = vibss.modes(with_mounts(best, scale))
    k, share = roll_mode(md)
    print(f"engine mounts x{scale}: roll mode {md.frequency_hz[k]:5.2f} Hz, {100 * share:.1f} % roll")"""),
    ("md", """The kinetic-energy distribution and the roll mode at the best angle:"""),
    ("code", """md = vibss.modes(with_mounts(best))
plot_energy(md)"""),
    ("code", """plot_modes(md, which=[roll_mode(md)[0]], view="three")"""),
]

DESIGN = [
    ("md", """# Designing a powertrain mount system

The example powertrain (175 kg, a full inertia tensor, two V-inclined engine mounts, a gearbox mount
and a torque strut) is not decoupled: its roll mode keeps only 60 % of its kinetic energy about the
torque-roll axis (TRA). We (1) find the axes, (2) certify the layout, (3) optimise rates, positions
and the V angle so every rigid-body mode is at least 90 % pure in TRA axes within 5 ... 18.9 Hz
(idle 800 rpm, second order 26.7 Hz, divided by √2), (4) check the optimum under ±15 % rate
tolerance."""),
    ("code", """%matplotlib inline
import numpy as np
import vibss
from vibss import design
from vibss.design import plot_design_axes

pt = vibss.load_example("powertrain")
windows = (5.0, 26.7 / np.sqrt(2))
plot_design_axes(pt)"""),
    ("md", """## 1-2. Axes and certificate

The TRA is the direction of J⁻¹e (e the crank axis). The static rotation under a pure torque is
11.5° away from it, and the mounts have no elastic centre: the layout is not focalised."""),
    ("code", """cert = design.certificate(pt, purity=0.9, windows=windows, frame="tra")
print(cert.summary())
cert.plot()"""),
    ("md", """## 3. Optimization with exact gradients

Fifteen variables: the three rates of the engine-mount pair (kept symmetric), of the gearbox mount
and of the torque strut (×0.5 ... ×2), the height and spread of the engine pair, the V angle, the
gearbox mount's x and z and the strut's z (±30 mm, ±20°). SLSQP with the analytic gradients of
the purities and frequencies."""),
    ("code", """from vibss.design.optimize import benchmark_case

model, variables, options = benchmark_case()
opt = design.optimize(model, variables, **options)
print(opt.comparison())
opt.plot()"""),
    ("md", """## 4. Tolerance check: ±15 % on every rate

Twenty thousand variants, Latin hypercube, solved as one batch."""),
    ("code", """tol = {f"{m.name}.k{j}": 0.15 for m in opt.model.mounts for j in (1, 2, 3)}
mc = design.monte_carlo(opt.model, tol, n=20_000, purity=0.9, windows=windows, frame="tra")
print(mc.summary())
mc.plot()"""),
    ("md", """The optimum put the first mode on the 5 Hz edge of its window, and three modes just above
90 %: under tolerance only about 28 % of the variants meet every target. A robust layout asks for
margins: optimise again for 5.5 ... 18 Hz and a 93 % purity floor, then check."""),
    ("code", """robust = design.optimize(model, variables, frame="tra", windows=(5.5, 18.0), purity=0.93)
mc2 = design.monte_carlo(robust.model, tol, n=20_000, purity=0.9, windows=windows, frame="tra")
print(f"P(all targets) {mc.probability['all']:.2f} -> {mc2.probability['all']:.2f}")"""),
]

CONTROL = [
    ("md", """# Active isolation of a precision platform

A 500 kg optical table on four air springs (1.1-1.5 Hz) amplifies floor vibration about 15 times at
its suspension resonances. Beside each isolator axis sits a voice-coil actuator (300 Hz bandwidth)
and a geophone: twelve collocated pairs. We build the control plant from the model file, close
skyhook loops, check stability and margins, compare with an H-infinity design, and try a
semi-active variable damper on a single-DOF isolator."""),
    ("code", """%matplotlib inline
import numpy as np
import vibss
import vibss.control as vc

m = vibss.load_example("platform")
ground = ["ground.x.vel", "ground.y.vel", "ground.z.vel"]
table = ["table.x.vel", "table.y.vel", "table.z.vel"]
P = vc.plant(m, ground, performance=table)         # measurements: the 12 geophones
P.groups["u"][:3], P.nstates"""),
    ("md", """## Skyhook: a damper to an inertial reference

Each actuator pushes against its own geophone's velocity, u = -c v. With ideal collocated pairs the
loop cannot go unstable; the actuators' 300 Hz lag only trims the phase far above the loop's band."""),
    ("code", """K = vc.skyhook(P, gains=1200.0)           # N s/m per loop
cl = vc.close(P, K)
print(cl.margin_table())
cl.plot_transmissibility(ground, table, np.geomspace(0.3, 30, 400))"""),
    ("md", """## H-infinity, weights named after the goals

The performance outputs are the table's six velocities and the twelve actuator commands; the
weights say how much each matters. The design model leaves the actuator lags out
(`ideal_actuators=True`); the loop is then closed on the full plant to check it."""),
    ("code", """perf = [f"table.{d}.vel" for d in ("x", "y", "z", "rx", "ry", "rz")]
design = vc.plant(m, ground, performance=perf + [a.command for a in m.actuators], noise=1e-2,
                  ideal_actuators=True)
weights = {**{s: 1.0 for s in perf}, "table.x.vel": 2.0, "table.y.vel": 2.0,
           **{a.command: 1.6e-3 for a in m.actuators}}
Kh = vc.hinf(design, weights)
clh = vc.close(P, Kh)
print(f"gamma {Kh.design['gamma']:.3f}; worst gain margin {min(x.gain_margin_db for x in clh.margins):.1f} dB")
for name, loop in (("skyhook", cl), ("H-infinity", clh)):
    passive, active = loop.transmissibility(ground, table, np.geomspace(0.3, 30, 400))
    k = np.abs(passive.response[2, 2]).argmax()
    print(f"{name}: bounce |T| {abs(passive.response[2, 2, k]):.1f} -> {abs(active.response[2, 2, k]):.2f}")
clh.plot_transmissibility(ground, table, np.geomspace(0.3, 30, 400))"""),
    ("md", """## Semi-active: clipped skyhook on one isolator

A variable damper can only dissipate. The clipped law gives the skyhook force when the damper can,
the least damping otherwise; the damper power is never positive."""),
    ("code", """t = vibss.MountType("iso", [1e4] * 3, [0.0] * 3)
one = vibss.Model([vibss.Body("b", 10.0, [1, 1, 1])], [vibss.Mount("m", t, "b")],
                  actuators=[vibss.Actuator("d", mount="m", axis=3)],
                  sensors=[vibss.Sensor("v", "velocity", body="b", direction=[0, 0, 1]),
                           vibss.Sensor("rv", "relative_velocity", mount="m", axis=3)])
Ps = vc.plant(one, ["ground.z.vel"], performance=["b.z.vel"], dofs=["b.z"])
r = vc.clipped_skyhook(Ps, {"ground.z.vel": vibss.HalfSine(0.2, duration=0.02)}, end=1.0, step=1e-3,
                       c_sky=400.0, c_min=5.0, c_max=300.0)
print(r.report())
import matplotlib.pyplot as plt
fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 4.5))
a1.plot(r.time, r["b.z.vel"]); a1.set_ylabel("body velocity [m/s]")
a2.plot(r.time, r.damping[0]); a2.set_ylabel("damping used [N s/m]"); a2.set_xlabel("time [s]")
a1.grid(alpha=0.3); a2.grid(alpha=0.3)"""),
]

INSIGHT = [
    ("md", """# From "this resonance is too high" to the mount to change and a controller that survives

A car powertrain (the `powertrain` example: one rigid body on two engine mounts, a gearbox mount and
a torque strut). The alternator bracket shakes too much under the engine's roll torque. We ask, in
order: which frequency, which mode, which mount, which path; what a passive change does; and
whether an active loop at the engine mounts still holds when every mount rate is ±20 % off."""),
    ("code", """%matplotlib inline
import dataclasses
import numpy as np
import matplotlib.pyplot as plt
import vibss
import vibss.control as vc
from vibss import Actuator, Sensor

model = vibss.load_example("powertrain")
f = np.geomspace(2.0, 40.0, 600)
H = vibss.frequency_response(model, inputs=["powertrain.mx"], outputs=["alternator.z"], frequencies=f)
h = np.abs(H["alternator.z", "powertrain.mx"])
k = int(np.argmax(h))
print(f"largest |alternator.z / powertrain.mx| = {h[k]:.3g} m/(N m) at {f[k]:.2f} Hz")"""),
    ("md", """## Which mode? Modal contributions

The response split into one term per mode (plus a residual), summing to the exact FRF."""),
    ("code", """c = vibss.modal_contributions(model, ["powertrain.mx"], ["alternator.z"], f)
print(c.dominant(top=2).render())"""),
    ("md", """Mode 3 (8.3 Hz) makes the peak. **Which mount?** Its strain energy per mount and per local axis:"""),
    ("code", """strain = vibss.energy_distribution(model, "strain")
print(strain.table().render())
strain.plot(by_axis=True)                   # returns the Figure, shown inline"""),
    ("md", """Mode 3 stores 41 % of its strain energy in `engine.xz` along its local axis 2 and 34 % in
`engine` along axis 2: the two engine mounts' lateral rates carry it. **Which path** does the force
take into the ground?"""),
    ("code", """p = vibss.path_contributions(model, ["powertrain.mx"], f, receiver="ground")
print(p.table("fz").render())"""),
    ("md", """## The passive change

Dissipation acts where the strain energy is: four times the damping of `engine.xz` (the mount with
the largest share of mode 3) takes the peak down by more than half."""),
    ("code", """xz = {m.name: m for m in model.mounts}["engine.xz"]
damped = dataclasses.replace(xz.type, name="engine.xz damped", damping=4 * xz.type.damping)
model2 = model.replace(mounts=[dataclasses.replace(m, type=damped) if m.name == "engine.xz" else m
                               for m in model.mounts])
H2 = vibss.frequency_response(model2, inputs=["powertrain.mx"], outputs=["alternator.z"], frequencies=f)
h2 = np.abs(H2["alternator.z", "powertrain.mx"])
print(f"peak {h.max():.3g} -> {h2.max():.3g} m/(N m)")
fig, ax = plt.subplots(figsize=(7, 3.8))
ax.loglog(f, h, label="as built"); ax.loglog(f, h2, label="engine.xz damping x4")
ax.set_xlabel("frequency [Hz]"); ax.set_ylabel("|alternator.z / powertrain.mx| [m/(N m)]")
ax.legend(); ax.grid(True, which="both", alpha=0.3)"""),
    ("md", """## An active loop that survives the tolerances

Actuators in parallel with the two engine mounts along their axis 2 (40 Hz bandwidth) and a
collocated geophone each, with a noise floor. `vc.tune` tunes one skyhook gain per loop so that the
alternator's velocity peak falls to 60 % of the passive one and the disk margin stays above 0.5, on
the nominal mounts **and** on the corners of ±20 % on the engine mounts' lateral rates, with the least
actuator effort; `close` verifies it."""),
    ("code", """mounts = {m.name: m for m in model.mounts}
acts, sens = [], []
for name in ("engine", "engine.xz"):
    m, tag = mounts[name], name.replace(".", "_")
    acts.append(Actuator(f"act_{tag}", mount=name, axis=2, bandwidth=40.0))
    sens.append(Sensor(f"geo_{tag}", "velocity", body=m.body, at=m.at, frame=m.frame,
                       direction=m.orientation.matrix[:, 1],
                       noise=([1.0, 10.0, 100.0], [1e-12, 1e-14, 1e-14])))     # (m/s)^2/Hz
active = model.replace(actuators=acts, sensors=sens)
P = vc.plant(active, ["powertrain.mx"], performance=["alternator.z.vel"])
channel = ("powertrain.mx", "alternator.z.vel")
passive_peak = h.max() * 2 * np.pi * f[k]                    # velocity per unit torque, about
goals = [("peak_transmissibility", "<=", 0.6 * passive_peak, channel), ("disk_margin", ">=", 0.5)]
tuned = vc.tune(P, "skyhook", goals, tolerances={"engine.k2": 0.2, "engine.xz.k2": 0.2})
print(tuned.report())"""),
    ("md", """**Does it hold** when every rate of every mount is ±20 % off (12 parameters)? A Monte Carlo of
300 variants plus the corners of the six most sensitive rates, each variant's loop closed exactly
(the rate changes as an internal feedback on the nominal loop)."""),
    ("code", """tol = {f"{m.name}.k{j}": 0.2 for m in model.mounts for j in (1, 2, 3)}
rob = vc.robustness(P, tuned.controller, tol, n=300, channel=channel)
print(rob.table.render())
rob.plot()"""),
    ("md", """## What the geophones' noise costs

The noise budget of the alternator's velocity under a white roll torque of 1 (N m)²/Hz: each source's
share, and the cumulative RMS from the top of the band down."""),
    ("code", """b = tuned.closed.noise_budget(["alternator.z.vel"], np.geomspace(1.0, 100.0, 400),
                             disturbances={"powertrain.mx": 1.0})
print(b.summary().render())
b.plot()"""),
]

TEST_DATA = [
    ("md", """# Test data in, a model out: a supplier's table, a prototype FRF, a flexible floor

An engine (120 kg) sits on four rubber mounts. Three pieces of test data arrive from the lab, and
each one changes the model:

1. the mount supplier's **dynamic-stiffness table** (ISO 10846 style: frequency, storage stiffness
   k′ and loss factor η per axis): we fit a mount law to it;
2. a **measured FRF of the prototype**, delivered as a UFF58 file: we update the mounts' vertical
   rates until the model reproduces it;
3. the structure the engine will stand on is **not rigid**: we couple the source to it by its
   receptance at the mount points and ask which mount carries the vibration into it.

At the end the updated system goes to MATLAB. No real lab here: every "measurement" is synthesised
from a known model plus noise, and the notebook checks that what comes back is that known model."""),
    ("code", """%matplotlib inline
import pathlib, tempfile, warnings
import numpy as np
import matplotlib.pyplot as plt
import vibss
from vibss import Body, ControlPoint, Foundation, Model, Mount, MountType
from vibss.model.rheology import FractionalZener

rng = np.random.default_rng(32)                 # seeded: the same "measurements" every run
workdir = pathlib.Path(tempfile.mkdtemp())"""),
    ("md", """## 1. The supplier's table to a fitted mount

The table below is synthesised: a fractional Zener law (the stiffness rises by a factor two from
static to high frequency, with a broad loss peak) sampled at the preferred third-octave-ish
frequencies 2 to 500 Hz, with 1 % random error on k′ and on η, as a supplier's rig would give.
`vibss.fit_rheology` fits the same kind of law to it; the tolerance is set to 2 % because the data
are only good to about 1 %."""),
    ("code", """truth = FractionalZener(k_0=[1.6e5, 1.6e5, 4.0e5], k_inf=[3.2e5, 3.2e5, 8.0e5],      # N/m
                        tau=[2e-3, 2e-3, 1.5e-3], alpha=[0.5, 0.5, 0.45], band=[2.0, 500.0])
f_table = np.array([2.0, 3.15, 5.0, 8.0, 12.5, 20.0, 31.5, 50.0, 80.0, 125.0, 200.0, 315.0, 500.0])  # Hz
k_true = truth.dynamic_stiffness(2 * np.pi * f_table).T                                       # (3, nf) N/m
k_storage = k_true.real * (1 + 0.01 * rng.standard_normal(k_true.shape))                    # k' [N/m]
eta = k_true.imag / k_true.real * (1 + 0.01 * rng.standard_normal(k_true.shape))             # loss factor
fit = vibss.fit_rheology(f_table, k_storage, "fractional", loss_factor=eta, tolerance=0.02)
supplier = MountType("supplier", rheology=fit.rheology)          # the fitted law, ready for a model

off_truth = np.abs(np.log(fit.fitted / k_true)).max(axis=1)      # fit against the noise-free law
print(" axis   k_0 [N/m]  k_inf [N/m]  tau [ms]  alpha  RMS error vs table  max error vs true law")
for a in range(3):
    print(f"   {a + 1}   {fit.rheology.k_0[a]:9.0f}  {fit.rheology.k_inf[a]:11.0f}  {1e3 * fit.rheology.tau[a]:8.2f}"
          f"  {fit.rheology.alpha[a]:5.2f}  {fit.rms_error[a]:18.4f}  {off_truth[a]:21.4f}")
assert off_truth.max() < 0.02, "the fitted law should follow the true one to about the noise level\""""),
    ("code", """fig = fit.plot()
fig.axes[0].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))   # beside the data
fig"""),
    ("md", """**What it means.** The fitted law passes through the table within its scatter (about 1 %) and,
more to the point, within 1 % of the law the table came from: the noise is not fitted. Its
individual parameters (τ, α) trade off against each other and move more than the curve does, so
judge a fit by its curve and its error per frequency (the bottom panel), not by one parameter.
Axis 3's loss factor sits a few per cent of itself under the table: the fit weighs an error in
loss angle like one in log stiffness, and 0.004 in η is 0.4 % of |k*|. `supplier` is a
`MountType` that every analysis (FRF, time response, modes) can use as it is."""),
    ("md", """## 2. A prototype FRF to updated mount rates

The engine's rigid-body modes lie between 5 and 25 Hz, where the fitted law changes little, so for
updating we take each mount at the band's centre (20 Hz) as a rate k′ with a constant loss factor η
(`vibss.update` fits rates; a fitted law itself cannot be scaled yet). Then the "prototype": the
same engine with its four vertical rates 20 % low, 15 % high, 10 % low and 25 % high (preload and
production spread), its FRF from two force inputs to three accelerometer positions with 1 % complex
noise, written to a UFF58 file and read back as the lab would send it."""),
    ("code", """k20 = supplier.rheology.dynamic_stiffness([2 * np.pi * 20.0])[0]     # (3,) complex N/m at 20 Hz
k_prime, loss = k20.real, k20.imag / k20.real
corners = {"m1": (0.4, 0.3, 0.0), "m2": (-0.4, 0.3, 0.0), "m3": (-0.4, -0.3, 0.0), "m4": (0.4, -0.3, 0.0)}  # m


def engine_on(k3):
    \"\"\"The engine on its four mounts, vertical rates k3 [N/m] (m1..m4).\"\"\"
    mounts = [Mount(n, MountType(f"rubber.{n}", [k_prime[0], k_prime[1], k], loss_factor=loss), "engine", at=a,
                    frame="global") for (n, a), k in zip(corners.items(), k3)]
    engine = Body("engine", 120.0, [4.0, 6.0, 7.0], cog=[0.05, -0.02, 0.25])
    return Model([engine], mounts, [ControlPoint("sensor", "engine", [0.3, 0.2, 0.4], frame="global")],
                 name="engine")


nominal = [k_prime[2]] * 4
true_k3 = [k_prime[2] * s for s in (0.8, 1.15, 0.9, 1.25)]            # the prototype as built
f = np.geomspace(3.0, 60.0, 80)                                        # Hz
inputs, outputs = ["engine.fz", "engine.fx"], ["engine.z", "sensor.z", "sensor.x"]
clean = vibss.frequency_response(engine_on(true_k3), inputs, outputs, frequencies=f)
noise = (rng.standard_normal(clean.response.shape) + 1j * rng.standard_normal(clean.response.shape)) / np.sqrt(2)
lab = vibss.FrequencyResponse.from_measurement(f, clean.response * (1 + 0.01 * noise), inputs, outputs, clean.units)
uff = vibss.io.write_uff(lab, workdir / "prototype.uff")
measured = vibss.io.read_uff(uff)                                      # what the lab hands over
print(f"{uff.name}: {len(measured.outputs)} x {len(measured.inputs)} channels, {measured.frequency_hz.size} "
      f"frequencies, method {measured.method!r}")"""),
    ("code", """result = vibss.update(engine_on(nominal), measured, [f"{n}.k3" for n in corners])
print("mount  start [N/m]  updated [N/m]  std [N/m]  true [N/m]  (updated - true) / std")
for (name, value), t in zip(result.values.items(), true_k3):
    print(f"{name:6} {nominal[0]:12.0f}  {value:13.0f}  {result.std[name]:9.0f}  {t:10.0f}  "
          f"{(value - t) / result.std[name]:+22.2f}")
print("\\nchannel              FRAC before  FRAC after")
for ch, b, a in zip(result.labels, result.correlation_before,
                    result.correlation_after):
    print(f"{ch:20} {b:11.4f}  {a:10.4f}")
assert all(abs(result.values[f"{n}.k3"] - t) < 3 * result.std[f"{n}.k3"] for n, t in zip(corners, true_k3))"""),
    ("code", """fig = result.plot()
for ax in fig.axes:                         # an FRF is displacement per force
    ax.set_ylabel(ax.get_ylabel().replace("[m]", "[m/N]"))
fig"""),
    ("md", """**What it means.** From a start at the supplier's nominal rate, the four rates come back within
their stated standard deviations (0.03 % here) of the rates used to make the "measurement": the
1 % noise costs little because 80 frequencies × 6 channels over-determine 4 rates. The FRAC (1 is
a perfect match of shape and level) rises to 0.9999 on every channel. In a real test the std is
your error bar; when two rates cannot be told apart (mirror-image mounts seen by one channel)
`update` warns and names them."""),
    ("md", """## 3. The same source on a flexible structure

The engine will not stand on rigid ground but on a frame (60 kg) bolted through stiff bushings to a
deck (400 kg) on soft mounts: a second vibss model. `Foundation.from_model` gives that structure's
receptance (displacement per force, x, y, z) at the four points under the engine mounts; in a real
project it would be measured or come from FE. `frequency_response(..., foundation=)` couples the
updated source to it exactly (frequency-based substructuring)."""),
    ("code", """frame = Body("frame", 60.0, [3.0, 5.0, 7.0], cog=[0.0, 0.0, -0.1])
deck = Body("deck", 400.0, [30.0, 50.0, 70.0], cog=[0.0, 0.0, -0.4])
bushings = [Mount(f"b{i}", MountType("bushing", [2e6, 2e6, 4e6], loss_factor=0.1), "frame", at=(x, y, -0.2),
                  frame="global", to="deck") for i, (x, y) in enumerate([(0.6, 0.5), (-0.6, 0.5), (-0.6, -0.5), (0.6, -0.5)])]
feet = [Mount(f"d{i}", MountType("foot", [3e5, 3e5, 8e5], loss_factor=0.15), "deck", at=(x, y, -0.5),
              frame="global") for i, (x, y) in enumerate([(1.0, 0.8), (-1.0, 0.8), (-1.0, -0.8), (1.0, -0.8)])]
points = [ControlPoint(f"p{n}", "frame", a, frame="global") for n, a in corners.items()]
structure = Model([frame, deck], bushings + feet, control_points=points, name="structure")

updated = result.model
fF = np.geomspace(3.0, 100.0, 300)                                    # Hz
floor = Foundation.from_model(structure, {n: f"p{n}" for n in corners}, fF)
on_floor = vibss.frequency_response(updated, ["engine.fz"], ["engine.z", "mount.m1.fz"], foundation=floor)
on_ground = vibss.frequency_response(updated, ["engine.fz"], ["engine.z", "mount.m1.fz"], frequencies=fF)

# an independent check: engine, frame and deck modelled as one system
whole = Model([updated.bodies[0], frame, deck],
              [Mount(m.name, m.type, "engine", at=m.at, frame="global", to="frame") for m in updated.mounts]
              + bushings + feet, control_points=points)
ref = vibss.frequency_response(whole, ["engine.fz"], ["engine.z", "mount.m1.fz"], frequencies=fF)
err = np.abs(on_floor.response[:2] - ref.response).max() / np.abs(ref.response).max()
print(f"coupled by FBS against the whole model: {err:.1e}")
assert err < 1e-9
z_floor, z_ground = np.abs(on_floor["engine.z", "engine.fz"]), np.abs(on_ground["engine.z", "engine.fz"])
print(f"engine.z peak: rigid ground {z_ground.max():.3g} m/N at {fF[z_ground.argmax()]:.1f} Hz, "
      f"on the structure {z_floor.max():.3g} m/N at {fF[z_floor.argmax()]:.1f} Hz")"""),
    ("code", """fig, ax = plt.subplots(figsize=(7, 3.8))
ax.loglog(fF, z_ground, label="on rigid ground")
ax.loglog(fF, z_floor, label="on the frame and deck (FBS)")
ax.loglog(fF, np.abs(on_floor["foundation.m1.z", "engine.fz"]), "--", label="frame under m1")
ax.set_xlabel("frequency [Hz]"); ax.set_ylabel("|z / engine.fz| [m/N]")
ax.grid(True, which="both", alpha=0.3); ax.legend(loc="lower left"); fig.tight_layout()"""),
    ("md", """**Blocked forces** are the source's own property: the forces the engine pushes into its mount
points if they were held fixed. They do not depend on what it stands on, which is why transfer path
analysis starts from them."""),
    ("code", """fb = vibss.blocked_forces(updated, ["engine.fz"], [0.0, 10.0, 20.0, 50.0])
print("blocked |fz| per N of engine.fz [N/N]")
print("mount    0 Hz   10 Hz   20 Hz   50 Hz")
for n in corners:
    print(f"{n:5}" + "".join(f"{v:8.3f}" for v in np.abs(fb[f"{n}.fz", "engine.fz"])))
print(f"sum at 0 Hz: {np.abs(fb.response[2::3, 0, 0]).sum():.3f} (the static force splits over the mounts)")"""),
    ("md", """**Which mount path carries it?** `path_contributions(..., foundation=)` splits the frame's motion
under m1 into one term per mount: the structure's receptance from that mount's point times the
force it puts in. The terms sum to the total (checked)."""),
    ("code", """tpa = vibss.path_contributions(updated, ["engine.fz"], receiver="m1", foundation=floor)
k = int(np.argmax(np.abs(tpa.total[2, 0])))
print(f"frame under m1, z, at its worst peak {fF[k]:.1f} Hz: |total| {abs(tpa.total[2, 0, k]):.3g} m/N")
print("path  |contribution| [m/N]  share [%]")
for q, p in enumerate(tpa.paths):
    print(f"{p:5} {abs(tpa.forces[q, 2, 0, k]):20.3g}  {100 * tpa.share[q, 2, 0, k]:9.0f}")
tpa.plot(component="z")                     # returns the Figure, shown inline"""),
    ("md", """At the worst peak the far corner m4 (the stiffest mount of the prototype) carries more than m1
itself: the frame rocks, so quieting the point under m1 starts at m4. On rigid ground that question
cannot even be asked."""),
    ("md", """## 4. To MATLAB

The updated source as a state space with its signal names and units, plus its second-order
matrices M, C, K and the structural damping matrix H (the mounts' loss factors: K + iH) with the
force and output maps F and Oq. A constant loss factor has no causal time-domain form, so A, B, C, D
leave it out (write_matlab warns); the frequency-domain matrices keep it exactly. In MATLAB:
`s = load('engine_updated.mat'); sys = ss(s.A, s.B, s.C, s.D, 'InputName', s.InputName, 'OutputName', s.OutputName);`
and the damped FRF `s.second_order.Oq * ((s.second_order.K + 1i*s.second_order.H - w^2*s.second_order.M) \\ s.second_order.F)`.
Below, that formula on the file read back, against vibss's own FRF."""),
    ("code", """with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    mat = vibss.io.write_matlab(updated, workdir / "engine_updated.mat", inputs=inputs, outputs=outputs)
print(f"write_matlab: {len(caught)} warning (loss factors not in A, B, C, D)")
back = vibss.io.read_matlab(mat)
so = back.second_order
print(f"{mat.name}: inputs {back.inputs}, outputs {back.outputs}, units {back.output_units}")
print("matrices:", ", ".join(f"{k} {v.shape}" for k, v in so.items() if k in ("M", "C", "K", "H", "F", "Oq")))
w = 2 * np.pi * f
h_file = np.stack([so["Oq"] @ np.linalg.solve(so["K"] + 1j * so["H"] + 1j * wk * so["C"] - wk**2 * so["M"], so["F"])
                   for wk in w], axis=-1)
h_vibss = vibss.frequency_response(updated, inputs, outputs, frequencies=f).response
err = np.abs(h_file - h_vibss).max() / np.abs(h_vibss).max()
print(f"FRF from the file's M, C, K, H against vibss: {err:.1e}")
assert err < 1e-9"""),
]

NONLINEAR = [
    ("md", """# A cabinet on snubbered isolators: the operating point, a shock into the stops, a sine sweep

The example `snubbed_cabinet` is a 40 kg electronics cabinet on four rubber isolators. Each isolator's
rubber stiffens in compression (a progressive force-deflection curve, `curve`) and has snubbers that
close after 4 mm in compression, 6 mm in rebound and 5 mm sideways (`stops`). Three questions:

1. Where does the cabinet sit under its weight, and how does that change its modes?
2. Does a 30 g, 11 ms half-sine shock of the base close the snubbers, and how hard?
3. How does the steady response to a 0.25 g base sine bend when the isolators stiffen?"""),
    ("code", """%matplotlib inline
import dataclasses
import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq
import vibss
from vibss.io.harmonicfile import harmonic_balance_arguments

model = vibss.load_example("snubbed_cabinet")
op = vibss.operating_point(model)
print(op.report())"""),
    ("md", """## The operating point against a hand calculation

The four isolators share the weight, so each carries m g / 4 on its curve. Solve that on the
supplier's table (PCHIP through the same points, N against mm) with `brentq`: the sag and the
clearance left to the compression snubber (4 mm minus the sag) must be what vibss reports."""),
    ("code", """table = np.array([[-4, -300], [-3, -210], [-2, -125], [-1, -60], [0, 0], [1, 60], [2, 120], [4, 240.0]])
curve = PchipInterpolator(table[:, 0], table[:, 1])
sag = brentq(lambda d: curve(d) + 40.0 * 9.81 / 4, -3.9, 0.0)           # mm (negative: compressed)
print(f"sag by hand {sag:.6f} mm, vibss {op['cabinet.z'] * 1e3:.6f} mm")
print(f"clearance left by hand {4 + sag:.6f} mm, vibss {op.clearance['foot.z'] * 1e3:.6f} mm")
print(f"tangent rate by hand {curve.derivative()(sag):.4f} N/mm")"""),
    ("md", """## Tangent modes against the nominal ones

`vibss.modes` on a model with nonlinear mounts analyses the tangent model at the operating point
(its note says so). Beside it, the nominal model: the same isolators with their rates at zero
deflection, without curve or stops. The sag stiffens the vertical rate by 8 %, so bounce and the
rocking modes rise."""),
    ("code", """nominal = dataclasses.replace(model, mounts=tuple(
    dataclasses.replace(m, type=dataclasses.replace(m.type, stops=None, curve=None)) for m in model.mounts))
tangent, plain = vibss.modes(model), vibss.modes(nominal)
print(tangent.note)
for i, (ft, fn) in enumerate(zip(tangent.frequency_hz, plain.frequency_hz), 1):
    print(f"mode {i}: tangent {ft:7.3f} Hz   nominal {fn:7.3f} Hz   ({100 * (ft / fn - 1):+.1f} %)")"""),
    ("md", """## A 30 g half-sine into the snubbers

`vibss.simulate` keeps the linear part in modal form and treats the isolators' nonlinear forces as
local forces (`nonlinear_modal`); every snubber contact is located, not stepped over.
`r.contacts` lists which stops were hit, when, and the peak contact force."""),
    ("code", """shock = vibss.simulate(model, list(model.excitations), outputs=["cabinet.z.rel", "mount.foot.d3"],
                       t_end=0.1, dt=2e-4)
print(shock.method, "|", shock.contacts.table.render())
fig = shock.plot()
fig"""),
    ("md", """## The steady response to a base sine: harmonic balance

The model file asks for a harmonic balance in `[analysis] harmonic_balance` (0.25 g of base
acceleration, 5 to 40 Hz, 11 harmonics): the curve bends over to the right as the isolators stiffen
and the compression snubber closes. Between the turning points three steady states coexist; a slow
upward sweep jumps down at the first, a downward sweep jumps up at the second. Dashed: unstable
(Floquet multipliers of the monodromy matrix)."""),
    ("code", """hb = vibss.harmonic_balance(model, **harmonic_balance_arguments(model.settings["harmonic_balance"],
                                                              model.excitations))
print(hb.turning_table().render())
print(hb.check.text())
fig = hb.plot()
fig"""),
]

NOTEBOOKS = {"frf_transmissibility.ipynb": FRF, "shock_study.ipynb": SHOCK,
             "mount_stiffness_study.ipynb": STIFFNESS, "mount_design.ipynb": DESIGN,
             "active_isolation.ipynb": CONTROL, "insight_engine.ipynb": INSIGHT,
             "test_data.ipynb": TEST_DATA, "nonlinear_cabinet.ipynb": NONLINEAR}


def build(cells: list[tuple[str, str]]) -> nbformat.NotebookNode:
    """A notebook of markdown and code cells, outputs empty."""
    nb = new_notebook(cells=[new_markdown_cell(src) if kind == "md" else new_code_cell(src)
                             for kind, src in cells])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nb.metadata["language_info"] = {"name": "python"}
    return nb


def main() -> None:
    """Write every notebook next to this script."""
    for name, cells in NOTEBOOKS.items():
        nb = build(cells)
        for i, cell in enumerate(nb.cells):   # stable ids keep git diffs small
            cell["id"] = f"{Path(name).stem[:20]}-{i}"
        nbformat.validate(nb)
        nbformat.write(nb, HERE / name)
        print("wrote", HERE / name)


if __name__ == "__main__":
    main()
