"""Tests of leopod.io.sp3: real SP3-c/d files, round trips through write_sp3, broken files."""

from __future__ import annotations

import logging

import numpy as np
import pytest
import xarray as xr
from _helpers import assert_format_error, write_lines

from leopod.io import FormatError
from leopod.io.sp3 import read_sp3
from leopod.io.sp3_write import write_sp3

COD_SP3C = "grace-a_2007-080/cod14193.sp3.gz"
COD_SP3D = "products_2023-189_cod_osb/COD0OPSFIN_20231890000_01D_05M_ORB.SP3"
SWARM = "swarm-a_2023-001/SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_0201.sp3"

# Layout of a file written by write_sp3 with < 86 satellites: 2 + 5 "+" + 5 "++" + 6 "%" + 4 "/*"
FIRST_EPOCH_LINE = 23


def _small(n_time=3, sats=("G01", "G02"), velocity=False) -> xr.Dataset:
    """A small orbit Dataset with the read_sp3 schema (values in m, s, m/s)."""
    rng = np.random.default_rng(1)
    time = np.datetime64("2023-01-01T00:00:00", "ns") + np.arange(n_time) * np.timedelta64(30, "s")
    pos = rng.uniform(-2.6e7, 2.6e7, (n_time, len(sats), 3))
    clk = rng.uniform(-1e-3, 1e-3, (n_time, len(sats)))
    data = {"pos_m": (("time", "sv", "xyz"), pos, {"units": "m", "long_name": "position"}),
            "clk_s": (("time", "sv"), clk, {"units": "s", "long_name": "clock"})}
    if velocity:
        data["vel_m_s"] = (("time", "sv", "xyz"), rng.uniform(-7600, 7600, pos.shape),
                           {"units": "m s-1", "long_name": "velocity"})
        data["clk_rate_s_s"] = (("time", "sv"), rng.uniform(-1e-9, 1e-9, clk.shape),
                                {"units": "s s-1", "long_name": "clock rate"})
    return xr.Dataset(data, coords={"time": time, "sv": list(sats), "xyz": ["x", "y", "z"]},
                      attrs={"time_system": "GPS"})


def _written_lines(tmp_path, **kwargs) -> list[str]:
    path = tmp_path / "small.sp3"
    write_sp3(_small(**kwargs), path)
    return path.read_text().splitlines()


def _write(tmp_path, lines, name="broken.sp3"):
    return write_lines(tmp_path, lines, name)


_assert_error = assert_format_error


# ------------------------------------------------------------------------------ real files


@pytest.mark.shared
def test_cod_sp3c_header_and_first_record(shared_data):
    ds = read_sp3(shared_data / COD_SP3C)
    assert ds.sizes == {"time": 96, "sv": 43, "xyz": 3}
    # line 1: "#cP2007  3 21  0  0  0.00000000      96 d+D   IGS05 FIT AIUB"
    assert ds.attrs["sp3_version"] == "c"
    assert ds.attrs["coordinate_system"] == "IGS05"
    assert ds.attrs["orbit_type"] == "FIT"
    assert ds.attrs["agency"] == "AIUB"
    assert ds.attrs["data_used"] == "d+D"
    assert ds.attrs["interval_s"] == 900.0  # line 2
    assert ds.attrs["time_system"] == "GPS"  # "%c M  cc GPS ccc ..."
    assert ds.attrs["filename"] == "cod14193.sp3.gz"
    assert "Center for Orbit Determination in Europe" in ds.attrs["comments"]
    assert ds.time.values[0] == np.datetime64("2007-03-21T00:00:00")
    assert ds.time.values[-1] == np.datetime64("2007-03-21T23:45:00")  # line 4203
    assert ds.sv.values[0] == "G01" and ds.sv.values[-1] == "R24"
    # line 24: "PG01 -18297.936920 -14173.440314  13290.143931    115.016696"
    np.testing.assert_allclose(ds.pos_m.sel(sv="G01").values[0],
                               [-18297936.920, -14173440.314, 13290143.931], rtol=0, atol=1e-7)
    assert ds.clk_s.sel(sv="G01").values[0] == pytest.approx(115.016696e-6, abs=1e-15)
    # line 4246: "PR24  15934.901315  -4936.027207 -19247.760629 999999.999999"
    np.testing.assert_allclose(ds.pos_m.sel(sv="R24").values[-1],
                               [15934901.315, -4936027.207, -19247760.629], rtol=0, atol=1e-7)
    assert np.isnan(ds.clk_s.sel(sv="R24").values[-1])
    # "++" line 8, first entry 5: accuracy 2**5 mm of G01
    assert ds.orbit_accuracy_m.sel(sv="G01").item() == pytest.approx(0.032)
    assert "vel_m_s" not in ds
    assert ds.pos_m.attrs["units"] == "m" and ds.clk_s.attrs["units"] == "s"


