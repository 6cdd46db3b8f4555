"""Orbit overlaps of consecutive arcs (Jiang et al. 2023, "Internal consistency validation",
Fig. 13).

Analytic truth: arcs of a circular Kepler orbit displaced by known offsets along its inertial
R, T, N axes; the campaign mean ± STD is checked against numpy on the per-pair values. Real
data: the Swarm-A ESA orbit cut into overlapping 30-h arcs, one of them decimated.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import xarray as xr

from leopod.constants import GM_EARTH_M3_S2
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.netcdf import write_netcdf
from leopod.io.sp3 import read_sp3
from leopod.validation.compare import orbit_from_sp3
from leopod.validation.orbit_statistics import COMPONENTS, statistics_table
from leopod.validation.overlap import overlap, overlap_summary

DAY0 = np.datetime64("2023-01-01T00:00:00", "ns")
HOUR = np.timedelta64(3600, "s")
A_M = 6_878_137.0
N_RAD_S = math.sqrt(GM_EARTH_M3_S2 / A_M**3)   # Kepler's third law
INC_RAD = math.radians(97.4)


def _arc(start, hours: float = 30.0, step_s: float = 10.0, offset_rtn_m=(0.0, 0.0, 0.0),
         itrf_only: bool = False) -> xr.Dataset:
    """A circular-orbit arc (GCRF + ITRF), displaced by ``offset_rtn_m`` in its RTN axes."""
    t_s = np.arange(0.0, hours * 3600.0 + 1e-6, step_s)
    times = np.datetime64(start, "ns") + (t_s * 1e9).astype("timedelta64[ns]")
    u = np.longdouble(N_RAD_S) * (times - DAY0).astype(np.int64).astype(np.longdouble) * 1e-9
    cu, su = np.cos(u).astype(float), np.sin(u).astype(float)
    ci, si = math.cos(INC_RAD), math.sin(INC_RAD)
    pos = A_M * np.stack([cu, su * ci, su * si], axis=1)
    vel = A_M * N_RAD_S * np.stack([-su, cu * ci, cu * si], axis=1)
    pos = pos + np.einsum("nji,j->ni", rtn_matrix(pos, vel), np.asarray(offset_rtn_m))
    pos_itrf, vel_itrf = gcrf_to_itrf(times, pos, vel)
    dims = ("time", "xyz")
    data = {"pos_itrf_m": (dims, pos_itrf), "vel_itrf_m_s": (dims, vel_itrf)}
    if not itrf_only:
        data.update({"pos_gcrf_m": (dims, pos), "vel_gcrf_m_s": (dims, vel)})
    return xr.Dataset(data, coords={"time": times, "xyz": ["x", "y", "z"]})


def _daily_arc(day: int, **kwargs) -> xr.Dataset:
    """30-h arc of day ``day`` (0 = 2023-01-01): 21:00 of the previous day to 03:00 next."""
    return _arc(DAY0 + day * 24 * HOUR - 3 * HOUR, **kwargs)


def test_overlap_recovers_offsets_over_the_common_span():
    # arc b displaced by (1, -2, 3) cm: a - b = (-1, 2, -3) cm over 21:00-03:00 (6 h at 10 s)
    a = _daily_arc(0)
    b = _daily_arc(1, offset_rtn_m=(0.01, -0.02, 0.03))
    ov = overlap(a, b)
    assert ov.time.values[0] == DAY0 + 21 * HOUR
    assert ov.time.values[-1] == DAY0 + 27 * HOUR
    assert int(ov.n_epochs) == 6 * 360 + 1
    np.testing.assert_allclose(ov.diff_rtn_m.values, np.broadcast_to([-0.01, 0.02, -0.03],
                                                                      (2161, 3)), atol=1e-9)
    np.testing.assert_allclose(ov.rms_m.sel(component="3D"), math.sqrt(14) * 0.01, atol=1e-9)
    np.testing.assert_allclose(ov.mean_m.sel(component=["R", "T", "N"]), [-0.01, 0.02, -0.03],
                               atol=1e-9)
    np.testing.assert_allclose(ov.std_m.values, 0.0, atol=1e-9)
    assert ov.attrs["frame"] == "gcrf"


def test_overlap_is_antisymmetric_and_frame_independent():
    a = _daily_arc(0, offset_rtn_m=(0.004, 0.0, 0.0))
    b = _daily_arc(1, offset_rtn_m=(0.0, 0.05, -0.01))
    ab, ba = overlap(a, b), overlap(b, a)
    np.testing.assert_allclose(ab.diff_rtn_m.values, -ba.diff_rtn_m.sel(time=ab.time).values,
                               atol=1e-12)
    # ITRF-only orbits: differences rotated into the same inertial axes (to ITRF round-off)
    itrf = overlap(_daily_arc(0, offset_rtn_m=(0.004, 0.0, 0.0), itrf_only=True),
                   _daily_arc(1, offset_rtn_m=(0.0, 0.05, -0.01), itrf_only=True))
    assert itrf.attrs["frame"] == "itrf"
    np.testing.assert_allclose(itrf.diff_rtn_m.values, ab.diff_rtn_m.values, atol=1e-8)


def test_trim_and_different_sampling():
    # b tabulated at 30 s: interpolated to a's 10-s epochs; 1 h trimmed at both ends
    a = _daily_arc(0)
    b = _daily_arc(1, step_s=30.0, offset_rtn_m=(0.0, 0.0, 0.02))
    ov = overlap(a, b, trim_s=3600.0)
    assert ov.time.values[0] == DAY0 + 22 * HOUR
    assert ov.time.values[-1] == DAY0 + 26 * HOUR
    np.testing.assert_allclose(ov.diff_rtn_m.sel(rtn="N"), -0.02, atol=1e-6)
    assert ov.attrs["trim_s"] == 3600.0
    with pytest.raises(ValueError, match="no common span"):
        overlap(a, b, trim_s=4 * 3600.0)
    with pytest.raises(ValueError, match="trim_s"):
        overlap(a, b, trim_s=-1.0)


def test_campaign_summary_mean_and_std_over_pairs():
    # three pairs with along-track offsets of 1, 2 and 4 cm (plus 5 mm radial on the last)
    arcs = [_daily_arc(0), _daily_arc(1, offset_rtn_m=(0.0, 0.01, 0.0)),
            _daily_arc(2, offset_rtn_m=(0.0, -0.01, 0.0)),
            _daily_arc(3, offset_rtn_m=(0.005, 0.03, 0.0))]
    ovs = [overlap(a, b) for a, b in itertools.pairwise(arcs)]
    summary = overlap_summary(ovs)
    assert list(summary.pair.values) == ["2023-01-02", "2023-01-03", "2023-01-04"]
    assert list(summary.component.values) == list(COMPONENTS)
    rms_t = np.array([0.01, 0.02, 0.04])
    np.testing.assert_allclose(summary.rms_m.sel(component="T"), rms_t, atol=1e-9)
    np.testing.assert_allclose(summary.campaign_rms_mean_m.sel(component="T"), rms_t.mean(),
                               atol=1e-9)
    np.testing.assert_allclose(summary.campaign_rms_std_m.sel(component="T"), rms_t.std(),
                               atol=1e-9)
    rms_3d = np.array([0.01, 0.02, math.hypot(0.005, 0.04)])
    np.testing.assert_allclose(summary.campaign_rms_mean_m.sel(component="3D"), rms_3d.mean(),
                               atol=1e-9)
    table = statistics_table(summary)
    assert list(table.index) == ["2023-01-02", "2023-01-03", "2023-01-04", "campaign mean",
                                 "campaign std"]
    assert table.loc["campaign mean", "rms_T_m"] == pytest.approx(rms_t.mean(), abs=1e-9)
    assert table.loc["2023-01-03", "n_epochs"] == 2161
    with pytest.raises(ValueError, match="labels"):
        overlap_summary(ovs, labels=["x"])


def test_overlap_and_summary_write_to_netcdf_and_csv(tmp_path):
    ov = overlap(_daily_arc(0), _daily_arc(1, offset_rtn_m=(0.0, 0.01, 0.0)))
    summary = overlap_summary([ov], labels=["doy001/doy002"])
    for name, ds in (("pair.nc", ov), ("summary.nc", summary)):
        write_netcdf(ds, tmp_path / name, step="overlap", time_system="GPS")
        with xr.open_dataset(tmp_path / name) as back:
            xr.testing.assert_allclose(back.rms_m.load(), ds.rms_m)
    statistics_table(summary).to_csv(tmp_path / "summary.csv")
    assert (tmp_path / "summary.csv").read_text().splitlines()[1].startswith("doy001/doy002,")


@pytest.mark.shared
def test_swarm_arcs_overlap_at_the_interpolation_level(shared_data):
    # Two overlapping 30-h arcs cut from the ESA Swarm-A orbit; the later one decimated to
    # 30 s, so the overlap measures only the interpolation of a real LEO orbit (0.1 mm RMS
    # for the 10-s Swarm SP3, see test_compare.py): bound 0.2 mm 3D RMS.
    files = sorted((shared_data / "swarm-a_2023-001").glob("SW_OPER_SP3ACOM_2__*.sp3"))
    orbit = xr.concat([orbit_from_sp3(read_sp3(f), "L47") for f in files], dim="time",
                      data_vars="all")
    a = orbit.sel(time=slice(DAY0, DAY0 + 27 * HOUR))
    b = orbit.sel(time=slice(DAY0 + 21 * HOUR, DAY0 + 51 * HOUR)).isel(time=slice(0, None, 3))
    ov = overlap(a, b)
    assert int(ov.n_epochs) == 6 * 360 + 1
    assert float(ov.rms_m.sel(component="3D")) < 2e-4
