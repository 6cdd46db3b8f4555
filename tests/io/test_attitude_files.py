"""Attitude quaternion files: the real GRACE SCA1B fixture against its GNV1B orbit, leopod's
CSV / netCDF layout (round trip, malformed files), and the ``file`` law of every step.

Authorities: the GRACE Level 1B Data Product User Handbook (Case et al. 2010, JPL D-22027:
SCA1B record layout, quaternion from the inertial frame to the SRF, +X to the K-band horn, +Z
nadir-ish; GNV1B Earth-fixed orbit), the geometry of the GRACE formation (horns pointed at each
other: +X pitched down by half the angle the ~220 km separation subtends, ~0.9 deg; Tapley et al.
2004), and the independent GNV1B orbit of the same day (GRACE-A 2003-09-14 was the leading
satellite, so its +X points against the velocity).
"""

from __future__ import annotations

import numpy as np
import pytest
from _helpers import assert_format_error, write_lines

from leopod.frames.attitude import nominal_body_axes
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices, itrf_to_gcrf
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes, leo_body_axes_ef
from leopod.frames.quaternion import AttitudeCoverageError, quaternion_from_body_axes
from leopod.io import FormatError
from leopod.io.attitude import (
    GRACE_EPOCH,
    attitude_series,
    load_leo_attitude,
    read_attitude,
    read_attitude_csv,
    read_sca1b,
)
from leopod.io.attitude_write import write_attitude_csv, write_attitude_netcdf

DIR = "grace_l1b_fixture_2003-09-14"


def _gnv1b(path):
    """GNV1B ASCII records: GPS time, Earth-fixed position [m] and velocity [m/s] (Case et
    al. 2010: gps_time GRACE_id coord_ref xpos ypos zpos 3 sigmas xvel yvel zvel 3 sigmas
    qualflg)."""
    lines = path.read_text().splitlines()
    end = next(k for k, s in enumerate(lines) if s.startswith("END OF HEADER"))
    rows = [s.split() for s in lines[end + 1:] if s.strip()]
    assert all(r[2] == "E" for r in rows)                                 # Earth-fixed
    t = GRACE_EPOCH + np.array([int(r[0]) for r in rows]) * np.timedelta64(1, "s")
    v = np.array([[float(x) for x in r[3:15]] for r in rows])
    return t.astype("datetime64[ns]"), v[:, 0:3], v[:, 6:9]


@pytest.fixture(scope="module", params=["A", "B"])
def grace(request, shared_data):
    sat = request.param
    sca = read_sca1b(shared_data / DIR / f"SCA1B_2003-09-14_{sat}_00.asc")
    t, pos, vel = _gnv1b(shared_data / DIR / f"GNV1B_2003-09-14_{sat}_00.asc")
    common = np.isin(t, sca.time.values)
    return sat, sca, t[common], pos[common], vel[common]


def test_sca1b_reads_the_first_record_as_written(shared_data):
    sca = read_sca1b(shared_data / DIR / "SCA1B_2003-09-14_A_00.asc")
    assert sca.sizes["time"] == 60                                       # header record count
    assert sca.time.values[0] == np.datetime64("2003-09-14T00:00:00")    # 116769600 s
    assert sca.time.values[-1] == np.datetime64("2003-09-14T00:04:55")
    q = [0.6001211159413961, -0.2133887325030409, 0.1857303141739774, 0.7482139703579684]
    np.testing.assert_allclose(sca["quat"].values[0], q, rtol=0, atol=1e-9)
    assert int(sca.sca_id[0]) == 4 and sca.attrs["satellite"] == "GRACE A"
    assert int(sca.qualflg[6]) == 0b10000000