@pytest.mark.shared
def test_cod_sp3d_78_satellites(shared_data):
    ds = read_sp3(shared_data / COD_SP3D)
    assert ds.sizes == {"time": 289, "sv": 78, "xyz": 3}
    assert ds.attrs["sp3_version"] == "d"
    assert ds.attrs["coordinate_system"] == "IGS20"
    assert ds.attrs["interval_s"] == 300.0
    assert ds.time.values[-1] == np.datetime64("2023-07-09T00:00:00")  # line 22776
    # line 22854: "PE36 -14283.322238  10383.111252  23748.946549    -83.087544"
    np.testing.assert_allclose(ds.pos_m.sel(sv="E36").values[-1],
                               [-14283322.238, 10383111.252, 23748946.549], rtol=0, atol=1e-7)
    assert ds.clk_s.sel(sv="E36").values[-1] == pytest.approx(-83.087544e-6, abs=1e-15)
    assert np.isfinite(ds.pos_m.values).all()


@pytest.mark.shared
def test_cod_sp3d_matches_georinex(shared_data):
    """Independent reader: georinex (test extra) gives the same km and µs values."""
    gr = pytest.importorskip("georinex")
    ref = gr.load(shared_data / COD_SP3D)
    ds = read_sp3(shared_data / COD_SP3D)
    np.testing.assert_array_equal(ref.position.sel(sv=ds.sv.values).values * 1e3, ds.pos_m.values)
    np.testing.assert_array_equal(ref.clock.sel(sv=ds.sv.values).values * 1e-6, ds.clk_s.values)


@pytest.mark.shared
def test_swarm_positions_and_velocities(shared_data):
    ds = read_sp3(shared_data / SWARM)
    assert ds.sizes == {"time": 8640, "sv": 1, "xyz": 3}
    assert ds.attrs["pv_flag"] == "V" and ds.attrs["agency"] == "TUD"
    assert list(ds.sv.values) == ["L47"]
    assert (np.diff(ds.time.values) == np.timedelta64(10, "s")).all()
    # line 24: "PL47 -4062.4839362 -5508.2572862   110.2459607 999999.999999" (7 decimals)
    np.testing.assert_allclose(ds.pos_m.values[0, 0], [-4062483.9362, -5508257.2862, 110245.9607],
                               rtol=0, atol=1e-7)
    # line 25: "VL47 -1978.2150585  -195.1374440-76231.7632170 999999.999999" (dm/s)
    np.testing.assert_allclose(ds.vel_m_s.values[0, 0], [-197.82150585, -19.5137444,
                                                         -7623.1763217], rtol=0, atol=1e-9)
    assert np.isnan(ds.clk_s.values).all() and np.isnan(ds.clk_rate_s_s.values).all()
    assert ds.vel_m_s.attrs["units"] == "m s-1"
    speed = np.linalg.norm(ds.vel_m_s.values[:, 0], axis=1)
    assert 7.4e3 < speed.min() and speed.max() < 7.8e3  # LEO speed: checks the dm/s scale


