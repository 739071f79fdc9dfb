"""Issue 18: model and table files that are hostile or absurd end in one located ModelFileError.

Each case is one finding of the adversarial campaign: before, it ended in a RecursionError, an
OverflowError, Python's "Exceeds the limit (4300 digits)", a hang (``/dev/zero``, a FIFO), a silently
dropped duplicate key, a byte-order mark read as a syntax error, or an absurd value accepted.
"""

from __future__ import annotations

import contextlib
import os
import stat
import threading
import warnings
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import vibss
from vibss import load_model, loads_model
from vibss.errors import ModelError, ModelFileError
from vibss.io import modelfile
from vibss.io.filetable import MAX_DEPTH, MAX_INT_DIGITS
from vibss.model import excitation as excitation_module

BODY = '[[body]]\nname = "b"\nmass = {mass}\ninertia = [1.0, 1.0, 1.0]\n'
MOUNT = ('[[mount_type]]\nname = "t"\nstiffness = [{k}, 1e4, 1e4]\n'
         '[[mount]]\ntype = "t"\nbody = "b"\norientation = {{ euler = [{angle}, 0, 0] }}\n')


def toml(mass: str = "10.0", k: str = "1e4", angle: str = "0") -> str:
    return BODY.format(mass=mass) + MOUNT.format(k=k, angle=angle)


def one_line(err: pytest.ExceptionInfo[BaseException]) -> str:
    text = str(err.value)
    assert "\n" not in text and "Traceback" not in text
    return text


# -- nesting and numbers ---------------------------------------------------------------------------
@pytest.mark.parametrize("fmt,text", [
    ("toml", "[model]\nname = " + "[" * 3000 + "]" * 3000),
    ("toml", "[model]\nname = " + "{ a = " * 2000 + "1" + " }" * 2000),
    ("json", '{"model": {"name": ' + "[" * 100_000 + "]" * 100_000 + "}}"),
    ("json", '{"model": ' + '{"a": ' * 60 + "1" + "}" * 60 + "}"),
])
def test_deep_nesting_is_one_line(fmt: str, text: str) -> None:
    with pytest.raises(ModelFileError, match=f"nested deeper than {MAX_DEPTH} levels") as err:
        loads_model(text, fmt, f"m.{fmt}")
    assert one_line(err).startswith(f"m.{fmt}")


def test_huge_integers_name_file_entry_and_key() -> None:
    # 401 digits: float() overflowed in filetable.numbers (OverflowError, exit 1)
    with pytest.raises(ModelFileError, match=r"m\.toml: body\[1\] \('b'\): mass: an integer with 401 digits"):
        loads_model(toml(mass="1" + "0" * 400), source="m.toml")
    # past Python's 4300-digit limit: "use sys.set_int_max_str_digits()" named neither file nor entry
    with pytest.raises(ModelFileError, match=r"m\.json: body\[1\] \('b'\): mass: an integer with 5001 digits"):
        loads_model('{"body": [{"name": "b", "mass": 1' + "0" * 5000 + ', "inertia": [1, 1, 1]}]}', "json",
                    "m.json")
    with pytest.raises(ModelFileError, match=r"m\.toml: line 5: an integer with more than"):
        loads_model("[model]\nname = 'a'\n" + toml(mass="1" + "0" * 5000), source="m.toml")
    ok = "9" * MAX_INT_DIGITS                            # the largest accepted: then the range check
    with pytest.raises(ModelFileError, match="outside what a rigid-body mount model means"):
        loads_model(toml(mass=ok))


def test_json_duplicate_keys_are_refused() -> None:
    """They were silently taken as the last value."""
    text = '{"body": [{"name": "b", "mass": 1.0, "inertia": [1, 1, 1], "mass": 2.0}]}'
    with pytest.raises(ModelFileError, match=r"m\.json: body\[1\] \('b'\): mass: key given more than once"):
        loads_model(text, "json", "m.json")
    with pytest.raises(ModelFileError, match=r"m\.json: model: key given more than once"):
        loads_model('{"model": {"name": "a"}, "model": {"name": "b"}}', "json", "m.json")


