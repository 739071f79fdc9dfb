"""Parameter-grid runner (:func:`grid_study`): a grid or a table of variants of a model -> any analysis -> one tidy table.

Variants change mount rates, positions and angles by name (:mod:`vibss.design.parameters`), or
anything else through a ``build(model, values) -> Model`` function. The analysis is a name from
:data:`ANALYSES` or any function ``f(model) -> mapping of scalars`` (or one scalar). Each variant
is one row of a :class:`pandas.DataFrame`, in the order of the variants, with the parameter values,
the analysis' outputs and an ``error`` column: a failed variant reports its error there and does not
stop the study.

Runs in-process by default; with ``client=`` on Dask (:mod:`dask.distributed`, the ``dask`` extra):
a :class:`distributed.Client`, a scheduler address (``"tcp://host:8786"``) or ``"local"`` (a
:class:`distributed.LocalCluster` on this machine, closed afterwards). Variants travel in chunks (a
task per variant would cost more than a small model's analysis); results come back as chunks
finish, and the progress display counts them.
"""

from __future__ import annotations

import itertools
import sys

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import integer
from ..errors import ArgumentError, MissingDependencyError, did_you_mean
from ..model.model import Model
from ..results import require_pandas
from .batch import BATCH_RTOL, batch_frequencies, variant_rates
from .parameters import Parameter, apply, parameters_of

__all__ = ["grid_study", "ANALYSES"]

Progress = Callable[[int, int], None]


def _modes(model: Model) -> dict[str, float]:
    from ..modal.api import modes

    return {f"f{i + 1}_hz": float(f) for i, f in enumerate(modes(model).frequency_hz)}


def _certificate(model: Model) -> dict[str, Any]:
    from .certificate import certificate

    c = certificate(model)
    out: dict[str, Any] = {f"f{i + 1}_hz": float(f) for i, f in enumerate(c.frequency_hz)}
    out.update({f"purity{i + 1}": float(p) for i, p in enumerate(c.purity)})
    i = model.body_index(c.body)
    out["sag_z_m"] = float(c.sag_weight[6 * i + 2])
    return out


ANALYSES: dict[str, Callable[[Model], Any]] = {"modes": _modes, "certificate": _certificate}
"""Named analyses: ``"modes"`` (natural frequencies [Hz]) and ``"certificate"`` (frequencies,
purities and vertical sag under weight [m], global frame)."""


def _as_row(out: Any) -> dict[str, Any]:
    if isinstance(out, Mapping):
        return dict(out)
    if np.ndim(out) == 0:
        return {"value": out}
    return {f"value{i}": v for i, v in enumerate(np.ravel(out))}


def _run_chunk(model: Model, params: tuple[Parameter, ...] | None, names: list[str], build: Any,
               analysis: Any, rows: Sequence[tuple[float, ...]]) -> list[dict[str, Any]]:
    """Run the analysis on a chunk of variants (on a worker or in-process)."""
    out = []
    for values in rows:
        try:
            variant = build(model, dict(zip(names, values))) if params is None \
                else apply(model, params, np.asarray(values, float))
            row = _as_row(analysis(variant))
            row["error"] = None
        except Exception as exc:      # a failed variant is reported in its row, never fatal
            row = {"error": f"{type(exc).__name__}: {exc}"}
        out.append(row)
    return out


BATCH = 4096
"""Variants per stacked solve of :func:`_batched_modes` (about 1 kB each at 6 DOF)."""


def _batchable(model: Model) -> bool:
    """Whether every variant's ``"modes"`` row can come from one stacked solve: linear mounts of
    principal rates (no stops or curves, no coupled 6x6 matrix, no frequency-dependent branches),
    whose stiffness :func:`~vibss.design.batch.batch_stiffness` builds as the assembly does."""
    return all(not getattr(m.type, "nonlinear", False) and not m.type.coupled
               and not getattr(m.type, "has_branches", False) for m in model.mounts)


def _batched_modes(model: Model, params: tuple[Parameter, ...], names: list[str],
                   rows: Sequence[tuple[float, ...]]) -> list[dict[str, Any]]:
    """``"modes"`` rows of a chunk of variants by one stacked ``eigh``
    (:func:`~vibss.design.batch.batch_frequencies`): a variant whose every frequency the bound
    certifies to :data:`~vibss.design.batch.BATCH_RTOL` keeps its row; the others (a negative or
    non-finite rate, a mode that may be rigid, a graded model, frequencies over
    :data:`vibss.modal.api.IMPLAUSIBLE_HZ`, which :func:`vibss.modes` warns about) are run by
    :func:`vibss.modes` on the variant itself, as without batching, errors and warnings included."""
    from ..modal.api import IMPLAUSIBLE_HZ

    values = np.asarray(rows, dtype=float).reshape(len(rows), len(params))
    rates, shift, angle = variant_rates(model, params, values)
    sane = (np.isfinite(values).all(axis=1) & (rates >= 0).all(axis=(1, 2)) & np.isfinite(rates).all(axis=(1, 2))
            & np.isfinite(shift).all(axis=(1, 2)) & np.isfinite(angle).all(axis=(1, 2)))
    out: list[dict[str, Any] | None] = [None] * len(rows)
    if np.any(sane):
        f, bound = batch_frequencies(model, params, values[sane])
        good = (bound <= BATCH_RTOL).all(axis=1) & (f <= IMPLAUSIBLE_HZ).all(axis=1)
        labels = [f"f{i + 1}_hz" for i in range(f.shape[1])]
        for v, fv in zip(np.flatnonzero(sane)[good], f[good].tolist()):
            row: dict[str, Any] = dict(zip(labels, fv))
            row["error"] = None
            out[v] = row
    for v in [i for i, r in enumerate(out) if r is None]:
        out[v] = _run_chunk(model, params, names, None, ANALYSES["modes"], [rows[v]])[0]
    return [r for r in out if r is not None]


def _in_process(model: Model, params: tuple[Parameter, ...] | None, names: list[str], build: Any, analysis: Any,
                rows: Sequence[tuple[float, ...]], chunk: int | None, batched: bool,
                report: Progress | None) -> list[dict[str, Any]]:
    """Every variant's row in this process, chunk by chunk (stacked when ``batched``)."""
    total, results = len(rows), []
    size = chunk or (BATCH if batched else max(1, total // 100))
    for start in range(0, total, size):
        results += _batched_modes(model, params or (), names, rows[start:start + size]) if batched else \
            _run_chunk(model, params, names, build, analysis, rows[start:start + size])
        if report:
            report(len(results), total)
    return results


def _stderr_bar(done: int, total: int) -> None:
    width = 30
    full = int(width * done / max(total, 1))
    sys.stderr.write(f"\rstudy [{'#' * full}{'.' * (width - full)}] {done}/{total}")
    if done >= total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _client(client: Any) -> tuple[Any, Any]:
    """(client, what to close afterwards): nothing for the user's client; the client made for an
    address; the client and its cluster for ``"local"``."""
    try:
        import distributed
    except ImportError:
        raise MissingDependencyError("grid_study(client=...) needs dask.distributed, an optional dependency: "
                                     "pip install 'vibss[dask]'", argument="client") from None
    if isinstance(client, distributed.Client):
        return client, None
    if client == "local":
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None)
        return distributed.Client(cluster), cluster
    if isinstance(client, str):
        made = distributed.Client(client)
        return made, made
    raise ArgumentError(f"grid_study: client: expected a distributed.Client, a scheduler address or 'local', "
                        f"got {client!r}", argument="client", received=client)


def grid_study(model: Model, analysis: Any = "modes", *, grid: Mapping[Any, Sequence[float]] | None = None,
               table: Mapping[Any, Sequence[float]] | None = None, build: Callable[[Model, dict[str, float]], Model] | None = None,
               client: Any = None, scheduler: str | None = None, chunk: int | None = None,
               progress: bool | Progress = False) -> Any:
    """Run an analysis on every variant of a model; one row per variant.

    Parameters
    ----------
    model : Model
        The base model.
    analysis : {"modes", "certificate"} or callable
        A name from :data:`ANALYSES`, or ``f(model) -> mapping of scalars`` (or a scalar, or an
        array: ``value0, value1 ...``). Must be picklable for Dask (module-level functions are).
    grid : mapping or None
        Parameter to the values it takes; every combination is a variant (full factorial).
        Parameters are ``"<mount>.<kind>"`` / :class:`~vibss.design.parameters.Parameter` (rates
        [N/m], shifts [m] and angles [rad] as in :func:`~vibss.design.parameters.apply`), or any
        names when ``build`` is given.
    table : mapping or None
        Parameter to a column of values (all the same length): one variant per row.
    build : callable or None
        ``build(model, values) -> Model`` making a variant from ``{name: value}`` (any model field);
        default: :func:`~vibss.design.parameters.apply`.
    client : distributed.Client, str or None
        Run on Dask: a client, a scheduler address, or ``"local"`` (a 2-worker LocalCluster, closed
        afterwards); None: in-process.
    scheduler : str or None
        Address of a running Dask scheduler (``"tcp://host:8786"``): the same as
        ``client=address``; give one of the two.
    chunk : int or None
        Variants per Dask task (default: about 8 tasks per worker).
    progress : bool or callable
        Show progress: True for a bar on stderr, or ``f(done, total)``.

    Returns
    -------
    pandas.DataFrame
        One row per variant (index ``variant``): parameter values, outputs, ``error``.

    Examples
    --------
    >>> import vibss
    >>> df = grid_study(vibss.load_example("powertrain"), grid={"engine.k3": [2e5, 3e5], "gearbox.k3": [1e5, 2e5]})
    >>> df.shape, df["f1_hz"].round(3).tolist()
    ((4, 9), [5.513, 5.614, 5.517, 5.621])
    """
    pd = require_pandas()
    if scheduler is not None:
        if client is not None:
            raise ArgumentError("grid_study: give client= or scheduler=, not both", argument="scheduler",
                                received=scheduler)
        if not isinstance(scheduler, str) or not scheduler:
            raise ArgumentError(f"grid_study: scheduler: expected a scheduler address such as "
                                f"'tcp://127.0.0.1:8786', got {scheduler!r}", argument="scheduler",
                                received=scheduler)
        client = scheduler
    if (grid is None) == (table is None):
        raise ArgumentError("grid_study: give exactly one of grid= (every combination) and table= (one "
                            "variant per row)", argument="grid")
    spec = grid if grid is not None else table
    if not isinstance(spec, Mapping) or not spec:
        raise ArgumentError(f"grid_study: grid/table: expected a mapping of parameter to values, got {spec!r}",
                            argument="grid" if grid is not None else "table", received=spec)
    params = parameters_of(model, list(spec)) if build is None else None
    names = [p.name if isinstance(p, Parameter) else str(p) for p in spec]
    columns = [np.atleast_1d(np.asarray(v, dtype=float)) for v in spec.values()]
    if grid is not None:
        rows = list(itertools.product(*[c.tolist() for c in columns]))
    else:
        if len({len(c) for c in columns}) != 1:
            raise ArgumentError("grid_study: table: every column must have the same length, got "
                                f"{[len(c) for c in columns]}", argument="table")
        rows = list(zip(*[c.tolist() for c in columns]))
    batched = client is None and params is not None and analysis in ("modes", _modes) and _batchable(model)
    if isinstance(analysis, str):
        if analysis not in ANALYSES:
            raise ArgumentError(f"grid_study: analysis: unknown {analysis!r}; expected one of {list(ANALYSES)} "
                                "or a function" + did_you_mean(analysis, ANALYSES), argument="analysis",
                                received=analysis, expected=list(ANALYSES))
        analysis = ANALYSES[analysis]
    elif not callable(analysis):
        raise ArgumentError(f"grid_study: analysis: expected a name or a function, got {analysis!r}",
                            argument="analysis", received=analysis)
    report: Progress | None = _stderr_bar if progress is True else (progress or None)
    total = len(rows)
    results: list[dict[str, Any]] = []
    if client is None:
        results = _in_process(model, params, names, build, analysis, rows, chunk, batched, report)
    else:
        cl, cluster = _client(client)
        try:
            workers = max(1, len(cl.scheduler_info().get("workers", {})))
            size = integer(chunk, "chunk", who="study") if chunk else max(1, -(-total // (8 * workers)))
            chunks = [rows[s:s + size] for s in range(0, total, size)]
            # a key of its own: a second study of the same model must not share (and lose) it
            [m_fut] = cl.scatter([model], broadcast=True, hash=False)
            futures = [cl.submit(_run_chunk, m_fut, params, names, build, analysis, c, pure=False) for c in chunks]
            index = {f.key: i for i, f in enumerate(futures)}
            parts: list[list[dict[str, Any]] | None] = [None] * len(futures)
            done = 0
            from distributed import as_completed

            for fut in as_completed(futures):
                parts[index[fut.key]] = fut.result()
                done += len(chunks[index[fut.key]])
                if report:
                    report(done, total)
            results = [r for part in parts for r in (part or [])]
        finally:
            if cluster is not None:             # what this call started, not the user's client
                cl.close()
                if cluster is not cl:
                    cluster.close()
    df = pd.DataFrame([dict(zip(names, r)) for r in rows])
    out = pd.DataFrame(results)
    err = out.pop("error") if "error" in out else pd.Series([None] * total)
    df = pd.concat([df, out], axis=1)
    df["error"] = err.values
    df.index = pd.RangeIndex(total, name="variant")
    return df