@pytest.mark.shared
def test_compressed_eph(shared_data):
    ds = read_sp3(shared_data / "products_2008-279_whu/COD15000.EPH.Z")
    assert ds.sizes["sv"] == 46 and ds.sizes["time"] == 96
    assert ds.time.values[0] == np.datetime64("2008-10-05T00:00:00")


# ------------------------------------------------------------------------------ writer


def test_round_trip_positions_clocks(tmp_path):
    ds = _small()
    path = tmp_path / "o.sp3"
    write_sp3(ds, path, comments=("a test",))
    back = read_sp3(path)
    assert back.attrs["sp3_version"] == "d" and back.attrs["agency"] == "LEO"
    assert back.attrs["coordinate_system"] == "ITRF" and back.attrs["orbit_type"] == "FIT"
    assert back.attrs["interval_s"] == 30.0
    assert "a test" in back.attrs["comments"]
    np.testing.assert_array_equal(back.time.values, ds.time.values)
    np.testing.assert_allclose(back.pos_m.values, ds.pos_m.values, rtol=0, atol=0.5e-3 + 1e-9)
    np.testing.assert_allclose(back.clk_s.values, ds.clk_s.values, rtol=0, atol=0.5e-12 + 1e-18)
    assert "vel_m_s" not in back


def test_round_trip_velocities_and_missing(tmp_path):
    ds = _small(velocity=True)
    ds["pos_m"][1, 0] = np.nan
    ds["clk_s"][2, 1] = np.nan
    path = tmp_path / "o.sp3.gz"
    write_sp3(ds, path)
    back = read_sp3(path)
    assert back.attrs["pv_flag"] == "V"
    np.testing.assert_allclose(back.vel_m_s.values, ds.vel_m_s.values, rtol=0, atol=0.5e-7 + 1e-12)
    np.testing.assert_allclose(back.clk_rate_s_s.values, ds.clk_rate_s_s.values, rtol=0,
                               atol=0.5e-16 + 1e-22)
    assert np.isnan(back.pos_m.values[1, 0]).all()
    assert np.isnan(back.clk_s.values[2, 1])
    assert np.isfinite(back.pos_m.values[0]).all()


def test_header_lines_follow_sp3d(tmp_path):
    lines = _written_lines(tmp_path, sats=("L47",), velocity=True)
    # SP3-d columns: version, P/V flag, start epoch, epochs, data used, frame, type, agency
    assert lines[0] == "#dV2023  1  1  0  0  0.00000000       3 u+U   ITRF  FIT LEO "
    # GPS week 2243, day 0 (Sunday) -> 0 s of week; MJD 59945
    assert lines[1] == "## 2243      0.00000000    30.00000000 59945 0.0000000000000"
    assert lines[2].startswith("+    1   L47  0")
    assert sum(line.startswith("+ ") for line in lines) == 5
    assert sum(line.startswith("++") for line in lines) == 5
    assert lines[12].startswith("%c L  cc GPS ccc")
    assert lines[FIRST_EPOCH_LINE - 1] == "*  2023  1  1  0  0  0.00000000"
    assert lines[FIRST_EPOCH_LINE][:4] == "PL47" and len(lines[FIRST_EPOCH_LINE]) == 60
    assert lines[FIRST_EPOCH_LINE + 1][:4] == "VL47"
    assert lines[-1] == "EOF"


def test_more_than_85_satellites(tmp_path):
    sats = tuple(f"{s}{k:02d}" for s in "GREC" for k in range(1, 24))  # 92 satellites
    path = tmp_path / "many.sp3"
    write_sp3(_small(n_time=2, sats=sats), path)
    lines = path.read_text().splitlines()
    assert sum(line.startswith("+ ") for line in lines) == 6  # ceil(92 / 17)
    assert lines[2][3:6] == " 92"
    back = read_sp3(path)
    assert list(back.sv.values) == list(sats)
    assert back.attrs["file_type"] == "M"