def test_a_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    """'Invalid statement (at line 1, column 1)' before."""
    plain = loads_model(toml())
    for fmt, text in (("toml", toml()), ("json", vibss.dumps_model(plain, "json"))):
        path = tmp_path / f"bom.{fmt}"
        path.write_bytes(b"\xef\xbb\xbf" + text.encode())
        assert load_model(path).bodies[0].mass == plain.bodies[0].mass
    table = tmp_path / "t.csv"
    table.write_bytes(b"\xef\xbb\xbf0, 0\n1, 2\n")
    t, v = excitation_module.read_table_file(table)
    assert t.tolist() == [0.0, 1.0] and v.tolist() == [0.0, 2.0]


# -- absurd values ---------------------------------------------------------------------------------
@pytest.mark.parametrize("kw,match", [
    ({"mass": "1e-300"}, r"body\[1\] \('b'\): mass: 1e-300 \[kg\] is outside .* from 1e-09 to 1e\+10 \[kg\]"),
    ({"mass": "1e12"}, r"mass: 1000000000000.0 \[kg\] is outside"),
    ({"k": "1e-300"}, r"mount_type\[1\] \('t'\): stiffness: .* from 1e-06 to 1e\+20 \[N/m\]"),
    ({"k": "1e30"}, r"stiffness: .* is outside"),
    ({"angle": "-1e20"}, r"mount\[1\]: orientation: euler: angles must lie within \+-360 \[deg\]"),
    ({"angle": "361"}, r"euler: angles must lie within"),
])
def test_absurd_values_are_refused_with_the_range(kw: dict[str, str], match: str) -> None:
    with pytest.raises(ModelFileError, match=match) as err:
        loads_model(toml(**kw))
    one_line(err)


def test_ranges_keep_every_meaningful_model() -> None:
    """Zero stiffness (a free axis), a 1e16 N/m link, a turn of -360 deg and mm units all load."""
    m = loads_model(toml(k="0.0", angle="-360"))
    assert m.mounts[0].type.stiffness[0] == 0.0
    loads_model(toml(k="1e16", angle="360"))
    mm = loads_model('[model]\nunits = { length = "mm" }\n' + toml(k="1e-3"))  # 1 N/m in N/mm
    assert mm.mounts[0].type.stiffness[0] == pytest.approx(1.0)
    for name in vibss.example_names():
        vibss.load_example(name)


def test_a_range_is_printed_in_the_files_units() -> None:
    with pytest.raises(ModelFileError, match=r"from 1e-12 to 1e\+07 \[t\]"):
        loads_model('[model]\nunits = { mass = "t" }\n' + toml(mass="1e8"))


# -- what a file names -----------------------------------------------------------------------------
def _model_with_table(tmp_path: Path, target: str) -> Path:
    path = tmp_path / "m.toml"
    path.write_text(toml() + '[[excitation]]\nname = "e"\nkind = "force"\ntarget = "b"\ndof = "z"\n'
                    f'function = {{ type = "table", file = "{target}" }}\n')
    return path


@pytest.mark.parametrize("special,kind", [("/dev/zero", "a character device"), ("/dev/urandom", "a character device"),
                                          (".", "a directory")])
def test_special_table_files_are_refused_before_they_are_read(tmp_path: Path, special: str, kind: str) -> None:
    """/dev/zero grew to 6.9 GB in 30 s and hung even `vibss modes`."""
    if not os.path.exists(special):
        pytest.skip(f"no {special}")
    with pytest.raises(ModelFileError, match=f"not a regular file \\({kind}\\)") as err:
        load_model(_model_with_table(tmp_path, special))
    assert "excitation[1] ('e'): function" in one_line(err)


def test_fifos_and_links_to_them_are_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    link = tmp_path / "link.csv"
    link.symlink_to(fifo)
    for target in (fifo, link):
        result: list[BaseException] = []
        worker = threading.Thread(target=lambda: _catch(result, _model_with_table(tmp_path, str(target))),
                                  daemon=True)
        worker.start()
        worker.join(10.0)
        assert not worker.is_alive(), "reading a FIFO blocked"
        assert isinstance(result[0], ModelFileError) and "a FIFO" in str(result[0])
    assert "a link to" in str(result[0])
    model = tmp_path / "m.toml"                     # the model file itself: a FIFO named *.toml
    model.unlink()
    os.mkfifo(model)
    with pytest.raises(ModelFileError, match="not a regular file"):
        load_model(model)
    assert stat.S_ISFIFO(os.stat(model).st_mode)


