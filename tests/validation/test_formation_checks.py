"""Baseline checks of a formation pair (leopod.validation.formation).

Authorities: real data — the GRACE-A/B Bernese orbits and the K-band-derived range of
2010-07-27 (../shared/data/grace-b_2010-208; the range agrees with the orbits to 12 mm offset
and 9.9 mm RMS about it, tests/io/test_grace_orbit_csv.py) — and analytic rotations.
"""

from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.grace_orbit_csv import read_grace_orbit_csv, read_kband_range_csv
from leopod.validation.compare import interpolate_orbit
from leopod.validation.formation import (
    baseline_overlap,
    burn_windows,
    difference_rtn,
    formation_day_row,
    formation_table,
    range_residuals,
    rms_rtn,
    sd_residual_rms,
)

DIR = "grace-b_2010-208"


@pytest.mark.shared
def test_range_residuals_of_the_grace_pair(shared):
    data = shared / "data" / DIR
    kb = read_kband_range_csv(data / "grc_kb_rng.csv")
    a = read_grace_orbit_csv(data / "grca_truth.csv")
    b = read_grace_orbit_csv(data / "grcb_truth.csv")
    t = kb.time.values[::3]                                   # every 30 s, as a POD output
    base = (interpolate_orbit(b, t).pos_itrf_m.values - interpolate_orbit(a, t).pos_itrf_m.values)
    res = range_residuals(base, t, kb.range_m.values, kb.time.values)
    assert np.isfinite(res).all()
    assert abs(res.mean() - 0.012) < 0.003 and res.std() < 0.011       # 12 mm, 9.9 mm
    # epochs without a range value are not compared
    half = range_residuals(base, t, kb.range_m.values[::2], kb.time.values[::2])
    assert np.isnan(half[1::2]).all() and np.allclose(half[::2], res[::2])


def test_difference_rtn_is_the_rotated_vector():
    # a difference of +1 m along the leader's velocity direction in the GCRF is T = 1 m
    t = np.datetime64("2022-07-14T06:00", "ns") + np.arange(3) * np.timedelta64(30, "s")
    pos = np.array([[7e6, 0.0, 0.0], [6.9e6, 1e6, 0.0], [6.8e6, 2e6, 1e5]])
    vel = np.array([[0.0, 7.5e3, 0.0], [-1e3, 7.4e3, 10.0], [-2e3, 7.2e3, 100.0]])
    leader = np.concatenate([pos, vel], axis=1)
    t_dir = rtn_matrix(pos, vel)[:, 1]                                    # GCRF unit T
    d_itrf, _ = itrf_to_gcrf(t, t_dir)               # ITRF -> GCRF is a rotation R: use Rᵀ
    rot = np.stack([itrf_to_gcrf(t, np.tile(e, (3, 1)))[0] for e in np.eye(3)], axis=2)
    t_itrf = np.einsum("mji,mj->mi", rot, t_dir)                        # Rᵀ t_dir
    assert np.allclose(difference_rtn(t_itrf, np.zeros((3, 3)), t, leader),
                       [[0.0, 1.0, 0.0]] * 3, atol=1e-12)
    rms = rms_rtn(np.array([[0.0, 3.0, 4.0], [0.0, -3.0, -4.0], [np.nan, 0.0, 0.0]]))
    assert rms == {"R": 0.0, "T": 3.0, "N": 4.0, "3D": 5.0, "n": 2}


def test_formation_table_rows_means_and_counts():
    # analytic: the table carries each day's attributes in its units, means and sample STDs
    # of the daily figures, sums of the counts
    def day(nl, fixed_3d, kin_3d, std):
        base = xr.Dataset(attrs={"wl_fixing_rate": 1.0, "nl_fixing_rate": nl,
                                 "G_nl_fixing_rate": nl, "n_dd_constraints_used": 400,
                                 **{f"{k}_rms_{c}_m": fixed_3d / 1e3 for k in ("float", "fixed")
                                    for c in ("r", "t", "n", "3d")},
                                 "fixed_sd_G_phase_rms_m": fixed_3d / 1e3 + 0.001})
        kin = xr.Dataset(
            {"rms_minus_truth_m": (("system", "ambiguities", "component"),
                                   np.full((1, 2, 4), kin_3d / 1e3))},
            coords={"system": ["G"], "ambiguities": ["float", "fixed"],
                    "component": ["R", "T", "N", "3D"]})
        rng = xr.Dataset({"std_m": ("solution", [std / 1e3])},
                         coords={"solution": ["dynamic DD-fixed"]})
        wrong = {"all": {"wl_wrong": 0, "nl_wrong": 1, "constrained_wrong": 0}}
        return formation_day_row(base, kinematic=kin, ranges=rng, wrong=wrong)

    table, meta = formation_table({"2022-195": day(0.99, 3.0, 15.0, 1.4),
                                   "2022-196": day(0.97, 5.0, 17.0, 1.6)})
    assert meta["dd_nl_rate"][0] == "%" and meta["dynamic_fixed_vs_truth_3d"][0] == "mm"
    assert table.loc["2022-195", "dd_nl_rate"] == pytest.approx(99.0)
    assert table.loc["mean", "dynamic_fixed_vs_truth_3d"] == pytest.approx(4.0)
    assert table.loc["std", "dynamic_fixed_vs_truth_3d"] == pytest.approx(np.sqrt(2.0))
    assert table.loc["mean", "kinematic_G_fixed_minus_truth_3d"] == pytest.approx(16.0)
    assert table.loc["mean", "range_std_dynamic_fixed"] == pytest.approx(1.5)
    assert table.loc["mean", "dd_nl_wrong"] == 2 and np.isnan(table.loc["std", "dd_nl_wrong"])
    assert table.loc["mean", "dd_constraints"] == 800
    assert table.loc["mean", "sd_phase_residual_G_fixed"] == pytest.approx(5.0)
    assert meta["sd_phase_residual_G_fixed"][0] == "mm"
    assert "sd_code_residual_G_fixed" not in table
    # the report page of that table: rates in per cent, mm with two decimals, counts as
    # integers (their mean column the sum), no "nan" but a footnoted dash
    from leopod.plots.pages import formation_html

    page = formation_html(table, meta, "LT-1")
    assert "<th>mean (counts: sum)</th><th>STD</th>" in page
    row = next(r for r in page.split("<tr>") if meta["dd_nl_rate"][1] in r)
    assert "<td>99.0</td><td>97.0</td><td>98.0</td>" in row
    row = next(r for r in page.split("<tr>") if meta["dd_constraints"][1] in r)
    assert "<td>400</td><td>400</td><td>800</td><td class='missing'>" in row
    row = next(r for r in page.split("<tr>") if meta["dynamic_fixed_vs_truth_3d"][1] in r)
    assert "<td>3.00</td><td>5.00</td><td>4.00</td><td>1.41</td>" in row
    assert "nan" not in page