def test_write_rejects_overflow_and_bad_labels(tmp_path):
    ds = _small()
    with pytest.raises(ValueError, match="agency"):
        write_sp3(ds, tmp_path / "x.sp3", agency="TOOLONG")
    ds["pos_m"][0, 1, 2] = 1e10  # 1e7 km does not fit F14.6
    with pytest.raises(ValueError, match="position of G02"):
        write_sp3(ds, tmp_path / "x.sp3")
    ds = _small()
    ds["clk_s"][0, 0] = 1.0  # 1e6 µs would read back as the bad-clock value 999999.999999
    with pytest.raises(ValueError, match="clock of G01"):
        write_sp3(ds, tmp_path / "x.sp3")


# ------------------------------------------------------------------------------ broken files


def test_truncated_mid_record(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 2  # 1-based: the second P record (G02) of the first epoch
    path = _write(tmp_path, lines[:n - 1] + [lines[n - 1][:25]])
    with pytest.raises(FormatError) as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "G02 y")


def test_non_numeric_field(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 1
    lines[n - 1] = lines[n - 1][:4] + "     abc.defgh" + lines[n - 1][18:]
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="abc.defgh") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "G01 x")


def test_nan_clock(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 5  # second epoch, G02
    lines[n - 1] = lines[n - 1][:46] + f"{'nan':>14s}"
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="finite") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "G02 clock")


def test_bad_epoch_line(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 3  # second epoch line
    lines[n - 1] = "*  2023 13  1  0  0 30.00000000"
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="month") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "epoch")


def test_truncated_epoch_line(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 3
    path = _write(tmp_path, lines[:n - 1] + [lines[n - 1][:14]])
    with pytest.raises(FormatError, match="truncated") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "epoch")


def test_fewer_epochs_than_declared(tmp_path, caplog):
    # Issue 24: a header count that disagrees with a complete file (closed by EOF) is a
    # warning, as in the GFZ MGEX rapid orbit kept by gnss_lib_py (288 declared, 3 held);
    # without EOF the same file is refused as truncated.
    lines = _written_lines(tmp_path)
    path = _write(tmp_path, lines[:FIRST_EPOCH_LINE + 5] + ["EOF"])  # 2 of 3 epochs
    with caplog.at_level(logging.WARNING, logger="leopod.io.sp3"):
        assert read_sp3(path).sizes["time"] == 2
    assert "declares 3 epochs, file has 2" in caplog.text
    path = _write(tmp_path, lines[:FIRST_EPOCH_LINE + 5])
    with pytest.raises(FormatError, match="declares 3 epochs") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, FIRST_EPOCH_LINE + 5, "number of epochs")


def test_more_epochs_than_declared_is_a_warning(tmp_path, caplog):
    lines = _written_lines(tmp_path)
    lines[0] = lines[0][:32] + f"{2:7d}" + lines[0][39:]
    path = _write(tmp_path, lines)
    with caplog.at_level(logging.WARNING, logger="leopod.io.sp3"):
        ds = read_sp3(path)
    assert ds.sizes["time"] == 3
    assert "declares 2 epochs" in caplog.text


def test_missing_eof_tolerated_when_last_epoch_complete(tmp_path):
    lines = _written_lines(tmp_path)
    assert lines[-1] == "EOF"
    ds = read_sp3(_write(tmp_path, lines[:-1]))
    assert ds.sizes["time"] == 3 and np.isfinite(ds.pos_m.values).all()


def test_missing_eof_with_incomplete_last_epoch(tmp_path):
    lines = _written_lines(tmp_path)
    path = _write(tmp_path, lines[:-2])  # drops EOF and the last epoch's G02 record
    with pytest.raises(FormatError, match="incomplete") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, len(lines) - 2, "EOF")


def test_wrong_first_line(tmp_path):
    lines = _written_lines(tmp_path)
    lines[0] = "#xP" + lines[0][3:]
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError) as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, 1, "version")


def test_missing_satellite_list(tmp_path):
    lines = _written_lines(tmp_path)
    path = _write(tmp_path, lines[:2] + lines[7:])
    with pytest.raises(FormatError, match="satellite list") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, 3, "+")