def _catch(out: list[BaseException], path: Path) -> None:
    try:
        load_model(path)
    except BaseException as exc:     # noqa: BLE001 - handed to the test thread
        out.append(exc)


def test_size_limits(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    table = tmp_path / "big.csv"
    table.write_text("".join(f"{i}, {i}\n" for i in range(200)))
    monkeypatch.setattr(excitation_module, "MAX_TABLE_FILE_BYTES", 1000)
    with pytest.raises(ModelFileError, match=r"larger than the limit of 1,000 bytes \(\d,\d{3} bytes\)"):
        load_model(_model_with_table(tmp_path, "big.csv"))
    monkeypatch.setattr(modelfile, "MAX_MODEL_FILE_BYTES", 100)
    path = tmp_path / "m.toml"
    with pytest.raises(ModelFileError, match=r"m\.toml: larger than the limit of 100 bytes"):
        load_model(path)


def test_table_file_numbers_are_finite_and_short(tmp_path: Path) -> None:
    table = tmp_path / "t.csv"
    for bad in ("1, nan", "1, inf", "1, 1" + "0" * 5000):
        table.write_text(f"0, 0\n{bad}\n")
        with pytest.raises(ModelError, match="line 2: expected two numbers"):
            excitation_module.read_table_file(table)


def test_the_loader_never_changes_its_input(tmp_path: Path) -> None:
    path = _model_with_table(tmp_path, "t.csv")
    (tmp_path / "t.csv").write_text("0, 0\n0.1, 1\n")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    load_model(path)
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
    np.testing.assert_array_equal(load_model(path).excitations[0].function.values, [0.0, 1.0])


def test_table_files_are_read_only_by_the_analyses_that_use_them(tmp_path: Path,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """`vibss modes` read (and, for /dev/zero, hung on) an excitation's table file it never uses."""
    from vibss.cli import main

    table = tmp_path / "t.csv"
    table.write_text("0, 0\n0.01, 1\nnot a number here\n")        # broken on line 3
    path = _model_with_table(tmp_path, "t.csv")
    reads: list[str] = []
    real = excitation_module.read_table_file
    monkeypatch.setattr(excitation_module, "read_table_file", lambda p: reads.append(str(p)) or real(p))
    model = load_model(path)
    vibss.modes(model)
    vibss.static(model)
    assert reads == []
    assert main(["modes", str(path)]) == 0 and reads == []
    with pytest.raises(ModelError, match=r"m\.toml: excitation\[1\] \('e'\): function: .*line 3: expected two numbers"):
        vibss.simulate(model, t_end=0.02, dt=1e-3)
    assert reads == [str(table)]
    assert main(["time", str(path), "--end", "0.02", "--step", "0.001"]) == 2


def test_values_that_overflow_in_si_are_refused_in_one_line() -> None:
    """Found by the fuzzer: 1e308 N s/mm is 1e311 N s/m: an overflow warning, then inf."""
    text = '[model]\nunits = { length = "mm" }\n' + toml()
    with _no_warning():
        with pytest.raises(ModelFileError, match=r"mount_type\[1\] \('t'\): stiffness: .* overflows when converted to SI"):
            loads_model(text.replace("[1e4, 1e4, 1e4]", "[1e4, 1e308, 1e4]"))
    shock = (toml() + '[[excitation]]\nkind = "force"\ntarget = "b"\ndof = "z"\n'
             'function = { type = "step", amplitude = 1e308, start = 0.0 }\n')
    with _no_warning():
        with pytest.raises(ModelFileError, match=r"step function: amplitude: 1e\+308 overflows when converted to SI"):
            loads_model('[model]\nunits = { force = "kN" }\n' + shock)
    ok = shock.replace("start = 0.0 }", "start = 0.0, end = inf }").replace("1e308", "1.0")
    assert loads_model('[model]\nunits = { time = "ms" }\n' + ok).excitations[0].function.end == np.inf


@contextlib.contextmanager
def _no_warning() -> Iterator[None]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield
