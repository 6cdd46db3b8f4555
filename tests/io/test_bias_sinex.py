"""Tests of leopod.io.bias_sinex on real Bias-SINEX files and on broken copies."""

from __future__ import annotations

import logging

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._text import FormatError, read_lines
from leopod.io.bias_sinex import osb, read_bias_sinex
from leopod.io.bias_sinex_write import write_bias_sinex

WHU = "products_2008-279_whu/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z"
COD = "products_2023-189_cod_osb/COD0OPSFIN_20231890000_01D_01D_OSB.BIA"


@pytest.mark.shared
def test_whu_osb_values_and_header(shared_data):
    ds = read_bias_sinex(shared_data / WHU)
    assert ds.sizes["bias"] == 128  # "%=BIA 1.00 WHU ... A 00000128"
    # WHU...ABS.BIA line 50:
    # " OSB  G035 G05           C1W       2008:279:00000 2008:279:86400 ns   ...   4.563   0.000"
    rec = ds.isel(bias=4)
    assert (str(rec.prn.values), str(rec.svn.values), str(rec.obs1.values)) == \
        ("G05", "G035", "C1W")
    assert rec.value_s == pytest.approx(4.563e-9)
    assert rec.value_m == pytest.approx(4.563e-9 * C_LIGHT_M_S)
    assert rec.start.values == np.datetime64("2008-10-05T00:00")
    assert rec.end.values == np.datetime64("2008-10-06T00:00")  # 2008:279:86400
    # line 146: " OSB  G035 G05           L2W  ...  ns   -6.871"
    assert osb(ds, "G05", "L2W", "2008-10-05T12:00") == pytest.approx(-6.871e-9 * C_LIGHT_M_S)
    assert ds.attrs["bias_mode"] == "ABSOLUTE" and ds.attrs["time_system"] == "GPS"
    assert ds.attrs["observation_sampling"] == 30
    assert ds.attrs["satellite_clock_reference_observables_G"] == "L1C L2W"
    assert ds.attrs["bias_timing"] == "window"
    for name in ds.data_vars:
        assert ds[name].attrs["units"] in ("s", "m", "s s-1") and ds[name].attrs["long_name"]
    assert all(isinstance(v, (str, int, float)) for v in ds.attrs.values())


@pytest.mark.shared
def test_whu_osb_outside_window(shared_data):
    ds = read_bias_sinex(shared_data / WHU)
    with pytest.raises(KeyError, match="G05 C1W at 2008-10-06"):
        osb(ds, "G05", "C1W", "2008-10-06T00:00")  # end of window is exclusive
    with pytest.raises(KeyError, match="no OSB record of G05 C5X"):
        osb(ds, "G05", "C5X", "2008-10-05T12:00")


@pytest.mark.shared
def test_cod_osb_code_phase_and_stations(shared_data):
    ds = read_bias_sinex(shared_data / COD)
    assert ds.sizes["bias"] == 14565
    stations = ds["station"].values != ""
    assert stations.sum() == 13910 and (~stations).sum() == 655
    # COD0OPSFIN...OSB.BIA line 90: " OSB  G050 G05           C1C  ...  ns   -6.2476   0.0001"
    assert osb(ds, "G05", "C1C", "2023-07-08T06:00") == pytest.approx(-6.2476e-9 * C_LIGHT_M_S)
    # line 14281: " OSB  G063 G01           L1C  ...  ns   0.75626   0.00000"
    assert osb(ds, "G01", "L1C", "2023-07-08T23:59:59") == \
        pytest.approx(0.75626e-9 * C_LIGHT_M_S)
    # line 372: " OSB  E    E   ABMF      C1C  ...  ns   -6.6103   0.0538"
    abmf = ds.where((ds.station == "ABMF") & (ds.prn == "E") & (ds.obs1 == "C1C"), drop=True)
    assert abmf.value_s.item() == pytest.approx(-6.6103e-9)
    assert abmf.sigma_s.item() == pytest.approx(0.0538e-9)
    assert ds.attrs["apc_model"] == "IGS20"
    assert ds.attrs["satellite_clock_reference_observables_E"] == "C1C C5Q"