def test_baseline_overlap_on_common_epochs():
    # analytic: two solutions 0.5 mm apart along the leader's velocity over 3 common epochs
    t = np.datetime64("2022-07-14T21:00", "ns") + np.arange(6) * np.timedelta64(30, "s")
    pos = np.tile([7e6, 0.0, 0.0], (6, 1))
    vel = np.tile([0.0, 7.5e3, 0.0], (6, 1))
    leader = np.concatenate([pos, vel], axis=1)
    rot = np.stack([itrf_to_gcrf(t, np.tile(e, (6, 1)))[0] for e in np.eye(3)], axis=2)
    t_itrf = np.einsum("mji,mj->mi", rot, np.tile([0.0, 1.0, 0.0], (6, 1)))   # GCRF +y in ITRF
    base_a = np.tile([100.0, -5000.0, 300.0], (6, 1)) + 5e-4 * t_itrf
    base_b = np.tile([100.0, -5000.0, 300.0], (3, 1))
    base_b[1] = np.nan                                        # not solved: left out
    times, diff = baseline_overlap(t, base_a, t[3:], base_b, leader)
    assert np.array_equal(times, t[[3, 5]])
    assert np.allclose(diff, [[0.0, 5e-4, 0.0]] * 2, atol=1e-9)
    empty_t, empty = baseline_overlap(t[:3], base_a[:3], t[3:], base_b, leader[:3])
    assert empty_t.size == 0 and empty.shape == (0, 3)


def test_burn_windows_mark_the_margin_around_each_burn():
    # analytic: a 60-s burn at 12:00 with a 30-min margin covers 11:30:00-12:31:00
    t0 = np.datetime64("2022-07-14T11:00", "ns")
    t = t0 + np.arange(0, 7200, 30) * np.timedelta64(1, "s")
    burn = SimpleNamespace(start=np.datetime64("2022-07-14T12:00", "ns"),
                           end=np.datetime64("2022-07-14T12:01", "ns"))
    near = burn_windows(t, [burn], half_s=1800.0)
    assert t[near][0] == np.datetime64("2022-07-14T11:30", "ns")
    assert t[near][-1] == np.datetime64("2022-07-14T12:31", "ns")
    assert not burn_windows(t, []).any()


def test_sd_residual_rms_differences_common_epochs_and_satellites():
    # analytic: B - A on the epochs and satellites both solutions used; a residual NaN in
    # either (not used) drops that single difference; per system and observable
    t = np.array(["2022-07-14T00:00", "2022-07-14T00:00:30", "2022-07-14T00:01"],
                 dtype="datetime64[ns]")

    def res(times, sv, phase, code):
        return xr.Dataset({"phase_residual_m": (("time", "sv"), np.asarray(phase, float)),
                           "code_residual_m": (("time", "sv"), np.asarray(code, float))},
                          coords={"time": times, "sv": sv})

    a = res(t, ["C20", "G01", "G02"], [[0.001, 0.002, 0.0], [0.0, 0.001, np.nan],
                                       [0.0, 0.0, 0.0]], np.zeros((3, 3)))
    # B lacks the last epoch and has one more satellite (G03): neither enters
    b = res(t[:2], ["C20", "G01", "G02", "G03"], [[0.004, 0.006, 0.003, 9.0],
                                                  [0.0, 0.005, 0.5, 9.0]],
            [[0.3, 0.0, 0.4, 9.0], [0.0, 0.0, 0.0, 9.0]])
    out = sd_residual_rms(a, b)
    # G phase: SDs 0.004, 0.003, 0.004 (G02 at the second epoch is NaN in A)
    assert out["G_phase"][1] == 3
    assert out["G_phase"][0] == pytest.approx(np.sqrt((0.004**2 + 0.003**2 + 0.004**2) / 3))
    assert out["C_phase"] == (pytest.approx(np.sqrt(0.003**2 / 2)), 2)
    assert out["G_code"] == (pytest.approx(np.sqrt(0.4**2 / 4)), 4)
    assert set(out) == {"C_phase", "C_code", "G_phase", "G_code"}
