"""GRACE reference orbits and K-band range CSVs (LEOGPS example, 2010-07-27): reading, units,
frame and time scale verified on the data, malformed files.

Authorities: the first line of each file (values as written), kinematics (d/dt position =
velocity), the equation of motion in a frame rotating with the Earth (Coriolis and centrifugal
terms) with point-mass + J2 gravity (J2, GM, a_e of IERS Conventions 2010 Table 1.1),
single point positioning from the GRACE-B onboard GPS code in GPS time (RINEX 2 time tags) with
the CODE final orbits/clocks, and the independent K-band range.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from _helpers import assert_format_error, write_lines

from leopod.constants import GM_EARTH_M3_S2, OMEGA_EARTH_RAD_S, R_EARTH_EQUATOR_M
from leopod.gnss.combinations import ionosphere_free
from leopod.gnss.products import GnssProducts
from leopod.gnss.spp import solve_spp
from leopod.io import FormatError
from leopod.io.grace_orbit_csv import (
    read_grace_orbit_csv,
    read_kband_range_csv,
    write_kband_range_csv,
)
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import frequency_hz
from leopod.time.calendar import seconds_since
from leopod.validation.compare import fit_time_offset, interpolate_orbit

DIR = "grace-b_2010-208"
J2_EARTH = 1.0826359e-3   # dynamical form factor, IERS Conventions 2010 Table 1.1


@pytest.fixture(scope="module")
def grace_a(shared_data):
    return read_grace_orbit_csv(shared_data / DIR / "grca_truth.csv")


@pytest.fixture(scope="module")
def grace_b(shared_data):
    return read_grace_orbit_csv(shared_data / DIR / "grcb_truth.csv")


@pytest.mark.shared
def test_first_record_in_si_units(grace_a, grace_b):
    # grca_truth.csv line 1: 27/7/2010,00:00:00,2046.250381,270.772369,6513.38404,
    #                        -72393.98858,-6729.940446,23093.89481  (km, dm/s)
    assert grace_a.sizes["time"] == grace_b.sizes["time"] == 8641
    assert grace_a.time.values[0] == np.datetime64("2010-07-27T00:00:00", "ns")
    assert grace_a.time.values[-1] == np.datetime64("2010-07-28T00:00:00", "ns")
    np.testing.assert_allclose(grace_a.pos_itrf_m.values[0],
                               [2046250.381, 270772.369, 6513384.04], rtol=0, atol=1e-6)
    np.testing.assert_allclose(grace_a.vel_itrf_m_s.values[0],
                               [-7239.398858, -672.9940446, 2309.389481], rtol=0, atol=1e-9)
    assert grace_a.attrs["time_system"] == "GPS"
    assert np.all(np.diff(grace_a.time.values) == np.timedelta64(10, "s"))


@pytest.mark.shared
def test_velocity_unit_is_dm_per_s(grace_a):
    # 4th-order central difference of the km positions vs the velocities x 0.1 (dm/s -> m/s):
    # measured 0.15 mm/s RMS per component (1 mm position resolution / 10 s and the 5th
    # derivative term); a unit mistake would be a factor 10.
    r = grace_a.pos_itrf_m.values
    v = grace_a.vel_itrf_m_s.values[2:-2]
    dr = (-r[4:] + 8 * r[3:-1] - 8 * r[1:-3] + r[:-4]) / (12 * 10.0)
    assert np.sqrt(np.mean((dr - v) ** 2)) < 5e-4
    speed = np.linalg.norm(v, axis=1)
    assert 7.5e3 < speed.min() and speed.max() < 7.8e3   # circular speed at ~455 km altitude


def _gravity_j2(r: np.ndarray) -> np.ndarray:
    """Point-mass + J2 acceleration [m/s^2]: minus the gradient of GM/r (1 - J2 (a/r)^2 P2)."""
    rn = np.linalg.norm(r, axis=1, keepdims=True)
    z2 = (r[:, 2:3] / rn) ** 2
    fac = 1.5 * J2_EARTH * GM_EARTH_M3_S2 * R_EARTH_EQUATOR_M**2 / rn**5
    a_j2 = fac * r * (5 * z2 - np.array([1.0, 1.0, 3.0]))
    return -GM_EARTH_M3_S2 * r / rn**3 + a_j2


@pytest.mark.shared
def test_frame_is_earth_fixed(grace_a):
    # In a frame rotating with the Earth, r'' = g - 2 w x v - w x (w x r). With J2 gravity the
    # residual is the higher-degree field (measured 0.11 mm/s^2 RMS); without the rotation
    # terms (inertial frame) it is the Coriolis term, 2 w v ~ 1.1 m/s^2 (measured 0.56 RMS).
    r = grace_a.pos_itrf_m.values
    v = grace_a.vel_itrf_m_s.values[2:-2]
    acc = (-r[4:] + 16 * r[3:-1] - 30 * r[2:-2] + 16 * r[1:-3] - r[:-4]) / (12 * 10.0**2)
    w = np.array([0.0, 0.0, OMEGA_EARTH_RAD_S])
    g = _gravity_j2(r[2:-2])
    rotating = g - 2 * np.cross(w, v) - np.cross(w, np.cross(w, r[2:-2]))
    assert np.sqrt(np.mean((acc - rotating) ** 2)) < 1e-3
    assert np.sqrt(np.mean((acc - g) ** 2)) > 0.3


@pytest.mark.shared
def test_time_scale_is_gps_from_onboard_code(shared_data, grace_b):
    # SPP from 30 min of the GRACE-B ionosphere-free P1/P2 code (RINEX 2 time tags = GPS time,
    # CODE final SP3 orbits and clocks, IGS05). Measured: its positions are 1.4 m (median)
    # from grcb_truth.csv and the timing offset that best aligns the truth with them is 7 us
    # (bound 1 ms = 7.6 m along-track); a UTC-labelled file would be 15 s (GPS - UTC in 2010,
    # IERS Bulletin C), i.e. 114 km, off.
    obs = read_rinex_obs(shared_data / DIR / "GRCB2080.10D").isel(time=slice(0, 180))
    sp3 = read_sp3(shared_data / DIR / "COD15942.EPH")
    ref = np.datetime64("2010-07-27", "ns")
    products = GnssProducts.from_datasets(sp3, sp3, ref)
    code = ionosphere_free(obs.P1.values, obs.P2.values, frequency_hz("G", "1"),
                           frequency_hz("G", "2"))
    spp = solve_spp(seconds_since(obs.time.values, ref), obs.sv.values, code, products)
    ok = np.isfinite(spp.pos_m).all(axis=1)
    assert ok.sum() > 150
    truth = interpolate_orbit(grace_b, obs.time.values[ok])
    dist = np.linalg.norm(spp.pos_m[ok] - truth.pos_itrf_m.values, axis=1)
    assert np.median(dist) < 5.0
    kinematic = xr.Dataset({"pos_itrf_m": (("time", "xyz"), spp.pos_m[ok])},
                           coords={"time": obs.time.values[ok], "xyz": ["x", "y", "z"]})
    assert abs(fit_time_offset(kinematic, grace_b)) < 1e-3


@pytest.mark.shared
def test_kband_range_matches_orbits_in_gps_time(shared_data, grace_a, grace_b):
    # |r_A - r_B| from the Bernese orbits vs the K-band-derived distance (started from a POD
    # fix, so a constant offset is expected). Measured: offset 12 mm, 9.9 mm RMS about it,
    # timing offset -1.2 ms from the regression on the range rate (range rate up to 2 m/s, so
    # a 15-s UTC/GPS mix-up would show as metres). Bounds: 3 cm offset, 2 cm RMS, 5 ms.
    kb = read_kband_range_csv(shared_data / DIR / "grc_kb_rng.csv")
    assert kb.sizes["time"] == 8640
    assert kb.range_m.values[0] == pytest.approx(227379.1269, abs=1e-9)   # line 1 of the file
    a = interpolate_orbit(grace_a, kb.time.values)
    b = interpolate_orbit(grace_b, kb.time.values)
    dr = a.pos_itrf_m.values - b.pos_itrf_m.values
    dist = np.linalg.norm(dr, axis=1)
    rate = np.sum(dr * (a.vel_itrf_m_s.values - b.vel_itrf_m_s.values), axis=1) / dist
    res = dist - kb.range_m.values
    assert abs(res.mean()) < 0.03
    assert res.std() < 0.02
    rc, ec = rate - rate.mean(), res - res.mean()
    assert abs(np.sum(rc * ec) / np.sum(rc * rc)) < 5e-3


@pytest.mark.shared
def test_kband_range_written_as_the_file_is(shared_data, tmp_path):
    # authority: the LEOGPS file itself; written back with its 4 decimals, every line has the
    # same date and time text and the same number (the file drops trailing zeros)
    path = shared_data / DIR / "grc_kb_rng.csv"
    write_kband_range_csv(read_kband_range_csv(path), tmp_path / "kb.csv", decimals=4)
    original = [line.strip().split(",") for line in path.read_text().splitlines()
                if line.strip()]
    written = [line.split(",") for line in (tmp_path / "kb.csv").read_text().splitlines()]
    assert [w[:2] for w in written] == [o[:2] for o in original]
    assert [float(w[2]) for w in written] == [float(o[2]) for o in original]


def test_kband_range_round_trip_with_fractional_seconds(tmp_path):
    t = np.datetime64("2022-07-14T23:59:50", "ns") + np.array([0, 5_250_000_000, 10_000_000_000])
    ds = xr.Dataset({"range_m": ("time", [5012.123456, 5012.2, 5011.999999])},
                    coords={"time": t})
    write_kband_range_csv(ds, tmp_path / "r.csv")
    assert (tmp_path / "r.csv").read_text().splitlines()[1] == "14/7/2022,23:59:55.25,5012.200000"
    back = read_kband_range_csv(tmp_path / "r.csv")
    assert np.array_equal(back.time.values, t)
    assert np.allclose(back.range_m.values, ds.range_m.values, atol=5e-7)


# --------------------------------------------------------------------------- malformed files
GOOD = "27/7/2010,00:00:00,2046.250381,270.772369,6513.38404,-72393.98858,-6729.940446,23093.89481"
NEXT = "27/7/2010,00:00:10,1973.726333,264.078653,6536.071383,-72652.59169,-6657.289488,22280.33172"


def test_small_file_round_numbers(tmp_path):
    path = write_lines(tmp_path, [GOOD, NEXT, ""], "orbit.csv")
    ds = read_grace_orbit_csv(path)
    assert ds.sizes["time"] == 2
    assert ds.time.values[1] == np.datetime64("2010-07-27T00:00:10", "ns")
    assert ds.pos_itrf_m.attrs["units"] == "m" and ds.vel_itrf_m_s.attrs["units"] == "m s-1"
    rng = read_kband_range_csv(write_lines(tmp_path, ["27/7/2010,00:00:00.5,227379.1269"],
                                           "kb.csv"))
    assert rng.time.values[0] == np.datetime64("2010-07-27T00:00:00.5", "ns")


@pytest.mark.parametrize("lines,line,field", [
    ([GOOD, NEXT.replace(",22280.33172", "")], 2, "record"),
    ([GOOD, NEXT.replace("1973.726333", "19x3.7")], 2, "x"),
    ([GOOD, NEXT.replace("-6657.289488", "")], 2, "vy"),
    ([GOOD.replace("27/7/2010", "27-7-2010")], 1, "epoch"),
    ([GOOD.replace("27/7/2010", "31/2/2010")], 1, "epoch"),
    ([NEXT, GOOD], 2, "epoch"),
    ([GOOD, GOOD], 2, "epoch"),
])
def test_malformed_orbit_files(tmp_path, lines, line, field):
    path = write_lines(tmp_path, lines, "bad.csv")
    with pytest.raises(FormatError) as excinfo:
        read_grace_orbit_csv(path)
    assert_format_error(excinfo, path, line, field)


def test_file_without_data(tmp_path):
    path = write_lines(tmp_path, ["", "  "], "blank.csv")
    with pytest.raises(FormatError) as excinfo:
        read_kband_range_csv(path)
    assert_format_error(excinfo, path, None, "file")  # blank text: io._text.read_lines
