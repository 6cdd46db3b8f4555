"""Map products, stacking, differences, attitude modes and the code correction."""

import dataclasses

import numpy as np
import pytest
import xarray as xr
import yaml
from _synthetic import smooth_map, synthetic_passes

from leopod.codebias.apply import correct_codes, map_correction
from leopod.codebias.estimate import MapSettings
from leopod.codebias.period import estimate_period
from leopod.codebias.products import map_difference, node_vector, stack_maps, statistics_csv
from leopod.codebias.samples import attitude_mode, mp_samples
from leopod.workflow.boundary import REPOSITORY
from leopod.workflow.config import section_defaults, validated

#: The schema's defaults (campaign code_bias section) on a 10° grid.
MAP = MapSettings.from_config(section_defaults("code_bias"))
SETTINGS = dataclasses.replace(MAP, az_step_deg=10.0, el_step_deg=10.0, min_count=50)
T0 = np.datetime64("2021-07-14T00:00:00", "ns")


def quality_day(seed, map_fn=smooth_map, n_passes=300, n_sv=8):
    """A quality-like dataset: passes of the synthetic generator spread over (time, sv)."""
    az, el, mp, key, _, _ = synthetic_passes(n_passes=n_passes, seed=seed)
    mp = mp - smooth_map(az, el) + map_fn(az, el)
    n_time = int(np.ceil(az.size / n_sv))
    grid = {name: np.full((n_time, n_sv), np.nan) for name in ("az", "el", "mp")}
    pid = np.full((n_time, n_sv), -1, dtype=np.int32)
    t_idx, s_idx = np.divmod(np.arange(az.size), n_sv)  # passes interleaved over satellites
    for name, v in (("az", az), ("el", el), ("mp", mp)):
        grid[name][t_idx, s_idx] = v
    pid[t_idx, s_idx] = key
    dims = ("time", "sv")
    return xr.Dataset(
        {"el_deg": (dims, grid["el"]), "az_deg": (dims, grid["az"]),
         "mp_C1W_m": (dims, grid["mp"]), "pass_id": (dims, pid)},
        coords={"time": T0 + np.arange(n_time) * np.timedelta64(30, "s"),
                "sv": [f"G{i + 1:02d}" for i in range(n_sv)]},
        attrs={"codes": "C1W", "title": f"synthetic day {seed}"})


def test_attitude_modes_alternate_at_yaw_flips():
    # Jiang et al. (2023): periods 1 and 3 share the attitude mode, as do 2 and 4
    t = np.array(["2021-06-01", "2021-07-20", "2021-09-01", "2021-11-01"], dtype="datetime64[ns]")
    flips = ["2021-07-14T18:21:00", "2021-08-30T00:00:00", "2021-10-23T00:00:00"]
    assert attitude_mode(t, flips).tolist() == [0, 1, 0, 1]
    assert attitude_mode(t).tolist() == [0, 0, 0, 0]


def test_samples_keep_passes_of_different_days_apart():
    days = [quality_day(1, n_passes=20), quality_day(2, n_passes=20)]
    s = mp_samples(days, "C1W")
    assert np.unique(s.pass_key).size == 40
    with pytest.raises(KeyError, match="synthetic day 1: no variable mp_C2W_m"):
        mp_samples(days, "C2W")


def test_period_maps_per_attitude_mode_and_statistics():
    def mirrored(az, el):  # the pattern seen from the other side after a 180-deg yaw flip
        return smooth_map((az + 180.0) % 360.0, el)

    before, after = quality_day(3), quality_day(4, map_fn=mirrored)
    after = after.assign_coords(time=after.time + np.timedelta64(2, "D"))
    flip = str(after.time.values[0] - np.timedelta64(1, "h"))
    maps, stats = estimate_period([before, after], ["C1W"], SETTINGS, period="2021-07",
                                  satellite="sim", yaw_flips=[flip])
    assert maps.mode.values.tolist() == [0, 1]
    v0, v1 = (node_vector(maps, "C1W", m) for m in (0, 1))
    grid = SETTINGS.grid
    az, el = grid.node_directions()
    for v, truth in ((v0, smooth_map(az, el)), (v1, mirrored(az, el))):
        ok = np.isfinite(v)
        e = v[ok] - truth[ok]
        assert np.sqrt(np.mean((e - e.mean()) ** 2)) < 0.03
    # the MP RMS drops once the map is removed; the statistics table has every band
    s = maps.sel(signal="C1W")
    assert float(s.mp_rms_all_after_m) < 0.6 * float(s.mp_rms_all_before_m)
    csv = statistics_csv(maps).splitlines()
    assert csv[0].startswith("signal,el_min_deg") and len(csv) == 1 + 9 + 1
    assert stats["C1W"].el_deg.size == stats["C1W"].before_m.size


