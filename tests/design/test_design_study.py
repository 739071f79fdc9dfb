"""vibss.grid_study: grid and table variants, failed variants reported in their row, progress, and the
Dask path (a 2-worker LocalCluster) giving the same table as the in-process one."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import vibss
from vibss.design.parameters import apply, parameters_of
from vibss.errors import ArgumentError


def test_grid_rows_equal_direct_analyses(powertrain):
    df = vibss.grid_study(powertrain, grid={"engine.k3": [2e5, 3e5], "gearbox.z": [-0.01, 0.0, 0.01]})
    assert len(df) == 6 and df["error"].isna().all()
    params = parameters_of(powertrain, ["engine.k3", "gearbox.z"])
    for _, row in df.iterrows():
        f = vibss.modes(apply(powertrain, params, [row["engine.k3"], row["gearbox.z"]])).frequency_hz
        np.testing.assert_allclose(row[[f"f{i}_hz" for i in range(1, 7)]].to_numpy(float), f, rtol=1e-14)


def test_failed_variant_is_reported_in_its_row_and_progress_counts(powertrain):
    seen = []
    df = vibss.grid_study(powertrain, "certificate", table={"engine.k3": [2e5, -1.0, 3e5]}, chunk=1,
                     progress=lambda done, total: seen.append((done, total)))
    assert df["error"].isna().tolist() == [True, False, True]
    assert "stiffness must not be negative" in df.loc[1, "error"]
    assert np.isnan(df.loc[1, "purity1"]) and df.loc[2, "purity1"] > 0.9
    assert seen[-1] == (3, 3)


def test_custom_analysis_and_build(powertrain):
    def heavier(model, values):
        b = model.bodies[0]
        return model.replace(bodies=[vibss.Body(b.name, values["mass"], b.tensor, b.cog)])

    df = vibss.grid_study(powertrain, lambda m: vibss.modes(m).frequency_hz[0], grid={"mass": [175.0, 700.0]},
                     build=heavier)
    # four times the mass with the same inertia: the x-translation mode (nearly pure) halves
    assert df["value"][1] / df["value"][0] == pytest.approx(0.5, rel=0.02)


def test_refusals(powertrain):
    with pytest.raises(ArgumentError, match="exactly one"):
        vibss.grid_study(powertrain, grid={"engine.k3": [1e5]}, table={"engine.k3": [1e5]})
    with pytest.raises(ArgumentError, match="did you mean"):
        vibss.grid_study(powertrain, "mode", grid={"engine.k3": [1e5]})
    with pytest.raises(ArgumentError, match="same length"):
        vibss.grid_study(powertrain, table={"engine.k3": [1e5, 2e5], "gearbox.k3": [1e5]})


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_table(powertrain):
    distributed = pytest.importorskip("distributed")
    grid = {"engine.k3": [2e5, 2.5e5, 3e5], "torque-strut.k1": [8e4, -1.0, 1.2e5], "gearbox.z": [0.0, 0.01]}
    local = vibss.grid_study(powertrain, "certificate", grid=grid)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        remote = vibss.grid_study(powertrain, "certificate", grid=grid, client=client, chunk=4)
    pd.testing.assert_frame_equal(local, remote)
    assert remote["error"].notna().sum() == 6


@pytest.mark.slow
def test_client_local_starts_and_closes_its_own_cluster(powertrain):
    pytest.importorskip("distributed")
    grid = {"engine.k3": [2e5, 3e5]}
    df = vibss.grid_study(powertrain, grid=grid, client="local")
    pd.testing.assert_frame_equal(df, vibss.grid_study(powertrain, grid=grid))


def _per_variant(model, df, names):
    """Each row's frequencies by vibss.modes on the variant itself (the one eigen path: Jacobi SVD)."""
    params = parameters_of(model, names)
    return np.array([vibss.modes(apply(model, params, row[names].to_numpy(float))).frequency_hz
                     for _, row in df.iterrows()])


def test_batched_modes_table_equals_per_variant_modes(powertrain):
    """The stacked-eigh path of grid_study(..., "modes") gives the table vibss.modes gives variant by
    variant (rates, a ratio, a shift and an angle), to 1e-12 relative, and each frequency's error
    against it stays within the batch's own bound (frequency_bound)."""
    from vibss.design.batch import batch_frequencies

    grid = {"engine.k3": [1.5e5, 3e5], "engine.k1/k3": [0.4, 0.7], "gearbox.z": [0.0, 0.02], "gearbox.rx": [0.0, 0.2]}
    df = vibss.grid_study(powertrain, "modes", grid=grid)
    names = list(grid)
    cols = [f"f{i}_hz" for i in range(1, 7)]
    ref = _per_variant(powertrain, df, names)
    got = df[cols].to_numpy(float)
    assert df["error"].isna().all()
    np.testing.assert_allclose(got, ref, rtol=1e-12)
    f, bound = batch_frequencies(powertrain, parameters_of(powertrain, names), df[names].to_numpy(float))
    np.testing.assert_array_equal(f, got)
    assert np.all(np.abs(got - ref) / ref <= bound + 4 * np.finfo(float).eps)   # the reference's own rounding
    assert bound.max() < 1e-12                      # and the bound is tight enough to keep every row


def test_batched_modes_send_doubtful_variants_to_modes(powertrain):
    """A negative rate (an error row, as without batching) and a variant with free motions (a rigid
    mode the bound cannot certify) are run by vibss.modes on the variant itself."""
    off = {f"{m.name}.k{j}": [0.0] for m in powertrain.mounts for j in (1, 2)}
    df = vibss.grid_study(powertrain, "modes", table={"engine.k3": [2e5, -1.0, 2e5], **{k: v * 3 for k, v in off.items()}})
    assert df["error"].isna().tolist() == [True, False, True]
    assert "stiffness must not be negative" in df.loc[1, "error"]
    ref = _per_variant(powertrain, df.loc[[0]], ["engine.k3", *off])
    np.testing.assert_array_equal(df.loc[[0], [f"f{i}_hz" for i in range(1, 7)]].to_numpy(float), ref)
    assert df.loc[0, "f1_hz"] == 0.0              # rigid: exactly zero from the eigen path
