"""The BDS-2 SCB correction of a day of observations (leopod.codebias.scb).

Authority: Wanninger & Beer (2015), Table 2 (the correction at a node is the published value,
added to the observed code), and the ground-receiver relation sin η = (R / r) cos e that
places a nadir angle on a node; codes of GPS, BDS-3 and BDS-2 GEO satellites and all phases
stay as observed.
"""

import numpy as np
import pytest
import xarray as xr

from leopod.codebias.apply import CodeCorrection
from leopod.codebias.scb import NADIR_VARIABLE, correct_bds2_scb
from leopod.workflow.config import section_defaults

R_EARTH, R_MEO, R_IGSO = 6_371_008.8, 27_906e3, 42_164e3
SVS = ["C01", "C08", "C11", "C25", "G07"]          # GEO, IGSO, MEO, BDS-3, GPS


def _nadir_of(el_deg, r_m):
    """Nadir angle at a satellite of radius r seen from the ground at elevation e [deg]."""
    return np.degrees(np.arcsin(R_EARTH / r_m * np.cos(np.radians(el_deg))))


def _day(n=3):
    rng = np.random.default_rng(3)
    obs = xr.Dataset({c: (("time", "sv"), 2.2e7 + rng.normal(0, 10, (n, len(SVS))))
                      for c in ("C2I", "C7I", "C6I", "C1P", "L2I")},
                     coords={"time": np.datetime64("2016-05-01", "ns")
                             + np.arange(n) * np.timedelta64(30, "s"), "sv": SVS})
    # IGSO at e* = 20°, 50°, 90°; MEO at e* = 0°, 30°, 80°; the others anything
    nadir = np.full((n, len(SVS)), 5.0)
    nadir[:, 1] = _nadir_of(np.array([20.0, 50.0, 90.0]), R_IGSO)
    nadir[:, 2] = _nadir_of(np.array([0.0, 30.0, 80.0]), R_MEO)
    return obs, xr.Dataset({NADIR_VARIABLE: (("time", "sv"), nadir)}, coords=obs.coords)


def test_correction_adds_the_published_values_to_bds2_igso_meo_codes_only():
    obs, geometry = _day()
    fixed, summary = correct_bds2_scb(obs, geometry)
    # Wanninger & Beer (2015), Table 2 at the chosen nodes [m]
    igso = {"C2I": [-0.34, -0.04, 0.35], "C7I": [-0.33, -0.03, 0.33], "C6I": [-0.21, -0.04, 0.32]}
    meo = {"C2I": [-0.47, -0.23, 0.97], "C7I": [-0.40, -0.18, 0.64], "C6I": [-0.22, -0.10, 0.36]}
    for code in ("C2I", "C7I", "C6I"):
        delta = fixed[code].values - obs[code].values
        np.testing.assert_allclose(delta[:, 1], igso[code], atol=1e-6)
        np.testing.assert_allclose(delta[:, 2], meo[code], atol=1e-6)
        assert not delta[:, [0, 3, 4]].any()
        assert summary[code]["corrected"] == 6 and summary[code]["no_geometry"] == 0
    for name in ("C1P", "L2I"):                       # B1C is no BDS-2 signal; phases stay
        np.testing.assert_array_equal(fixed[name].values, obs[name].values)
    assert set(summary) == {"C2I", "C7I", "C6I"}


def test_codes_without_geometry_are_dropped_and_no_bds2_needs_no_geometry():
    obs, geometry = _day()
    geometry[NADIR_VARIABLE].values[1, 2] = np.nan
    fixed, summary = correct_bds2_scb(obs, geometry)
    assert np.isnan(fixed.C2I.values[1, 2]) and summary["C2I"]["no_geometry"] == 1
    gps_bds3 = obs.sel(sv=["C25", "G07"])
    same, nothing = correct_bds2_scb(gps_bds3, xr.Dataset())
    assert same is gps_bds3 and nothing == {}
    with pytest.raises(KeyError, match=NADIR_VARIABLE):
        correct_bds2_scb(obs, xr.Dataset(attrs={"title": "quality C2I day"}))


def test_the_switch_is_a_code_bias_setting_on_by_default():
    assert CodeCorrection.from_config(section_defaults("code_bias")).bds2_scb is True
    assert CodeCorrection.from_config({"bds2_scb": False}).bds2_scb is False
