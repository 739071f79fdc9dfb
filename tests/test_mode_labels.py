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


def test_pulses_need_a_duration():
    """Issue 16: HalfSine(amplitude) used to be a silent 1 s 'shock'; the duration is now required, in
    Python and in files (the message names the function and the key)."""
    import pytest

    from vibss import HalfSine, ModelError

    with pytest.raises(ModelError, match="half_sine function: duration: missing"):
        HalfSine(100.0)
    assert HalfSine(100.0, 0.0, 0.011).end_time == pytest.approx(0.011)
    text = ('[[body]]\nname = "b"\nmass = 1.0\ninertia = [1, 1, 1]\n[[mount_type]]\nname = "t"\n'
            'stiffness = [1e4, 1e4, 1e4]\n[[mount]]\nname = "m"\ntype = "t"\nbody = "b"\n'
            '[[excitation]]\nname = "shock"\nkind = "acceleration"\ntarget = "ground"\ndof = "z"\n'
            'function = { type = "half_sine", amplitude = 100.0 }\n')
    with pytest.raises(ModelError, match=r"excitation\[1\] \('shock'\).*duration: missing"):
        vibss.loads_model(text)


def test_no_negative_zeros_in_tables():
    """Issue 16: '-0.0' and 'zeta -0.00000' in tables. Cells that round to zero lose the sign;
    genuine small negatives keep it."""
    from vibss.results import Table

    t = Table(["a", "b"], [["-0.0", "-0.00000 mm"], ["-0.01", "-0e+00"], ["-1e-06", "x-0.0"]])
    assert t.rows == [["0.0", "0.00000 mm"], ["-0.01", "0e+00"], ["-1e-06", "x-0.0"]]
    # the powertrain's energy table printed "-0.0" for a tiny negative share before
    m = vibss.modes(vibss.load_example("powertrain"))
    assert np.any((m.energy < 0) & (m.energy > -5e-4)) and " -0.0" not in m.energy_table().render()


def test_assembly_matrices_cannot_be_changed_from_outside():
    """Issue 18: `K = asm.dense('K'); K *= 4` doubled every later frequency of modes(asm)."""
    import pytest

    asm = vibss.assemble(vibss.load_example("two_mass"), sparse=True)
    before = vibss.modes(asm).frequency_hz
    K = asm.dense("K")
    with pytest.raises(ValueError, match="read-only"):
        K *= 4
    np.testing.assert_array_equal(vibss.modes(asm).frequency_hz, before)
    mine = asm.dense("K").copy()
    mine *= 4                                           # a copy is the user's to change
    assert np.allclose(mine, 4 * asm.dense("K"))
