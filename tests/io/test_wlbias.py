"""Tests of leopod.io.wlbias.

No real CNES/CLS file is available to the project: every file below is CONSTRUCTED from the
documented layout (RINEX clock data record with type "WL", as read by the public converter
grg2snx.cpp of YuanxinPan/clkcomb; see the module docstring). The numbers are invented.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.io._text import FormatError
from leopod.io.clock import read_rinex_clock
from leopod.io.clock_write import write_rinex_clock
from leopod.io.wlbias import read_wl_bias
from leopod.io.wlbias_write import wl_bias_records, write_wl_bias


def _wl(sv, epoch, values, comment=False):
    """One WL record: A2,1X,A4,1X,I4,4I3,F10.6,I3,3X,nE19.12 (+ COMMENT label if asked)."""
    y, mo, d, h, mi, s = epoch
    text = (f"WL {sv:<4s} {y:4d}{mo:3d}{d:3d}{h:3d}{mi:3d}{s:10.6f}{len(values):3d}   "
            + "".join(f"{v:19.12E}" for v in values))
    return f"{text:<60}COMMENT" if comment else text


def _header_line(text, label):
    return f"{text:<60}{label}"


def _grg_clock_file(wl_lines):
    """A RINEX clock 3.00 file in the GRG style: WL records as header comment lines."""
    return "\n".join([
        _header_line("3.00           C                   G", "RINEX VERSION / TYPE"),
        _header_line("   GPS", "TIME SYSTEM ID"),
        *wl_lines,
        _header_line("", "END OF HEADER"),
        "AS G01  2016 01 01 00 00  0.000000  1    1.234567890123E-04",
    ]) + "\n"


EPOCH = (2016, 1, 1, 0, 0, 0.0)


def _write(tmp_path, text, name="grg18775.clk"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_wl_records_in_clock_header(tmp_path):
    path = _write(tmp_path, _grg_clock_file([_wl("G01", EPOCH, [-0.123], comment=True),
                                             _wl("G05", EPOCH, [0.456], comment=True)]))
    ds = read_wl_bias(path)
    assert ds["wl_bias_cyc"].dims == ("time", "sv")
    assert list(ds.sv.values) == ["G01", "G05"]
    assert ds.time.values[0] == np.datetime64("2016-01-01T00:00")
    np.testing.assert_allclose(ds["wl_bias_cyc"].values, [[-0.123, 0.456]])
    assert np.isnan(ds["wl_bias_sigma_cyc"].values).all()
    assert ds["wl_bias_cyc"].attrs["units"] == "1"
    assert ds.attrs["time_system"] == "GPS" and ds.attrs["n_records"] == 2


def test_wl_records_two_days_with_sigma(tmp_path):
    day2 = (2016, 1, 2, 0, 0, 0.0)
    text = "\n".join([_wl("G01", EPOCH, [0.25, 0.01]), _wl("G02", EPOCH, [-0.5, 0.02]),
                      _wl("G01", day2, [0.26, 0.01])]) + "\n"
    ds = read_wl_bias(_write(tmp_path, text, "wl.txt"))
    assert ds.sizes == {"time": 2, "sv": 2}
    assert ds["wl_bias_cyc"].sel(sv="G01").values.tolist() == [0.25, 0.26]
    assert np.isnan(ds["wl_bias_cyc"].sel(sv="G02", time="2016-01-02").item())
    assert ds["wl_bias_sigma_cyc"].sel(sv="G02").values[0] == pytest.approx(0.02)


def _expect(path, line, field):
    with pytest.raises(FormatError) as info:
        read_wl_bias(path)
    err = info.value
    assert err.line == line and err.field == field and path.name in str(err)
    return err


def test_wl_errors(tmp_path):
    good = _wl("G01", EPOCH, [-0.123], comment=True)
    # lines 1-2 are header records; the first WL line is line 3
    for bad, field in ((good.replace("-1.23", "-1.2x"), "WL value"),
                       (good.replace("-1.230000000000E-01", "                NaN"), "WL value"),
                       (good.replace("WL G01 ", "WL X1  "), "WL satellite"),
                       (good.replace("2016  1", "2016 13"), "WL epoch"),
                       (good[:37], "WL value")):
        _expect(_write(tmp_path, _grg_clock_file([bad])), 3, field)
    err = _expect(_write(tmp_path, _grg_clock_file([good, good])), 4, "WL")
    assert "G01" in err.message
    _expect(_write(tmp_path, _grg_clock_file([])), None, "WL")


# --------------------------------------------------------------------------------------------
# Writer (authority: the documented record layout, as built by _wl above, and the reader)


def _wl_dataset():
    times = np.array(["2016-01-01T00:00", "2016-01-02T00:00:30.25"], dtype="datetime64[ns]")
    values = np.array([[-0.123, 2.718281828459045, np.nan], [0.25, -3.5e-5, 1.0]])
    sigma = np.array([[np.nan, 0.01, np.nan], [0.02, np.nan, np.nan]])
    return xr.Dataset({"wl_bias_cyc": (("time", "sv"), values),
                       "wl_bias_sigma_cyc": (("time", "sv"), sigma)},
                      coords={"time": times, "sv": ["G01", "G05", "C19"]})


def test_write_records_have_the_documented_layout():
    lines = wl_bias_records(_wl_dataset())
    # columns 1-40 as the constructed records; values in Fortran E19.12 ("-0.123...E+00",
    # as RINEX clock files and the reader docstring write them)
    for line, (sv, epoch, values) in zip(lines, (("G01", EPOCH, [-0.123]),
                                                 ("G05", EPOCH, [2.718281828459045, 0.01]),
                                                 ("G01", (2016, 1, 2, 0, 0, 30.25),
                                                  [0.25, 0.02]))):
        assert line[:40] == _wl(sv, epoch, values)[:40]
        np.testing.assert_allclose([float(v) for v in line[40:].split()], values, rtol=1e-12)
    assert lines[0][40:] == "-0.123000000000E+00"
    assert len(lines) == 5   # the NaN (time, sv) is skipped
    assert max(len(line) for line in lines if line[34:37] == "  1") <= 60   # fits a COMMENT


def test_write_roundtrip(tmp_path):
    ds = _wl_dataset()
    for name in ("wl.txt", "wl.txt.gz"):
        write_wl_bias(ds, tmp_path / name)
        back = read_wl_bias(tmp_path / name)
        ref = ds.sel(sv=sorted(ds.sv.values))
        np.testing.assert_array_equal(back.time.values, ref.time.values)
        # E19.12: 12 significant digits
        np.testing.assert_allclose(back.wl_bias_cyc, ref.wl_bias_cyc, rtol=1e-12, atol=0)
        np.testing.assert_allclose(back.wl_bias_sigma_cyc, ref.wl_bias_sigma_cyc, rtol=1e-12)


def test_write_into_grg_style_clock_header(tmp_path):
    # GRG style: the WL records as COMMENT lines of a RINEX clock file; both readers agree
    ds = _wl_dataset().isel(time=[0])
    clk = xr.Dataset({"clk_s": (("time", "sv"), [[1.25e-4, -3.5e-5, 2.0e-6]])},
                     coords={"time": ds.time.values, "sv": ["C19", "G01", "G05"]},
                     attrs={"time_system": "GPS"})
    path = tmp_path / "grg.clk"
    write_rinex_clock(clk, path, comments=tuple(
        line for line in wl_bias_records(ds) if line[34:37] == "  1"))
    wl = read_wl_bias(path)
    assert list(wl.sv.values) == ["G01"]
    assert wl.wl_bias_cyc.item() == pytest.approx(-0.123, rel=1e-12)
    np.testing.assert_allclose(read_rinex_clock(path).clk_s.values, clk.clk_s.values,
                               rtol=1e-11)


def test_write_errors(tmp_path):
    ds = _wl_dataset()
    with pytest.raises(ValueError, match="G001"):
        write_wl_bias(ds.assign_coords(sv=["G001", "G05", "C19"]), tmp_path / "bad.txt")
    with pytest.raises(ValueError, match="no finite"):
        write_wl_bias(ds * np.nan, tmp_path / "bad.txt")
    with pytest.raises(ValueError, match="wl_bias_cyc"):
        write_wl_bias(ds.drop_vars("wl_bias_cyc"), tmp_path / "bad.txt")
    assert not (tmp_path / "bad.txt").exists()
