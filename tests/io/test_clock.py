"""Tests of leopod.io.clock: real RINEX clock 2.00 / 3.00 files, a 3.04 layout, round trips
through write_rinex_clock, and broken files."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from _helpers import assert_format_error, write_lines

from leopod.io import FormatError
from leopod.io.clock import read_rinex_clock
from leopod.io.clock_write import _fortran_e, write_rinex_clock

COD_CLK = "grace-a_2007-080/cod14193.clk.gz"
WHU_CLK = "products_2008-279_whu/whp15000.clk.Z"


def _hdr(content: str, label: str, width: int = 60) -> str:
    return f"{content:<{width}s}{label}"


# A RINEX clock 3.00 file typed after the specification's layout (A4 names, labels at col 61).
V300 = [
    _hdr("     3.00           C                   G", "RINEX VERSION / TYPE"),  # line 1
    _hdr("   GPS", "TIME SYSTEM ID"),  # 2
    _hdr("     2    AS    AR", "# / TYPES OF DATA"),  # 3
    _hdr("TST  Test analysis centre", "ANALYSIS CENTER"),  # 4
    _hdr("", "END OF HEADER"),  # 5
    "AS G01  2020 01 02 00 00  0.000000  2    0.123456789012E-03  0.100000000000E-10",  # 6
    "AS G02  2020 01 02 00 00  0.000000  1   -0.987654321098E-04",  # 7
    "AR ABCD 2020 01 02 00 00  0.000000  4    0.111111111111E-06  0.200000000000E-10",  # 8
    "    0.100000000000E-12  0.300000000000E-14",  # 9
    "AS G01  2020 01 02 00 00 30.000000  1    0.123456789999E-03",  # 10
    "AS G02  2020 01 02 00 00 30.000000  1   -0.987654321999E-04",  # 11
]

# The same content in the 3.04 layout: A9 names (columns 4-12), labels at columns 66-85.
V304 = [
    _hdr("3.04                 C                    G", "RINEX VERSION / TYPE", 65),
    _hdr("   GPS", "TIME SYSTEM ID", 65),
    _hdr("     2    AS    AR", "# / TYPES OF DATA", 65),
    _hdr("", "END OF HEADER", 65),
    "AS G01       2020 01 02 00 00  0.000000  2    0.123456789012E-03  0.100000000000E-10",
    "AR ABCD00DEU 2020 01 02 00 00  0.000000  1    0.111111111111E-06",
    "AS G01       2020 01 02 00 00 30.000000  1    0.123456789999E-03",
]


def _write(tmp_path, lines, name="test.clk"):
    return write_lines(tmp_path, lines, name)


_assert_error = assert_format_error


# ------------------------------------------------------------------------------ real files


@pytest.mark.shared
def test_cod_clock_200_satellites(shared_data):
    ds = read_rinex_clock(shared_data / COD_CLK)
    assert ds.sizes == {"time": 2880, "sv": 30}
    assert "station" not in ds.dims
    assert ds.attrs["rinex_version"] == 2.0
    assert ds.attrs["analysis_center"] == "COD"
    assert ds.attrs["time_system"] == "GPS"
    assert ds.attrs["interval_s"] == 30.0
    assert "P1C1.DCB" in ds.attrs["dcb_applied"]  # "G GPSEST V5.1  P1C1.DCB @ ... DCBS APPLIED"
    assert "IGS05_1402" in ds.attrs["pcv_applied"]
    assert ds.attrs["data_types"] == "AR AS"
    assert ds.time.values[0] == np.datetime64("2007-03-21T00:00:00")
    assert ds.time.values[-1] == np.datetime64("2007-03-21T23:59:30")
    # line 226: "AS G01  2007 03 21 00 00  0.000000  2    0.115016696417E-03  0.360574866033E-10"
    assert ds.clk_s.sel(sv="G01").values[0] == 0.115016696417e-03
    assert ds.clk_sigma_s.sel(sv="G01").values[0] == 0.360574866033e-10
    # 30-s records between the 5-min ones carry one value: sigma NaN
    assert np.isnan(ds.clk_sigma_s.sel(sv="G01").values[1])
    assert np.isfinite(ds.clk_s.values).all()  # 86400 AS records = 2880 x 30
    assert ds.clk_s.attrs["units"] == "s" and "long_name" in ds.clk_s.attrs


@pytest.mark.shared
def test_cod_clock_station_records(shared_data):
    ds = read_rinex_clock(shared_data / COD_CLK, kinds=("AS", "AR"))
    assert ds.sizes["station"] == 108 and ds.sizes["sv"] == 30
    wsrt = ds.sel(station="WSRT")
    t = np.datetime64("2007-03-21T00:05:00")
    # line 535: "AR WSRT 2007 03 21 00 05  0.000000  2    0.139430050914E-06  0.926191676620E-10"
    assert wsrt.clk_station_s.sel(time=t).item() == 0.139430050914e-06
    assert wsrt.clk_station_sigma_s.sel(time=t).item() == 0.926191676620e-10
    # line 672: "AR WSRT 2007 03 21 00 05 30.000000  1    0.139435857063E-06"
    t30 = np.datetime64("2007-03-21T00:05:30")
    assert wsrt.clk_station_s.sel(time=t30).item() == 0.139435857063e-06
    assert np.isnan(wsrt.clk_station_sigma_s.sel(time=t30).item())


@pytest.mark.shared
def test_whu_clock_300(shared_data):
    ds = read_rinex_clock(shared_data / WHU_CLK)
    assert ds.attrs["rinex_version"] == 3.0
    assert ds.attrs["analysis_center"] == "WHU"
    assert ds.sizes["sv"] == 32
    # last line: "AS G32  2008 10  5 23 59  0.000000  1    0.316534379284E-03"
    assert ds.clk_s.sel(sv="G32", time=np.datetime64("2008-10-05T23:59:00")).item() \
        == 0.316534379284e-03
    assert np.isnan(ds.clk_sigma_s.values).all()


# ------------------------------------------------------------------------------ layouts


def test_version_300_layout_with_continuation(tmp_path):
    ds = read_rinex_clock(_write(tmp_path, V300), kinds=("AS", "AR"))
    assert list(ds.sv.values) == ["G01", "G02"] and list(ds.station.values) == ["ABCD"]
    assert ds.attrs["analysis_center"] == "TST"
    assert ds.clk_s.values[:, 0].tolist() == [0.123456789012e-03, 0.123456789999e-03]
    assert ds.clk_sigma_s.values[0, 0] == 0.1e-10
    assert ds.clk_station_s.values[:, 0][0] == 0.111111111111e-06
    assert np.isnan(ds.clk_station_s.values[1, 0])  # no AR record at 00:00:30
    assert ds.attrs["interval_s"] == 30.0


def test_version_304_wide_names(tmp_path):
    ds = read_rinex_clock(_write(tmp_path, V304), kinds=("AS", "AR"))
    assert ds.attrs["rinex_version"] == 3.04
    assert list(ds.sv.values) == ["G01"] and list(ds.station.values) == ["ABCD00DEU"]
    assert ds.clk_s.values[:, 0].tolist() == [0.123456789012e-03, 0.123456789999e-03]
    assert ds.clk_sigma_s.values[0, 0] == 0.1e-10
    assert ds.time.values[1] == np.datetime64("2020-01-02T00:00:30")


def test_kinds_validation(tmp_path):
    with pytest.raises(ValueError, match="kinds"):
        read_rinex_clock(_write(tmp_path, V300), kinds=("CR",))


# ------------------------------------------------------------------------------ writer


def _clock_ds(n_time=4, sats=("G01", "G05", "R03")) -> xr.Dataset:
    rng = np.random.default_rng(7)
    time = np.datetime64("2023-01-01T00:00:00", "ns") + np.arange(n_time) * np.timedelta64(30, "s")
    clk = rng.uniform(-1e-3, 1e-3, (n_time, len(sats)))
    sigma = rng.uniform(1e-12, 1e-10, clk.shape)
    clk[1, 2] = np.nan
    sigma[2, 0] = np.nan
    return xr.Dataset({"clk_s": (("time", "sv"), clk, {"units": "s", "long_name": "clock"}),
                       "clk_sigma_s": (("time", "sv"), sigma, {"units": "s", "long_name": "sd"})},
                      coords={"time": time, "sv": list(sats)}, attrs={"time_system": "GPS"})


@pytest.mark.parametrize("version", ["3.00", "2.00"])
def test_round_trip(tmp_path, version):
    ds = _clock_ds()
    path = tmp_path / "out.clk"
    write_rinex_clock(ds, path, version=version)
    back = read_rinex_clock(path)
    assert back.attrs["rinex_version"] == float(version)
    assert back.attrs["analysis_center"] == "LEO"
    np.testing.assert_array_equal(back.time.values, ds.time.values)
    np.testing.assert_array_equal(np.isnan(back.clk_s.values), np.isnan(ds.clk_s.values))
    # E19.12 keeps 12 significant digits: far below the 1e-12 s requirement
    np.testing.assert_allclose(back.clk_s.values, ds.clk_s.values, rtol=5e-12, atol=0)
    assert np.nanmax(np.abs(back.clk_s.values - ds.clk_s.values)) < 1e-15
    expected_sigma = np.where(np.isnan(ds.clk_s.values), np.nan, ds.clk_sigma_s.values)
    np.testing.assert_allclose(back.clk_sigma_s.values, expected_sigma, rtol=5e-12, atol=0)


def test_writer_record_columns(tmp_path):
    path = tmp_path / "out.clk"
    write_rinex_clock(_clock_ds().isel(time=[0], sv=[0]), path)
    lines = path.read_text().splitlines()
    record = lines[-1]
    assert record[:34] == "AS G01  2023  1  1  0  0  0.000000"
    assert record[34:40] == "  2   " and len(record) == 79
    assert record[40:42] in (" 0", "-0") and record[55] == "E"


def test_values_are_fortran_e19_12():
    """Fortran E19.12 as the COD clock file writes it (lines 226, 535 of the 2007-080 file,
    quoted above): 0.d..d, 12 digits, exponent raised by one; the digits are Python's
    correctly rounded ``.11E`` (so 9.9999999999995e-5 rounds up into the next decade)."""
    got = _fortran_e(np.array([0.115016696417e-03, 0.360574866033e-10, 0.139430050914e-06,
                               -0.987654321098e-04, 9.9999999999995e-5, 0.0, -0.0, 1.0]))
    assert got.tolist() == [" 0.115016696417E-03", " 0.360574866033E-10",
                            " 0.139430050914E-06", "-0.987654321098E-04",
                            " 0.100000000000E-03", " 0.000000000000E+00",
                            "-0.000000000000E+00", " 0.100000000000E+01"]


@pytest.mark.shared
def test_real_file_round_trip_exact(shared_data, tmp_path):
    ds = read_rinex_clock(shared_data / WHU_CLK)
    path = tmp_path / "whu.clk.gz"
    write_rinex_clock(ds, path)
    back = read_rinex_clock(path)
    np.testing.assert_array_equal(back.clk_s.values, ds.clk_s.values)


# ------------------------------------------------------------------------------ broken files


def test_truncated_mid_value(tmp_path):
    lines = V300[:10] + [V300[10][:50]]  # "-0.98765432" loses its exponent
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="truncated") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 11, "G02 clock bias")


def test_truncated_record_missing_value(tmp_path):
    lines = V300[:5] + [V300[5][:60]]  # announces 2 values, has 1
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="announces 2 values") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 6, "number of values")


def test_truncated_before_continuation_line(tmp_path):
    path = _write(tmp_path, V300[:8])  # the AR record of line 8 announces 4 values
    with pytest.raises(FormatError, match="line 8") as excinfo:
        read_rinex_clock(path, kinds=("AR",))
    _assert_error(excinfo, path, 8, "continuation line")


def test_non_numeric_value(tmp_path):
    lines = list(V300)
    lines[6] = lines[6][:40] + "-0.98765432109XE-04"
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="not a number") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 7, "G02 clock bias")


def test_nan_value(tmp_path):
    lines = list(V300)
    lines[5] = lines[5][:60] + f"{'nan':>19s}"
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="finite") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 6, "G01 clock sigma")


def test_bad_epoch(tmp_path):
    lines = list(V300)
    lines[9] = lines[9].replace("2020 01 02", "2020 13 02")
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="month") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 10, "epoch")


def test_missing_end_of_header(tmp_path):
    path = _write(tmp_path, V300[:4])
    with pytest.raises(FormatError) as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, None, "END OF HEADER")


def test_missing_types_of_data(tmp_path):
    path = _write(tmp_path, V300[:2] + V300[3:])
    with pytest.raises(FormatError) as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, None, "# / TYPES OF DATA")


def test_not_a_clock_file(tmp_path):
    lines = list(V300)
    lines[0] = _hdr("     3.00           O                   G", "RINEX VERSION / TYPE")
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="not a RINEX clock file") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 1, "file type")


def test_duplicate_record(tmp_path):
    lines = V300 + [V300[9]]
    path = _write(tmp_path, lines)
    with pytest.raises(FormatError, match="second AS record of 'G01'") as excinfo:
        read_rinex_clock(path)
    _assert_error(excinfo, path, 12, "clock name")


# --------------------------------------------------------------------------- time systems
def test_bdt_file_read_in_gps_time(tmp_path):
    """RINEX clock 3.04 TIME SYSTEM ID: a BDT file whose epochs are 14 s before GPST
    (BDT = GPST - 14 s, BDS-SIS-ICD-B1I-3.0 / IS-GPS-200) reads back, with ``gps_time=True``,
    on the GPST epochs to better than 1 microsecond (here exactly)."""
    gps = _clock_ds()
    bdt = gps.assign_coords(time=gps.time.values - np.timedelta64(14, "s"))
    bdt.attrs["time_system"] = "BDT"
    path = tmp_path / "bdt.clk"
    write_rinex_clock(bdt, path, version="3.00")
    assert any(x[60:].strip() == "TIME SYSTEM ID" and x.split()[0] == "BDT"
               for x in path.read_text().splitlines())
    np.testing.assert_array_equal(read_rinex_clock(path).time.values, bdt.time.values)
    back = read_rinex_clock(path, gps_time=True)
    err_ns = np.abs((back.time.values - gps.time.values).astype(np.int64))
    assert err_ns.max() < 1_000
    assert back.attrs["time_system"] == "GPS" and back.attrs["time_system_file"] == "BDT"
    np.testing.assert_allclose(back.clk_s.values, gps.clk_s.values, rtol=5e-12)


def test_time_system_errors(tmp_path):
    """An identifier outside the RINEX clock list is a FormatError at its line; GLONASS time
    is read as written but has no conversion to GPS time."""
    path = tmp_path / "gps.clk"
    write_rinex_clock(_clock_ds(), path, version="3.00")
    lines = path.read_text().splitlines()
    k = next(i for i, x in enumerate(lines) if x[60:].strip() == "TIME SYSTEM ID")
    for code, name in (("XYZ", "xyz.clk"), ("GLO", "glo.clk")):
        edited = list(lines)
        edited[k] = f"   {code}".ljust(60) + lines[k][60:]
        bad = write_lines(tmp_path, edited, name)
        if code == "GLO":
            assert read_rinex_clock(bad).attrs["time_system"] == "GLO"
        with pytest.raises(FormatError, match="GLONASS" if code == "GLO" else "'XYZ'") as exc:
            read_rinex_clock(bad, gps_time=True)
        assert_format_error(exc, bad, k + 1, "TIME SYSTEM ID")


def test_empty_gzip_payload_is_a_format_error(tmp_path):
    """Issue 24: a gzip file with an empty payload raised IndexError at lines[0]."""
    import gzip

    path = tmp_path / "empty.clk.gz"
    path.write_bytes(gzip.compress(b""))
    with pytest.raises(FormatError) as exc:
        read_rinex_clock(path)
    assert_format_error(exc, path, None, "file")  # the shared rule of io._text.read_lines
