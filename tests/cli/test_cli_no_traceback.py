"""Issue 18: the command line never shows a traceback (unless asked with --debug).

Before, a deeply nested model file ended in ``RecursionError`` and a 401-digit mass in
``OverflowError``, each a traceback with exit status 1. Now a refusal is one line with exit 2 (model)
or 3 (analysis), and anything unexpected (a bug) is one line asking for a report, exit 70.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from vibss import cli
from vibss.cli import INTERNAL_ERROR, main
from vibss.errors import AnalysisError, MissingDependencyError, ModelError


def _failing(exc: BaseException):
    def build() -> argparse.ArgumentParser:
        parser = real()
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        boom = sub.add_parser("boom")

        def func(args: argparse.Namespace) -> int:
            raise exc
        boom.set_defaults(func=func)
        return parser
    real = cli.build_parser
    return build


@pytest.mark.parametrize("exc,status,start", [
    (ModelError("m.toml: body[1]: mass: must be positive"), 2, "vibss: error in model: m.toml"),
    (AnalysisError("free motion"), 3, "vibss: analysis failed: free motion"),
    (MissingDependencyError("needs pandas: pip install 'vibss[pandas]'"), 2, "vibss: error: needs pandas"),
    (TypeError("unsupported operand"), INTERNAL_ERROR, "vibss: internal error (TypeError: unsupported operand)"),
    (RecursionError("maximum recursion depth exceeded"), INTERNAL_ERROR, "vibss: internal error (RecursionError"),
    (OverflowError("int too large\nto convert"), INTERNAL_ERROR, "vibss: internal error (OverflowError: int too large to convert)"),
    (KeyError("x"), INTERNAL_ERROR, "vibss: internal error (KeyError: 'x')"),
])
def test_every_error_is_one_line_with_its_status(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                                                 exc: BaseException, status: int, start: str) -> None:
    monkeypatch.setattr(cli, "build_parser", _failing(exc))
    assert main(["boom"]) == status
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(start) and "Traceback" not in err
    assert ("please report" in err) == (status == INTERNAL_ERROR)


def test_debug_prints_the_traceback(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr(cli, "build_parser", _failing(ZeroDivisionError("division by zero")))
    assert main(["--debug", "boom"]) == INTERNAL_ERROR
    err = capsys.readouterr().err
    assert err.startswith("Traceback") and "ZeroDivisionError" in err and "please report" in err


def test_interrupt_is_one_line(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr(cli, "build_parser", _failing(KeyboardInterrupt()))
    assert main(["boom"]) == 130
    assert capsys.readouterr().err == "vibss: interrupted\n"


@pytest.mark.parametrize("text", ["[model]\nname = " + "[" * 3000 + "]" * 3000,
                                  '[[body]]\nname = "b"\nmass = 1' + "0" * 400 + "\ninertia = [1, 1, 1]\n"])
def test_the_campaigns_files_exit_2_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str) -> None:
    path = tmp_path / "m.toml"
    path.write_text(text)
    assert main(["modes", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"vibss: error in model: {path}")


def test_a_warning_is_one_line_without_source_or_path(tmp_path, capsys) -> None:
    """Issue 33 item 6: a warning printed the Python source line and the installed package's path."""
    path = tmp_path / "mm.toml"
    path.write_text('[model]\nname = "mm"\nunits = { length = "mm" }\ngravity = [0, 0, -9.81]\n'
                    '[[body]]\nname = "b"\nmass = 10.0\ninertia = [1e5, 1e5, 1e5]\n'
                    '[[mount_type]]\nname = "t"\nstiffness = [10, 10, 20]\n'
                    '[[mount]]\nname = "m"\ntype = "t"\nbody = "b"\nat = [0, 0, 0]\n')
    assert main(["modes", str(path)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vibss: warning: ") and "gravity 9.81 is read in mm/s^2" in err[0]
    assert ".py" not in err[0] and "warnings.warn" not in err[0]