def test_sca1b_axes_point_to_the_geocentre_and_along_the_velocity(grace):
    """SRF +Z within 1.1 deg of the geocentre and +X within 1.1 deg of -v (A, leading) or +v
    (B); the angle is the K-band pointing pitch (both about -0.6 to -0.9 deg: horns down)."""
    sat, sca, t, pos, vel = grace
    law = LeoAttitude.of({"attitude": "file", "attitude_file": {"path": "x"}})
    law = law.with_series(attitude_series([sca], max_gap_s=30.0))
    axes = leo_body_axes_ef(law, t, pos, vel)                            # ITRF -> body
    nadir = -pos / np.linalg.norm(pos, axis=1, keepdims=True)
    v_in = nominal_body_axes(pos, vel)[:, 0]                             # along-track unit
    z_deg = np.degrees(np.arccos(np.einsum("ni,ni->n", axes[:, 2], nadir)))
    sign = -1.0 if sat == "A" else 1.0
    x_deg = np.degrees(np.arccos(np.einsum("ni,ni->n", axes[:, 0], sign * v_in)))
    print(f"\nGRACE-{sat} SCA1B vs GNV1B ({t.size} epochs): +Z to geocentre "
          f"{z_deg.min():.3f}..{z_deg.max():.3f} deg, +X to {'-' if sign < 0 else '+'}velocity "
          f"{x_deg.min():.3f}..{x_deg.max():.3f} deg")
    assert z_deg.max() < 1.1 and x_deg.max() < 1.1
    pitch = np.degrees(np.arcsin(np.einsum("ni,ni->n", axes[:, 0], -nadir)))
    assert np.all((pitch > -1.0) & (pitch < -0.5))
    # the other direction of the rotation would be tens of degrees off
    wrong = np.swapaxes(axes, 1, 2)
    assert np.degrees(np.arccos(np.einsum("ni,ni->n", wrong[:, 2], nadir))).min() > 20


def test_modelled_grace_law_matches_the_star_camera(grace):
    """nominal + yaw 180 (A) + pitch -0.8 deg models SCA1B to 0.6 deg per axis. Measured
    over the 5 minutes (relative to nominal, yaw 180 for A; yaw, pitch, roll in deg): A yaw
    0.05..0.17, pitch -0.88..-0.92, roll 0.25..0.42; B yaw -0.10..-0.16, pitch -0.71..-0.62,
    roll 0.04..0.06: the pitch is the horn pointing, the rest attitude-control excursions
    that no law models (why a star-camera file beats the law)."""
    sat, sca, t, pos, vel = grace
    series_law = LeoAttitude.of({"attitude": "file", "attitude_file": {"path": "x"}})
    measured = leo_body_axes_ef(series_law.with_series(attitude_series([sca], max_gap_s=30)),
                                t, pos, vel)
    model = LeoAttitude.of({"attitude": "nominal", "attitude_offset": {
        "yaw_deg": 180.0 if sat == "A" else 0.0, "pitch_deg": -0.8}})
    axes = leo_body_axes_ef(model, t, pos, vel)
    for k in range(3):
        ang = np.degrees(np.arccos(np.clip(np.einsum("ni,ni->n", axes[:, k],
                                                     measured[:, k]), -1, 1)))
        assert ang.max() < 0.6, (sat, k, ang.max())


def test_csv_and_netcdf_round_trip_bit_identical(tmp_path, shared_data):
    sca = read_sca1b(shared_data / DIR / "SCA1B_2003-09-14_B_00.asc")
    t, q = sca.time.values, sca["quat"].values
    csv = write_attitude_csv(tmp_path / "att.csv", t, q, satellite="grace-b")
    back = read_attitude(csv)
    assert np.array_equal(back.time.values, t) and np.array_equal(back["quat"].values, q)
    assert back.attrs["satellite"] == "grace-b"
    nc = write_attitude_netcdf(tmp_path / "att.nc", t, q, satellite="grace-b")
    back = read_attitude(nc)
    assert np.array_equal(back["quat"].values, q)
    assert np.abs((back.time.values - t) / np.timedelta64(1, "ns")).max() < 1000
    assert read_attitude(shared_data / DIR / "SCA1B_2003-09-14_B_00.asc").sizes["time"] == 60