@pytest.mark.shared
def test_code_bia_windows_per_signal(shared_data):
    ds = read_bias_sinex(shared_data / "format_fixtures" / "code.bia")
    # code.bia line 71: " OSB  G049 G01  C1C  2024:237:00000 2024:266:00000 ns  -6.0527  0.0178"
    # line 72:          " OSB  G049 G01  C1W  2024:237:00000 2024:267:00000 ns  -5.0577  0.0069"
    t = "2024-09-22T12:00"  # day 266
    assert osb(ds, "G01", "C1W", t) == pytest.approx(-5.0577e-9 * C_LIGHT_M_S)
    with pytest.raises(KeyError):
        osb(ds, "G01", "C1C", t)
    assert osb(ds, "G01", "C1C", "2024-08-24") == pytest.approx(-6.0527e-9 * C_LIGHT_M_S)


# --------------------------------------------------------------------------------------------
# Constructed files (written here from the Bias-SINEX 1.00 record layout, not real files)

_HEAD = ("%=BIA 1.00 TST 2020:001:00000 TST 2020:001:00000 2020:002:00000 A {n:08d}\n"
         "+BIAS/SOLUTION\n"
         "*BIAS SVN_ PRN STATION__ OBS1 OBS2 BIAS_START____ BIAS_END______ UNIT "
         "__ESTIMATED_VALUE____ _STD_DEV___\n")


def _record(prn, obs, start, end, unit, value):
    return (f" OSB  {'G063':4s} {prn:3s} {'':9s} {obs:4s} {'':4s} {start:14s} {end:14s} "
            f"{unit:4s} {value:21.4f} {0.0:11.4f}\n")


def _write(tmp_path, records):
    path = tmp_path / "constructed.bia"
    path.write_text(_HEAD.format(n=len(records)) + "".join(records)
                    + "-BIAS/SOLUTION\n%=ENDBIA\n")
    return path


def test_constructed_cycles_converted_with_carrier_frequency(tmp_path):
    path = _write(tmp_path, [_record("G01", "L2W", "2020:001:00000", "2020:002:00000",
                                     "cyc", 0.25)])
    ds = read_bias_sinex(path)
    f2 = 120 * 10.23e6  # GPS L2, IS-GPS-200
    assert ds.value_s.item() == pytest.approx(0.25 / f2)
    assert ds.value_m.item() == pytest.approx(0.25 * C_LIGHT_M_S / f2)
    assert ds.unit.item() == "cyc"


def test_constructed_time_stamps_are_interpolated(tmp_path):
    path = _write(tmp_path, [_record("G01", "C1W", "2020:001:00000", "", "ns", 1.0),
                             _record("G01", "C1W", "2020:001:03600", "", "ns", 3.0)])
    ds = read_bias_sinex(path)
    assert ds.attrs["bias_timing"] == "epoch" and np.isnat(ds.end.values).all()
    assert osb(ds, "G01", "C1W", "2020-01-01T00:30") == pytest.approx(2e-9 * C_LIGHT_M_S)
    with pytest.raises(KeyError, match="time stamps span"):
        osb(ds, "G01", "C1W", "2020-01-01T02:00")


def test_constructed_open_bounds(tmp_path):
    path = _write(tmp_path, [_record("G01", "C1W", "0000:000:00000", "0000:000:00000",
                                     "ns", 1.5)])
    ds = read_bias_sinex(path)
    assert np.isnat(ds.start.values[0]) and np.isnat(ds.end.values[0])
    assert osb(ds, "G01", "C1W", "1999-01-01") == pytest.approx(1.5e-9 * C_LIGHT_M_S)


