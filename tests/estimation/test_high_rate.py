"""1-s data in the float POD and the code-bias maps (issue 24, item 5): they read only the
epochs of their sampling.

Authority: the POD's own selection (leopod.estimation.inputs.pod_observations keeps the epochs
on the ``pod.sampling_s`` grid); reading the daily files decimated must give the identical
observations, from a fraction of the memory. Synthetic files (2 h of 1-s data, 8 satellites):
the content does not matter, only which epochs arrive.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.codebias.samples import load_quality
from leopod.estimation.inputs import pod_observations
from leopod.io.netcdf import load_netcdf, on_grid, write_netcdf
from leopod.signals import signal_settings

SIGNALS = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                 "pod_code": ["C1W", "C2W"]}})
T0 = np.datetime64("2019-01-01T00:00", "ns")


def _day(folder, step_s: float, hours: float = 2.0, seed: int = 7):
    """Observation, quality and a-priori files of ``hours`` of data at ``step_s`` [s] (the
    values of the 1-s series at the same epochs whatever the step)."""
    rng = np.random.default_rng(seed)
    n1 = int(hours * 3600)
    times = T0 + np.arange(n1) * np.timedelta64(1, "s")
    sv = [f"G{k:02d}" for k in range(1, 9)]
    shape = (n1, len(sv))
    gap = rng.random(shape) < 0.02
    obs = xr.Dataset({name: (("time", "sv"), np.where(gap, np.nan, base + rng.normal(0, 1, shape)))
                      for name, base in (("L1C", 2.2e7), ("L2W", 2.2e7), ("C1C", 2.2e7),
                                         ("C1W", 2.2e7), ("C2W", 2.2e7))},
                     coords={"time": times, "sv": sv})
    pass_id = np.broadcast_to(np.arange(len(sv)) + 8 * (np.arange(n1)[:, None] // 1800),
                              shape).astype("i4")
    quality = xr.Dataset({"pass_id": (("time", "sv"), np.where(gap, -1, pass_id)),
                          "el_deg": (("time", "sv"), rng.uniform(0, 90, shape)),
                          "az_deg": (("time", "sv"), rng.uniform(0, 360, shape)),
                          "mp_C1W_m": (("time", "sv"), rng.normal(0, 0.1, shape))},
                         coords={"time": times, "sv": sv})
    leo = xr.Dataset({"pos_m": (("time", "xyz"), rng.normal(7e6, 1e3, (n1, 3))),
                      "clk_rx_m": ("time", rng.normal(0, 100, n1))},
                     coords={"time": times, "xyz": ["x", "y", "z"]})
    keep = on_grid(times, step_s)
    paths = {}
    for name, ds in (("obs", obs), ("quality", quality), ("leo", leo)):
        for var in ds.data_vars.values():
            var.attrs.update(units="m", long_name="test value")
        paths[name] = write_netcdf(ds.isel(time=keep), folder / f"{name}_{step_s:g}s.nc",
                                   step="test", inputs=[])
    return paths


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("high_rate")
    return {"1s": _day(folder, 1.0), "30s": _day(folder, 30.0)}


def _observations(paths, step_s):
    obs = load_netcdf(paths["obs"], step_s=step_s)
    quality = load_netcdf(paths["quality"], lazy=True, step_s=step_s)
    leo = load_netcdf(paths["leo"])
    return pod_observations([obs], [quality], [leo], SIGNALS, "G", T0,
                            T0 + np.timedelta64(7200, "s"), 30.0), obs


def test_decimated_read_gives_the_observations_of_the_full_read(files):
    full, full_obs = _observations(files["1s"], None)
    read, read_obs = _observations(files["1s"], 30.0)
    thirty, _ = _observations(files["30s"], None)
    assert full.times.size == 240
    for po in (read, thirty):      # the same POD input from 1-s files and from 30-s data
        np.testing.assert_array_equal(po.times, full.times)
        np.testing.assert_array_equal(po.epoch, full.epoch)
        np.testing.assert_array_equal(po.sat, full.sat)
        np.testing.assert_array_equal(po.pass_index, full.pass_index)
        np.testing.assert_array_equal(po.code_m, full.code_m)
        np.testing.assert_array_equal(po.phase_m, full.phase_m)
        np.testing.assert_array_equal(po.clk_rx_m, full.clk_rx_m)
    # memory as designed: the arrays read are those of the 30-s epochs, 1/30 of the file's
    assert read_obs.sizes["time"] * 30 == full_obs.sizes["time"]
    assert read_obs.nbytes * 29 < full_obs.nbytes


def test_the_read_keeps_the_epochs_that_are_multiples_of_the_step(files):
    # every 45th second of 1-s data (45 s divides the day: multiples since midnight); a 0.5-s
    # step keeps every 1-s epoch; of 30-s data a 45-s step keeps the multiples of 90 s
    assert load_netcdf(files["1s"]["obs"], step_s=45.0).sizes["time"] == 7200 // 45
    assert load_netcdf(files["1s"]["obs"], step_s=0.5).sizes["time"] == 7200
    assert load_netcdf(files["30s"]["obs"], step_s=45.0).sizes["time"] == 80


def test_code_bias_samples_of_1s_data_at_30s_are_those_of_30s_data(files):
    # config code_bias.sampling_s: the maps of 1-s data from the samples of 30-s data
    read = load_quality(files["1s"]["quality"], ["C1W"], step_s=30.0)
    thirty = load_quality(files["30s"]["quality"], ["C1W"])
    xr.testing.assert_identical(read.drop_attrs(), thirty.drop_attrs())
    assert load_quality(files["1s"]["quality"], ["C1W"]).sizes["time"] == 7200
