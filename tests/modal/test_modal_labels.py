"""Mode labels name the body on multi-body models (``body2.x``) and stay the direction on one body;
the body is the one holding most of that direction's kinetic energy, computed here from phi o (M phi)."""

from __future__ import annotations

import numpy as np

import vibss
from vibss.model.model import DOF_NAMES


def test_multi_body_labels_name_the_body():
    model = vibss.load_example("two_mass")
    m = vibss.modes(model)
    M = np.asarray(vibss.assemble(model).dense("M"))
    ke = (m.shapes * (M @ m.shapes)).T                                 # (modes, DOFs)
    ke = ke / ke.sum(axis=1, keepdims=True)
    names = [b.name for b in model.bodies]
    for k, (label, d) in enumerate(zip(m.labels, m.directions)):
        body = names[int(np.argmax(ke[k].reshape(len(names), 6)[:, DOF_NAMES.index(d)]))]
        assert label == f"{body}.{d}"
    assert len(set(m.labels)) == len(m.labels)                          # no two modes called "x"
    assert m.labels[0] in m.frequency_table().render() and m.labels[0] in m.report()


def test_single_body_labels_are_the_directions():
    m = vibss.modes(vibss.load_example("prism"))
    assert m.labels == m.directions


def test_figure_titles_use_the_labels():
    from vibss.plotting import mode_title

    m = vibss.modes(vibss.load_example("two_mass"))
    assert mode_title(m, 0).endswith(m.labels[0]) and "." in m.labels[0]


def _frf_resonances_against_modes(model, inputs, outputs, band=None):
    """The FRF's numbered resonances are the modes of vibss.modes (a second, independent eigen-solve
    and labelling of the model): same frequency, number and label; the ones in the band, no others."""
    m = vibss.modes(model)
    r = vibss.frequency_response(model, inputs, outputs, frequencies=band)
    lo, hi = r.frequency_hz.min(), r.frequency_hz.max()
    expected = [k + 1 for k in range(len(m)) if not m.rigid[k] and lo <= m.frequency_hz[k] <= hi]
    assert list(r.mode_numbers) == expected
    assert list(r.mode_labels) == [m.labels[k - 1] for k in expected]
    assert np.allclose(r.natural_hz, m.frequency_hz[np.array(expected) - 1], rtol=1e-9)
    return m, r


def test_frf_resonances_carry_mode_numbers_and_body_labels():
    m, r = _frf_resonances_against_modes(vibss.load_example("two_mass"), ["body1.fz"], ["body1.z", "body2.z"])
    assert len(r.mode_numbers) == len(m) and all("." in x for x in r.mode_labels)
    # a band holding only some modes keeps their numbers (not renumbered from 1)
    f = m.frequency_hz
    _, part = _frf_resonances_against_modes(vibss.load_example("two_mass"), ["body1.fz"], ["body1.z"],
                                            {"f1": 0.5 * (f[5] + f[6]), "f2": 2 * f[-1], "points": 50})
    assert part.mode_numbers[0] == 7
    _, one = _frf_resonances_against_modes(vibss.load_example("prism"), ["prism.fz"], ["prism.z"])
    assert set(one.mode_labels) <= set(DOF_NAMES)                     # one body: the direction alone


def test_transmissibility_and_sweeps_keep_the_mode_numbers():
    from vibss.frequency.sweep import sweep_response, transmissibility

    model = vibss.load_example("powertrain")
    ref = vibss.frequency_response(model, ["powertrain.mx"], ["ground.fz"])
    tr = transmissibility(model, ["powertrain.mx"], ["ground.fz"])
    assert tr.mode_numbers == ref.mode_numbers and tr.mode_labels == ref.mode_labels
    sw = sweep_response(model)
    assert set(sw.mode_numbers) <= set(ref.mode_numbers) and len(sw.mode_labels) == len(sw.mode_numbers)


def _top_numbers(fig):
    """Mode numbers drawn above the magnitude axes (the secondary axis' tick labels), per tick."""
    fig.canvas.draw()
    out = []
    for ax in [c for a in fig.axes for c in a.child_axes]:
        if type(ax).__name__ == "SecondaryAxis":
            lo, hi = sorted(ax.get_xlim())
            out += [t.get_text().strip() for t, v in zip(ax.get_xticklabels(), ax.get_xticks())
                    if t.get_text().strip() and lo <= v <= hi]
    return out


def test_bode_numbers_every_resonance_in_the_band_once():
    model = vibss.load_example("two_mass")
    m = vibss.modes(model)
    r = vibss.frequency_response(model, ["body1.fz"], ["body1.z", "body2.z"])
    fig = r.plot()
    drawn = [int(n) for tick in _top_numbers(fig) for n in tick.split(",")]
    assert sorted(drawn) == [k + 1 for k in range(len(m)) if not m.rigid[k]]
    key = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert [s.split()[1] for s in key] == [m.labels[n - 1] for n in r.mode_numbers]
    # nothing sticks out of the figure (title, numbers and key all inside)
    fig.canvas.draw()
    box = fig.bbox
    for t in [*fig.legends, *(a.title for a in fig.axes)]:
        e = t.get_window_extent()
        assert e.x0 >= box.x0 - 1 and e.x1 <= box.x1 + 1 and e.y0 >= box.y0 - 1 and e.y1 <= box.y1 + 1


def test_numbers_in_one_row_never_touch():
    from vibss.plotting.frequency import _CHAR, _ROW_GAP, _stagger

    rng = np.random.default_rng(3)
    pos = np.sort(rng.uniform(0, 1, 12))
    chars = rng.integers(1, 4, 12)
    rows = _stagger(pos, chars)
    assert rows.max() < 3
    for r in range(3):
        idx = np.flatnonzero(rows == r)
        gaps = np.diff(pos[idx])
        need = _CHAR * 0.5 * (chars[idx][:-1] + chars[idx][1:]) + _ROW_GAP
        # a row is reused below its gap only when every row is taken (the least-bad one)
        crowded = [all(np.any((rows == q) & (pos < pos[j]) & (pos > pos[j] - need.max())) for q in range(3))
                   for j in idx[1:]]
        assert np.all((gaps >= need - 1e-12) | np.array(crowded, dtype=bool))