def test_constructed_errors(tmp_path):
    win = ("2020:001:00000", "2020:002:00000")
    # mixed windows and stamps: the second record (line 5) has a blank BIAS_END
    path = _write(tmp_path, [_record("G01", "C1W", *win, "ns", 1.0),
                             _record("G02", "C1W", "2020:001:00000", "", "ns", 1.0)])
    with pytest.raises(FormatError) as info:
        read_bias_sinex(path)
    assert info.value.line == 5 and info.value.field == "BIAS_END"
    # unknown unit, GLONASS cycles (frequency channel unknown), bad day of year
    for rec, field in ((_record("G01", "C1W", *win, "ps", 1.0), "UNIT"),
                       (_record("R01", "L1C", *win, "cyc", 1.0), "UNIT"),
                       (_record("G01", "C1W", "2020:400:00000", win[1], "ns", 1.0),
                        "BIAS_START")):
        with pytest.raises(FormatError) as info:
            read_bias_sinex(_write(tmp_path, [rec]))
        assert info.value.line == 4 and info.value.field == field


# --------------------------------------------------------------------------------------------
# Broken copies of the real WHU file (line numbers are those of the decompressed file)


def _broken(shared_data, tmp_path, edit):
    lines = edit(read_lines(shared_data / WHU))
    path = tmp_path / "broken.bia"
    path.write_text("\n".join(lines) + "\n")
    return path


def _expect(path, line, field):
    with pytest.raises(FormatError) as info:
        read_bias_sinex(path)
    err = info.value
    assert err.line == line and err.field == field and "broken.bia" in str(err)
    return err


def _replace(lineno, old, new):
    def edit(lines):
        assert old in lines[lineno - 1]
        lines[lineno - 1] = lines[lineno - 1].replace(old, new, 1)
        return lines
    return edit


@pytest.mark.shared
def test_broken_truncated_mid_record(shared_data, tmp_path):
    # cut in the middle of line 50 (the G05 C1W record): the block is never closed
    def cut(lines):
        return lines[:49] + [lines[49][:60]]
    _expect(_broken(shared_data, tmp_path, cut), 50, "-BIAS/SOLUTION")


@pytest.mark.shared
def test_broken_short_record_and_count(shared_data, tmp_path, caplog):
    def short(lines):
        lines[49] = lines[49][:80]
        return lines
    _expect(_broken(shared_data, tmp_path, short), 50, "ESTIMATED_VALUE")
    # Issue 24: a count that disagrees with a *complete* file (closed by %=ENDBIA) is a
    # warning, as in real CODE 2021 OSB products ("%=BIA announces 6888 records,
    # +BIAS/SOLUTION holds 6844"); a file that ends before %=ENDBIA is refused.
    with caplog.at_level(logging.WARNING, logger="leopod.io.bias_sinex"):
        ds = read_bias_sinex(_broken(shared_data, tmp_path, lambda lines: lines[:49] + lines[50:]))
    assert ds.sizes["bias"] == 127
    assert "128" in caplog.text and "127" in caplog.text
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[:-1]), 174, "%=ENDBIA")


@pytest.mark.shared
def test_broken_non_numeric_and_nan(shared_data, tmp_path):
    err = _expect(_broken(shared_data, tmp_path, _replace(50, "4.563", "4.5x3")), 50,
                  "ESTIMATED_VALUE")
    assert "4.5x3" in err.message
    _expect(_broken(shared_data, tmp_path, _replace(50, "4.563", "  nan")), 50,
            "ESTIMATED_VALUE")
    _expect(_broken(shared_data, tmp_path, _replace(50, "0.000", "  inf")), 50, "STD_DEV")


@pytest.mark.shared
def test_broken_header_and_blocks(shared_data, tmp_path):
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[1:]), 1, "%=BIA")
    no_solution = _broken(shared_data, tmp_path, lambda lines: lines[:43] + lines[174:])
    _expect(no_solution, None, "+BIAS/SOLUTION")


# --------------------------------------------------------------------------------------------
# Writer: round trips (authority: the reader, and the layout of the real WHU/CODE files)


