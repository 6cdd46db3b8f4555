"""Reference orbits from SP3/netCDF files and the daily comparison (issue 8).

Authority: analytic truth — a circular orbit and the same orbit shifted by a known constant
offset along its radial/along-track/cross-track axes (RTN of the inertial state) must give
back exactly that offset; SP3 round trip through leopod's own writer (SP3-d, mm resolution).
"""

import numpy as np
import pytest
import xarray as xr

from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.io.sp3_write import write_sp3
from leopod.validation.reference import compare_day, read_reference_orbit

GM = 3.986004418e14
DAY = np.datetime64("2019-01-02T00:00", "ns")


def _orbit(offset_rtn_m=(0.0, 0.0, 0.0), step_s=30.0, hours=30.0, start_h=-3.0):
    """Circular 7000-km orbit in the GCRF, offset in its RTN axes; ITRF and GCRF states."""
    a = 7.0e6
    n = np.sqrt(GM / a**3)
    t = np.arange(start_h * 3600, (start_h + hours) * 3600 + 1e-6, step_s)
    inc = np.radians(98.0)
    u = n * t
    r_hat = np.stack([np.cos(u), np.sin(u) * np.cos(inc), np.sin(u) * np.sin(inc)], axis=1)
    t_hat = np.stack([-np.sin(u), np.cos(u) * np.cos(inc), np.cos(u) * np.sin(inc)], axis=1)
    n_hat = np.cross(r_hat, t_hat)
    pos = a * r_hat + offset_rtn_m[0] * r_hat + offset_rtn_m[1] * t_hat + offset_rtn_m[2] * n_hat
    vel = a * n * t_hat
    times = DAY + (t * 1e9).astype("timedelta64[ns]")
    pos_itrf, vel_itrf = gcrf_to_itrf(times, pos, vel)
    return xr.Dataset({"pos_itrf_m": (("time", "xyz"), pos_itrf),
                       "vel_itrf_m_s": (("time", "xyz"), vel_itrf),
                       "pos_gcrf_m": (("time", "xyz"), pos),
                       "vel_gcrf_m_s": (("time", "xyz"), vel)},
                      coords={"time": times, "xyz": ["x", "y", "z"]})


def _sp3(orbit: xr.Dataset, path, svs=("L01",)):
    pos = np.repeat(orbit.pos_itrf_m.values[:, None, :], len(svs), axis=1)
    vel = np.repeat(orbit.vel_itrf_m_s.values[:, None, :], len(svs), axis=1)
    write_sp3(xr.Dataset({"pos_m": (("time", "sv", "xyz"), pos),
                          "vel_m_s": (("time", "sv", "xyz"), vel)},
                         coords={"time": orbit.time.values, "sv": list(svs),
                                 "xyz": ["x", "y", "z"]}, attrs={"time_system": "GPS"}), path)


def test_known_offset_recovered_from_an_sp3_reference(tmp_path):
    truth = _orbit(step_s=10.0, hours=24.0, start_h=0.0)
    _sp3(truth, tmp_path / "ref.sp3")
    ref = read_reference_orbit([tmp_path / "ref.sp3"])
    diff = compare_day(_orbit((0.02, -0.05, 0.01)), ref, "2019-002")
    mean = diff.mean_m.sel(period="total")
    # SP3 stores mm: the interpolated reference is good to ~1 mm
    np.testing.assert_allclose([float(mean.sel(component=c)) for c in "RTN"],
                               [0.02, -0.05, 0.01], atol=1.5e-3)
    assert float(diff.rms_m.sel(period="total", component="3D")) == pytest.approx(
        np.sqrt(0.02**2 + 0.05**2 + 0.01**2), abs=2e-3)
    # only the day's epochs of the 30-h arc
    assert int(diff.n_epochs.sel(period="total")) == 2880


def test_netcdf_reference_and_satellite_choice(tmp_path):
    truth = _orbit(step_s=30.0, hours=24.0, start_h=0.0)
    truth.to_netcdf(tmp_path / "ref.nc")
    ref = read_reference_orbit([tmp_path / "ref.nc"])
    diff = compare_day(_orbit(), ref, "2019-002")
    assert float(diff.rms_m.sel(period="total", component="3D")) < 1e-6
    _sp3(truth, tmp_path / "two.sp3", svs=("L01", "L02"))
    with pytest.raises(ValueError, match="name the reference satellite"):
        read_reference_orbit([tmp_path / "two.sp3"])
    assert read_reference_orbit([tmp_path / "two.sp3"], sv="L02").sizes["time"] == 2881
    with pytest.raises(ValueError, match="no satellite L09"):
        read_reference_orbit([tmp_path / "two.sp3"], sv="L09")


def test_reference_outside_the_day_is_an_error(tmp_path):
    truth = _orbit(step_s=30.0, hours=24.0, start_h=0.0)
    truth.to_netcdf(tmp_path / "ref.nc")
    with pytest.raises(ValueError, match="no common span"):
        compare_day(_orbit(start_h=72.0), read_reference_orbit([tmp_path / "ref.nc"]),
                    "2019-005")
    with pytest.raises(ValueError, match="unknown reference-orbit format"):
        read_reference_orbit([tmp_path / "ref.txt"])


def test_a_netcdf_without_an_orbit_is_refused_naming_file_and_variable(tmp_path):
    # an ingest file: positions as pos_m, not the orbit variable pos_itrf_m of a POD product
    path = tmp_path / "2007-080_leo.nc"
    xr.Dataset({"pos_m": (("time", "xyz"), np.zeros((2, 3)))},
               coords={"time": np.array(["2007-03-21T00:00", "2007-03-21T00:00:10"],
                                        dtype="datetime64[ns]")}).to_netcdf(path)
    with pytest.raises(ValueError, match=r"2007-080_leo\.nc: no orbit variable pos_itrf_m"):
        read_reference_orbit([path])