def test_stack_and_difference_remove_the_datum():
    (maps, _) = estimate_period([quality_day(5)], ["C1W"], SETTINGS, period="a", satellite="x")
    other = maps.copy(deep=True)
    other["value_m"] = maps.value_m + 0.7  # another datum, same map
    diff, rms = map_difference(maps, other)
    assert float(rms.sel(signal="C1W", mode=0)) < 1e-12
    assert float(np.nanmax(np.abs(diff.values))) < 1e-12  # mean difference removed
    stacked = stack_maps([maps, other])
    assert np.allclose(stacked.value_m, maps.value_m, equal_nan=True)
    ok = np.isfinite(maps.sigma_m)
    assert np.allclose(stacked.sigma_m.values[ok], maps.sigma_m.values[ok] / np.sqrt(2))
    assert int(stacked["count"].sum()) == 2 * int(maps["count"].sum())


def test_correct_codes_subtracts_the_interpolated_map():
    q = quality_day(6)
    maps, _ = estimate_period([q], ["C1W"], SETTINGS, period="p", satellite="x")
    obs = xr.Dataset({"C1W": q.el_deg * 0 + 2.0e7, "C2W": q.el_deg * 0 + 2.0e7},
                     coords=q.coords)
    fixed, summary = correct_codes(obs, q, maps, ["C1W"], empty_cells="drop")
    have = np.isfinite(obs.C1W.values)
    corr = map_correction(maps, "C1W", q.az_deg.values[have], q.el_deg.values[have], 0)
    got = (obs.C1W.values - fixed.C1W.values)[have]
    ok = np.isfinite(corr)
    assert np.allclose(got[ok], corr[ok])
    assert np.isnan(fixed.C1W.values[have][~ok]).all()  # "drop": no map value, no code
    assert summary["C1W"] == {"corrected": int(ok.sum()), "no_map": int((~ok).sum())}
    assert fixed.C2W.equals(obs.C2W)
    kept, _ = correct_codes(obs, q, maps, ["C1W"], empty_cells="keep")
    assert np.array_equal(kept.C1W.values[have][~ok], obs.C1W.values[have][~ok])
    with pytest.raises(ValueError, match="has no C2W"):
        correct_codes(obs, q, maps, ["C2W"], empty_cells="drop")


def test_settings_from_config():
    # the campaign schema supplies the defaults of the keys a campaign leaves out
    raw = yaml.safe_load((REPOSITORY / "config" / "config.yaml").read_text())
    raw["code_bias"] = {"az_step_deg": 10.0, "min_count": 5}
    cfg = validated(raw)
    s = MapSettings.from_config(cfg["code_bias"])
    assert s.az_step_deg == 10.0 and s.min_count == 5 and s.el_step_deg == 5.0
    assert MapSettings.from_config({"az_step_deg": 10.0, "min_count": 5}) == s


def test_difference_counts_the_zenith_node_once():
    # analytic truth: maps that differ by 1 m at one node only (the zenith, stored once per
    # azimuth) over n nodes: mean difference 1/n, RMS about the mean sqrt(n - 1)/n
    g = dataclasses.replace(MAP, az_step_deg=30.0, el_step_deg=30.0).grid
    dims = ("signal", "mode", "elevation_deg", "azimuth_deg")
    zero = np.zeros((1, 1, g.n_rings + 1, g.n_az))
    coords = {"signal": ["C1W"], "mode": [0], "elevation_deg": g.elevation_deg,
              "azimuth_deg": g.azimuth_deg}
    a = xr.Dataset({"value_m": (dims, zero)}, coords=coords)
    b = a.copy(deep=True)
    b.value_m[0, 0, -1, :] = 1.0
    _, rms = map_difference(a, b)
    n = g.n_nodes
    assert float(rms.squeeze()) == pytest.approx(np.sqrt(n - 1) / n)