def test_satellite_not_in_header(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 2
    lines[n - 1] = "PG07" + lines[n - 1][4:]
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="G07") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "satellite")


def test_duplicate_record(tmp_path):
    lines = _written_lines(tmp_path)
    n = FIRST_EPOCH_LINE + 2
    lines[n - 1] = "PG01" + lines[n - 1][4:]
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="second record of G01") as excinfo:
        read_sp3(path)
    _assert_error(excinfo, path, n, "satellite")


def test_record_standard_deviations(tmp_path):
    lines = _written_lines(tmp_path)
    assert lines[14].startswith("%f")
    lines[14] = "%f  1.2500000  1.025000000  0.00000000000  0.000000000000000"
    n = FIRST_EPOCH_LINE + 1
    lines[n - 1] = lines[n - 1] + " 18 18 17 219"  # SP3-d columns 62-63, 65-66, 68-69, 71-73
    ds = read_sp3(_write(tmp_path, lines))
    # SP3-d: sdev = base**exponent in mm (positions) and ps (clocks)
    np.testing.assert_allclose(ds.pos_sigma_m.values[0, 0],
                               [1.25 ** 18 * 1e-3, 1.25 ** 18 * 1e-3, 1.25 ** 17 * 1e-3])
    assert ds.clk_sigma_s.values[0, 0] == pytest.approx(1.025 ** 219 * 1e-12)
    assert np.isnan(ds.pos_sigma_m.values[0, 1]).all()  # G02: blank exponents


# --------------------------------------------------------------------------- time systems
def test_bdt_file_read_in_gps_time(tmp_path):
    """SP3-d line %c columns 10-12 give the time system; a BDT file whose epochs are 14 s
    before GPST (BDT = GPST - 14 s, BDS-SIS-ICD-B1I-3.0 / IS-GPS-200) reads back, with
    ``gps_time=True``, on the GPST epochs to better than 1 microsecond (here exactly)."""
    gps = _small()
    bdt = gps.assign_coords(time=gps.time.values - np.timedelta64(14, "s"))
    bdt.attrs["time_system"] = "BDT"
    path = tmp_path / "bdt.sp3"
    write_sp3(bdt, path)
    pc = next(x for x in path.read_text().splitlines() if x.startswith("%c"))
    assert pc[9:12] == "BDT"  # the first %c line
    as_written = read_sp3(path)
    assert as_written.attrs["time_system"] == "BDT"
    np.testing.assert_array_equal(as_written.time.values, bdt.time.values)
    back = read_sp3(path, gps_time=True)
    err_ns = np.abs((back.time.values - gps.time.values).astype(np.int64))
    assert err_ns.max() < 1_000
    assert back.attrs["time_system"] == "GPS" and back.attrs["time_system_file"] == "BDT"
    np.testing.assert_allclose(back.pos_m.values, gps.pos_m.values, atol=1e-3)


def test_time_system_errors(tmp_path):
    """An identifier outside the SP3/RINEX list is a FormatError at the %c line; GLONASS
    time (UTC(SU) + 3 h) is read as written but has no conversion to GPS time."""
    lines = _written_lines(tmp_path)
    k = next(i for i, x in enumerate(lines) if x.startswith("%c"))
    assert lines[k][9:12] == "GPS"
    bad = list(lines)
    bad[k] = bad[k][:9] + "XYZ" + bad[k][12:]
    path = write_lines(tmp_path, bad, "xyz.sp3")
    with pytest.raises(FormatError, match="'XYZ' is not an SP3 time system") as exc:
        read_sp3(path)
    assert_format_error(exc, path, k + 1, "time system")
    glo = list(lines)
    glo[k] = glo[k][:9] + "GLO" + glo[k][12:]
    path = write_lines(tmp_path, glo, "glo.sp3")
    assert read_sp3(path).attrs["time_system"] == "GLO"
    with pytest.raises(FormatError, match="GLONASS") as exc:
        read_sp3(path, gps_time=True)
    assert_format_error(exc, path, k + 1, "time system")