def test_malformed_files_name_file_line_and_field(tmp_path, shared_data):
    good = ["# leopod attitude 1.0", "# time system: GPS", "time,q0,q1,q2,q3",
            "2020-01-01T00:00:00,1,0,0,0", "2020-01-01T00:00:10,1,0,0,0"]
    for lines, line, field in [
            (good[:3] + ["2020-01-01T00:00:00,1,0,0"], 4, "record"),
            (good[:3] + ["2020-13-01T00:00:00,1,0,0,0"], 4, "time"),
            (good[:3] + ["2020-01-01T00:00:00,1,0,x,0"], 4, "q2"),
            (good[:3] + ["2020-01-01T00:00:00,1,0,0.1,0"], 4, "quaternion"),
            (good[:4] + ["2020-01-01T00:00:00,1,0,0,0"], 5, "time"),
            (["# other file"] + good[1:], 1, "header"),
            (good[:2] + ["t,a,b,c,d"] + good[3:], 3, "columns")]:
        path = write_lines(tmp_path, lines, "bad.csv")
        with pytest.raises(FormatError) as err:
            read_attitude_csv(path)
        assert_format_error(err, path, line, field)
    sca = (shared_data / DIR / "SCA1B_2003-09-14_A_00.asc").read_text().splitlines()
    cut = write_lines(tmp_path, sca[:-1], "SCA1B_cut.asc")
    with pytest.raises(FormatError) as err:
        read_sca1b(cut)
    assert_format_error(err, cut, None, "NUMBER OF DATA RECORDS")
    bad = sca.copy()
    bad[30] = bad[30].replace(" A 4 ", " A 4 x ")
    path = write_lines(tmp_path, bad, "SCA1B_bad.asc")
    with pytest.raises(FormatError) as err:
        read_sca1b(path)
    assert_format_error(err, path, 31, "record")


def _orbit(n_s=600, step_s=1.0):
    """A circular 400-km orbit (GCRF) sampled at 1 s, inclined 89 deg."""
    t = np.datetime64("2020-06-01T00:00:00", "ns") + \
        (np.arange(0, n_s, step_s) * 1e9).astype("timedelta64[ns]")
    a, n = 6_778e3, np.sqrt(3.986004418e14 / 6_778e3 ** 3)
    u = n * np.arange(0, n_s, step_s)
    inc = np.radians(89.0)
    pos = a * np.stack([np.cos(u), np.sin(u) * np.cos(inc), np.sin(u) * np.sin(inc)], -1)
    vel = a * n * np.stack([-np.sin(u), np.cos(u) * np.cos(inc), np.cos(u) * np.sin(inc)], -1)
    return t, pos, vel


@pytest.mark.parametrize("fmt", ["csv", "netcdf"])
def test_closed_loop_file_written_from_a_law_gives_the_law(tmp_path, fmt):
    """A file written from the nominal law with GRACE-A's offsets gives the law's axes to
    < 1e-9 rad at its records (GCRF and ITRF inputs), and to the slerp bound between them."""
    t, pos, vel = _orbit()
    model = LeoAttitude.of({"attitude": "nominal",
                            "attitude_offset": {"yaw_deg": 180.0, "pitch_deg": -0.9}})
    axes = leo_body_axes(model, pos, vel, None)
    q = quaternion_from_body_axes(axes)
    write = write_attitude_csv if fmt == "csv" else write_attitude_netcdf
    path = write(tmp_path / f"att.{'csv' if fmt == 'csv' else 'nc'}", t[::10], q[::10])
    law = load_leo_attitude({"attitude": "file", "attitude_file": {"path": str(path)}}, path)
    got = leo_body_axes(law, pos, vel, None, times=t)
    err = np.linalg.norm(got - axes, axis=(1, 2)) / np.sqrt(2)           # ~ rotation angle
    at_records = err[::10].max()
    assert at_records < 1e-9 if fmt == "csv" else at_records < 1e-9 + 1e-3 * 1e-6
    assert err.max() < 1e-9        # circular orbit: constant rate, slerp is exact
    # Earth-fixed inputs: the file's GCRF attitude rotated to the ITRF is the law's there
    rot, _ = gcrf_from_itrf_matrices(t[:50])
    pos_ef = np.einsum("nji,nj->ni", rot, pos[:50])
    vel_ef = np.einsum("nji,nj->ni", rot, vel[:50])
    _, vel_back = itrf_to_gcrf(t[:50], pos_ef, vel_ef)
    ef = leo_body_axes_ef(law, t[:50], pos_ef, vel_ef)
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", ef, rot), axes[:50], atol=2e-9)


