"""Model files written back in the user's units (issue 16 item 3).

The independent references: the example files' own text (the numbers the user typed, read with
tomllib), hand conversions (1 N/mm = 1000 N/m, 1 g = 9.80665 m/s^2, 1 ms = 1e-3 s), and the SI
round trip (the reloaded model's matrices and SI data equal the original's).
"""

from __future__ import annotations

import tomllib
import warnings

import numpy as np
import pytest

import vibss
from vibss.errors import ModelError
from vibss.io.fileunits import powers_of
from vibss.io.modelfile import example_path, loads_model, model_to_dict


@pytest.mark.parametrize("name", vibss.example_names())
def test_every_example_is_written_back_in_its_own_units_and_reads_back_exactly(name: str) -> None:
    original = tomllib.loads(example_path(name).read_text())
    model = vibss.load_example(name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                      # no fallback to SI
        text = vibss.dumps_model(model)
    written = tomllib.loads(text)
    declared = {"angle": "deg", **original["model"].get("units", {})}
    assert {k: v for k, v in written["model"]["units"].items() if k in declared} == declared
    again = loads_model(text)
    a, b = vibss.assemble(model, sparse=False), vibss.assemble(again, sparse=False)
    for k in "MKC":
        np.testing.assert_array_equal(getattr(a, k), getattr(b, k))
    assert model_to_dict(again) == model_to_dict(model)     # every table, in SI, to the last bit
    # the numbers the user typed come back as typed (mount types and bodies are written in full)
    typed = {t["name"]: t for t in original.get("mount_type", [])}
    for t in written.get("mount_type", []):
        for key in ("stiffness", "damping"):
            if key in typed[t["name"]]:
                assert t[key] == pytest.approx(typed[t["name"]][key], rel=1e-15), (t["name"], key)
    for got, typed_body in zip(written["body"], original["body"]):
        assert got["cog"] == pytest.approx(typed_body.get("cog", [0, 0, 0]), rel=1e-15)
    if "gravity" in original["model"]:
        assert written["model"]["gravity"] == pytest.approx(original["model"]["gravity"], rel=1e-15)


def test_other_units_by_hand_conversion() -> None:
    """mm, kN, ms and g: each quantity against its hand conversion, then the SI round trip."""
    box = vibss.Body("box", 20.0, [0.5, 0.6, 0.7])
    rubber = vibss.MountType("rubber", stiffness=[2e5, 2e5, 4e5], damping=[100.0, 100.0, 200.0],
                             rotational_stiffness=[30.0, 30.0, 60.0])
    zener = vibss.MountType("zener", rheology={"type": "zener", "k_0": [1e5, 1e5, 2e5],
                                               "k_inf": [2e5, 2e5, 4e5], "tau": [0.01, 0.01, 0.01]})
    pulse = vibss.Excitation("shock", "acceleration", "ground",
                             vibss.HalfSine(30 * 9.80665, duration=0.011), dof="z")
    model = vibss.Model([box], [vibss.Mount("a", rubber, "box", at=[0.1, 0.2, -0.3]),
                                vibss.Mount("b", zener, "box", at=[-0.1, -0.2, -0.3])],
                        gravity=[0.0, 0.0, -9.80665], excitations=[pulse])
    assert tomllib.loads(vibss.dumps_model(model))["model"]["units"]["length"] == "m"   # Python: SI
    units = {"length": "mm", "force": "kN", "time": "ms", "acceleration": "g"}
    data = tomllib.loads(vibss.dumps_model(model, units=units))
    types = {t["name"]: t for t in data["mount_type"]}
    assert types["rubber"]["stiffness"] == pytest.approx([0.2, 0.2, 0.4])          # kN/mm
    assert types["rubber"]["damping"] == pytest.approx([0.1, 0.1, 0.2])   # 100 N s/m = 0.1 kN ms/mm
    assert types["rubber"]["rotational_stiffness"] == pytest.approx(             # kN mm/deg
        np.array([30.0, 30.0, 60.0]) * np.pi / 180)
    assert types["zener"]["rheology"]["tau"] == pytest.approx([10.0, 10.0, 10.0])   # ms
    assert types["zener"]["rheology"]["k_0"] == pytest.approx([0.1, 0.1, 0.2])
    assert data["model"]["gravity"] == pytest.approx([0.0, 0.0, -1.0])             # g
    assert data["mount"][0]["at"] == pytest.approx([100.0, 200.0, -300.0])          # mm
    shock = data["excitation"][0]["function"]
    assert shock["amplitude"] == pytest.approx(30.0) and shock["duration"] == pytest.approx(11.0)
    again = loads_model(vibss.dumps_model(model, "json", units=units), "json")
    a, b = model_to_dict(model), model_to_dict(again)
    assert a.keys() == b.keys()
    ka, kb = vibss.assemble(model, sparse=False).K, vibss.assemble(again, sparse=False).K
    np.testing.assert_allclose(kb, ka, rtol=1e-15, atol=1e-15 * np.abs(ka).max())


def test_units_argument_is_checked() -> None:
    model = vibss.load_example("prism")
    with pytest.raises(ModelError, match="units"):
        vibss.dumps_model(model, units="imperial")
    with pytest.raises(ModelError, match="length"):
        vibss.dumps_model(model, units={"length": "furlong"})
    assert 'length = "m"' in vibss.dumps_model(load := vibss.load_example("powertrain"), units="SI")
    assert 'angle = "rad"' in vibss.dumps_model(load, units="SI")


@pytest.mark.parametrize("ratio, expected", [(2.5, {"length": -1, "force": 1}), (13.0, {"acceleration": 1}),
                                             (3 * 4.0, {"mass": 1, "length": 2}), (1.0, {})])
def test_powers_are_read_off_the_probe(ratio: float, expected: dict[str, int]) -> None:
    assert powers_of(ratio) == expected


@pytest.mark.parametrize("ratio", [17.0, 2.5000001, np.pi])
def test_a_number_not_linear_in_the_units_is_refused(ratio: float) -> None:
    with pytest.raises(ModelError):
        powers_of(ratio)