def test_empty_gzip_payload_is_a_format_error(tmp_path):
    """Issue 24: a gzip file with an empty payload raised IndexError at lines[0]."""
    import gzip

    path = tmp_path / "empty.sp3.gz"
    path.write_bytes(gzip.compress(b""))
    with pytest.raises(FormatError) as exc:
        read_sp3(path)
    assert_format_error(exc, path, None, "file")  # the shared rule of io._text.read_lines


def test_year_outside_datetime64_range_is_an_error(tmp_path):
    """Issue 24: year 3000 overflowed datetime64[ns] (OverflowError) instead of FormatError."""
    lines = _written_lines(tmp_path)
    k = next(i for i, x in enumerate(lines) if x.startswith("*"))
    lines[k] = lines[k][:3] + "3000" + lines[k][7:]
    path = write_lines(tmp_path, lines, "year.sp3")
    with pytest.raises(FormatError, match="outside 1900-2199") as exc:
        read_sp3(path)
    assert_format_error(exc, path, k + 1, "epoch")


def test_record_accuracy_exponents_round_trip(tmp_path):
    # SP3-d (Hilla 2016), P record columns 62-73: sigma = base**n mm (positions, base 1.25) and
    # ps (clock, base 1.025), the bases on the first %f line; the nearest n is written
    ds = _small(n_time=4, sats=("L01",))
    pos_sigma = np.array([0.0021, 0.013, 0.4, np.nan])[:, None, None] * np.ones((4, 1, 3))
    ds["pos_sigma_m"] = (("time", "sv", "xyz"), pos_sigma)
    ds["clk_sigma_s"] = (("time", "sv"), np.array([[3e-11], [1e-10], [np.nan], [2e-9]]))
    write_sp3(ds, tmp_path / "s.sp3")
    lines = (tmp_path / "s.sp3").read_text().splitlines()
    assert any(line.startswith("%f  1.2500000  1.025000000") for line in lines)
    back = read_sp3(tmp_path / "s.sp3")
    for name, base in (("pos_sigma_m", 1.25), ("clk_sigma_s", 1.025)):
        given, decoded = ds[name].values, back[name].values
        ok = np.isfinite(given)
        assert np.abs(np.log(decoded[ok] / given[ok]) / np.log(base)).max() <= 0.5 + 1e-9
        np.testing.assert_array_equal(np.isnan(decoded), ~ok)      # NaN: blank field
    # without sigmas nothing changes: no exponents, zero bases
    write_sp3(_small(), tmp_path / "plain.sp3")
    assert "pos_sigma_m" not in read_sp3(tmp_path / "plain.sp3")


def test_a_job_s_sp3_names_the_frame_and_the_config_hash(tmp_path):
    # SP3-d (Hilla 2016) line 1 columns 47-51: coordinate system; "/*" lines: comments of at
    # most 80 columns. Inside a workflow job the campaign hash is the last comment.
    from leopod.io.provenance import JobProvenance, set_job

    digest = "ab" * 32
    set_job(JobProvenance(rule="float_pod", script="scripts/float_pod.py", settings="{}",
                          inputs=(), config_sha256=digest))
    try:
        write_sp3(_small(sats=("L47",)), tmp_path / "a.sp3", coordinate_system="IGS05",
                  comments=("leopod float orbit",))
    finally:
        set_job(None)
    lines = (tmp_path / "a.sp3").read_text().splitlines()
    assert lines[0][46:51] == "IGS05"
    comments = [line for line in lines if line.startswith("/*")]
    assert [c for c in comments if c != "/*"][-2:] == ["/* leopod float orbit",
                                                       f"/* config hash {digest}"]
    assert max(len(line) for line in comments) <= 80
    assert read_sp3(tmp_path / "a.sp3").attrs["coordinate_system"] == "IGS05"