@pytest.mark.shared
@pytest.mark.parametrize("name", [WHU, COD])
def test_write_roundtrip_real_files(shared_data, tmp_path, name):
    # real file -> Dataset -> written file -> the same Dataset (values, coordinates, attrs)
    ds = read_bias_sinex(shared_data / name)
    path = tmp_path / "roundtrip.bia"
    write_bias_sinex(ds, path)
    xr.testing.assert_identical(read_bias_sinex(path), ds)


@pytest.mark.shared
def test_write_layout_matches_real_whu_file(shared_data, tmp_path):
    real = read_lines(shared_data / WHU)
    path = tmp_path / "whu.bia"
    write_bias_sinex(read_bias_sinex(shared_data / WHU), path, decimals=3)
    ours = read_lines(path)
    solution_header = next(line for line in real if line.startswith("*BIAS SVN_"))
    # header line: the same fields; WHU writes the day end as 2008:279:86400, we (like CODE)
    # as 2008:280:00000, the same instant
    assert ours[0] == real[0].replace("2008:279:86400", "2008:280:00000")
    # block lines of the real file that the writer reproduces character for character
    for line in (" OBSERVATION_SAMPLING                              30",
                 " PARAMETER_SPACING                              86400",
                 " DETERMINATION_METHOD                    COMBINED_ANALYSIS",
                 " BIAS_MODE                               ABSOLUTE",
                 " TIME_SYSTEM                             G",
                 " DESCRIPTION        PRIDE Lab, GNSS Research Center, Wuhan University",
                 solution_header, "-BIAS/SOLUTION", "%=ENDBIA"):
        assert line in ours, line
    # records: same text up to the window end, same value and std columns
    rec_real = real[real.index(solution_header) + 1]
    rec_ours = ours[ours.index(solution_header) + 1]
    assert rec_ours[:50] == rec_real[:50]
    assert rec_ours[65:103] == rec_real[65:103]


def test_write_constructed_cycles_stamps_and_blanks(tmp_path):
    records = [_record("G01", "L2W", "2020:001:00000", "", "cyc", 0.25),
               _record("G01", "L2W", "2020:001:03600", "", "cyc", -0.125)]
    ds = read_bias_sinex(_write(tmp_path, records))
    out = tmp_path / "written.bia.gz"
    write_bias_sinex(ds, out)
    back = read_bias_sinex(out)
    assert back.attrs["bias_timing"] == "epoch" and list(back.unit.values) == ["cyc", "cyc"]
    np.testing.assert_allclose(back.value_s, ds.value_s, rtol=1e-12)
    assert np.isnan(back.slope_s_per_s).all()
    assert np.isnat(back.end.values).all()


def test_write_errors(tmp_path):
    good = read_bias_sinex(_write(tmp_path, [_record("G01", "C1W", "2020:001:00000",
                                                     "2020:002:00000", "ns", 1.0)]))
    bad_value = good.copy(deep=True)
    bad_value["value_s"][:] = np.nan
    bad_unit = good.assign_coords(unit=("bias", ["cyc"]))   # cycles of a code observable
    bad_time = good.assign_coords(start=("bias", [np.datetime64("2020-01-01T00:00:00.5")]))
    long_prn = good.assign_coords(prn=("bias", ["G001"]))
    for ds, match in ((bad_value, "not finite"), (bad_unit, "unit 'cyc'"),
                      (bad_time, "whole second"), (long_prn, "PRN")):
        with pytest.raises(ValueError, match=match):
            write_bias_sinex(ds, tmp_path / "bad.bia")
        assert not (tmp_path / "bad.bia").exists()   # no partial output


def test_write_open_bounds(tmp_path):
    ds = read_bias_sinex(_write(tmp_path, [_record("G01", "C1W", "0000:000:00000",
                                                   "0000:000:00000", "ns", 1.5)]))
    out = tmp_path / "open.bia"
    write_bias_sinex(ds, out)
    assert " 0000:000:00000 0000:000:00000 ns" in out.read_text()
    back = read_bias_sinex(out)
    xr.testing.assert_equal(back, ds)   # values and coordinates (the writer adds TIME_SYSTEM)
    assert {k: back.attrs[k] for k in ds.attrs} == ds.attrs