def test_coverage_errors_and_the_nominal_fallback(tmp_path):
    t, pos, vel = _orbit()
    axes = leo_body_axes(None, pos, vel, None)
    q = quaternion_from_body_axes(axes)
    keep = np.r_[0:200, 260:600]                                          # a 61-s gap
    path = write_attitude_csv(tmp_path / "att.csv", t[keep], q[keep])
    law = load_leo_attitude({"attitude": "file", "attitude_file": {"path": "x",
                                                                   "max_gap_s": 30.0}}, path)
    with pytest.raises(AttitudeCoverageError, match="2020-06-01T00:03:20"):
        leo_body_axes(law, pos, vel, None, times=t)
    end = t[-1] + np.timedelta64(15, "s")                                 # half a gap: ok
    leo_body_axes(law, pos[-1:], vel[-1:], None, times=[end])
    with pytest.raises(AttitudeCoverageError):
        leo_body_axes(law, pos[-1:], vel[-1:], None, times=[end + np.timedelta64(1, "s")])
    fallback = load_leo_attitude({"attitude": "file", "attitude_file": {
        "path": "x", "max_gap_s": 30.0, "outside": "nominal"}}, path)
    got = leo_body_axes(fallback, pos, vel, None, times=t)
    np.testing.assert_allclose(got, axes, atol=1e-9)
    with pytest.raises(ValueError, match="needs the epochs"):
        leo_body_axes(law, pos, vel, None)
    with pytest.raises(ValueError, match="needs attitude_file.path"):
        LeoAttitude.of({"attitude": "file"})
    with pytest.raises(ValueError, match="only read with attitude 'file'"):
        LeoAttitude.of({"attitude": "nominal", "attitude_file": {"path": "a.csv"}})


def test_antenna_range_terms_of_a_file_equal_those_of_its_law(tmp_path):
    """The seam of the quality and ambiguity steps (Earth-fixed states): the LEO PCO range
    term with the file law equals that of the law the file was written from (< 1 nm)."""
    from leopod.gnss.antenna_terms import antenna_range_m

    t, pos, vel = _orbit(n_s=120)
    rot, _ = gcrf_from_itrf_matrices(t)
    pos_ef = np.einsum("nji,nj->ni", rot, pos)
    vel_ef = np.einsum("nji,nj->ni", rot, vel)
    vel_ef = vel_ef - np.cross([0.0, 0.0, 7.292115e-5], pos_ef)         # Earth-fixed velocity
    model = LeoAttitude.of({"attitude": "nominal",
                            "attitude_offset": {"yaw_deg": 180.0, "pitch_deg": -0.9}})
    q = quaternion_from_body_axes(leo_body_axes_ef(model, t, pos_ef, vel_ef) @
                                  np.swapaxes(rot, 1, 2))              # GCRF -> body
    path = write_attitude_csv(tmp_path / "att.csv", t, q)
    law = load_leo_attitude({"attitude": "file", "attitude_file": {"path": str(path)}}, path)
    sv = pos_ef[:, None, :] + np.array([[[2.0e7, 1.0e6, 5.0e5], [-3.0e6, 2.1e7, 4.0e6]]])
    pco = [0.01, -0.02, -0.45]
    a = antenna_range_m(pos_ef, vel_ef, sv, pos_ef * 0 + 1e11, pco, leo_attitude=model,
                        times=t)
    b = antenna_range_m(pos_ef, vel_ef, sv, pos_ef * 0 + 1e11, pco, leo_attitude=law,
                        times=t)
    assert np.abs(a - b).max() < 1e-9
    assert np.abs(a).max() > 0.1                                        # the PCO matters
