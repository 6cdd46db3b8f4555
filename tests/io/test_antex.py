"""Tests of leopod.io.antex on real IGS/AIUB ANTEX files and on broken copies."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from leopod.io._text import FormatError
from leopod.io.antex import read_antex

# --------------------------------------------------------------------------------------------
# A small ANTEX 1.4 file constructed for these tests (not a real file): one receiver antenna
# with a 90-degree azimuth grid whose PCV is the plane pcv = 0.1*zen + 0.01*az [mm], so that
# linear/bilinear interpolation must reproduce the plane exactly.


def _label(text: str, label: str) -> str:
    return f"{text:<60}{label}"


def _plane_row(az: float, zeniths) -> str:
    return f"{az:8.1f}" + "".join(f"{0.1 * z + 0.01 * az:8.2f}" for z in zeniths)


def _constructed_antex() -> str:
    zen = [0, 30, 60, 90]
    lines = [
        _label("     1.4            M", "ANTEX VERSION / SYST"),
        _label("A", "PCV TYPE / REFANT"),
        _label("", "END OF HEADER"),
        _label("", "START OF ANTENNA"),
        _label("TEST_ANT        NONE", "TYPE / SERIAL NO"),
        _label("     90.0", "DAZI"),
        _label("     0.0  90.0  30.0", "ZEN1 / ZEN2 / DZEN"),
        _label("     1", "# OF FREQUENCIES"),
        _label("   G01", "START OF FREQUENCY"),
        _label("      1.00      2.00    100.00", "NORTH / EAST / UP"),
        "   NOAZI" + "".join(f"{0.1 * z:8.2f}" for z in zen),
        *[_plane_row(az, zen) for az in (0.0, 90.0, 180.0, 270.0, 360.0)],
        _label("   G01", "END OF FREQUENCY"),
        _label("", "END OF ANTENNA"),
    ]
    return "\n".join(lines) + "\n"


@pytest.fixture
def plane_atx(tmp_path):
    path = tmp_path / "plane.atx"
    path.write_text(_constructed_antex())
    return path


def test_constructed_receiver_pco_and_exact_interpolation(plane_atx):
    ant = read_antex(plane_atx).receiver("TEST_ANT")  # type given without radome -> NONE
    assert ant.kind == "receiver"
    np.testing.assert_allclose(ant.pco_m("G01"), [0.001, 0.002, 0.100])
    zen = np.array([0.0, 12.5, 44.0, 89.9])
    az = np.array([0.0, 45.0, 200.0, 359.0])
    np.testing.assert_allclose(ant.pcv_m("G01", zen, az), 1e-3 * (0.1 * zen + 0.01 * az),
                               atol=1e-12)
    np.testing.assert_allclose(ant.pcv_m("G01", zen), 1e-3 * 0.1 * zen, atol=1e-12)
    # azimuth is taken modulo 360
    assert ant.pcv_m("G01", 30.0, -90.0) == pytest.approx(1e-3 * (3.0 + 2.7))


def test_constructed_out_of_range_and_unknown_frequency(plane_atx):
    ant = read_antex(plane_atx).receiver("TEST_ANT NONE")
    with pytest.raises(ValueError, match="outside the pattern range"):
        ant.pcv_m("G01", 95.0)
    assert ant.pcv_m("G01", 95.0, outside="nearest") == pytest.approx(0.009)
    assert np.isnan(ant.pcv_m("G01", 95.0, outside="nan"))
    with pytest.raises(KeyError, match="G02.*available: G01"):
        ant.pco_m("G02")
    with pytest.raises(KeyError, match="no receiver antenna 'NOPE'"):
        read_antex(plane_atx).receiver("NOPE")


def test_constructed_rms_block_is_skipped(tmp_path):
    lines = _constructed_antex().splitlines()
    end_freq = next(i for i, ln in enumerate(lines) if ln.endswith("END OF FREQUENCY"))
    rms = [_label("   G01", "START OF FREQ RMS"),
           _label("      9.00      9.00      9.00", "NORTH / EAST / UP"),
           "   NOAZI" + "    9.00" * 4,
           *[f"{az:8.1f}" + "    9.00" * 4 for az in (0.0, 90.0, 180.0, 270.0, 360.0)],
           _label("   G01", "END OF FREQ RMS")]
    path = tmp_path / "rms.atx"
    path.write_text("\n".join(lines[:end_freq + 1] + rms + lines[end_freq + 1:]) + "\n")
    ant = read_antex(path).receiver("TEST_ANT")
    np.testing.assert_allclose(ant.pco_m("G01"), [0.001, 0.002, 0.100])
    assert ant.pcv_m("G01", 30.0, 90.0) == pytest.approx(1e-3 * (3.0 + 0.9))


def test_constructed_to_dataset_schema(plane_atx):
    ds = read_antex(plane_atx).receiver("TEST_ANT").to_dataset()
    assert ds["pcv_m"].dims == ("frequency", "azimuth_deg", "zenith_deg")
    assert ds["pco_m"].dims == ("frequency", "neu")
    assert list(ds["neu"].values) == ["north", "east", "up"]
    np.testing.assert_allclose(ds["azimuth_deg"], [0, 90, 180, 270, 360])
    for name in ds.data_vars:
        assert ds[name].attrs["units"] == "m" and ds[name].attrs["long_name"]
    assert all(isinstance(v, (str, int, float)) for v in ds.attrs.values())


# --------------------------------------------------------------------------------------------
# Real files


@pytest.mark.shared
def test_igs05_1627_satellite_by_epoch(shared_data):
    atx = read_antex(shared_data / "antex" / "igs05_1627.atx")
    # igs05_1627.atx, line 301: "BLOCK IIA           G05                 G035      1993-054A"
    # line 307-308: VALID FROM 1993 8 30 / VALID UNTIL 2009 6 8 23 59 59.9999999
    # line 310: "    279.00      0.00   2463.00                              NORTH / EAST / UP"
    g05 = atx.satellite("G05", np.datetime64("2008-10-05T12:00"))
    assert (g05.kind, g05.svn, g05.cospar_id) == ("satellite", "G035", "1993-054A")
    np.testing.assert_allclose(g05.pco_m("G01"), [0.279, 0.0, 2.463])
    assert g05.valid_until == np.datetime64("2009-06-08T23:59:59.9999999", "ns")
    # line 311: "   NOAZI   -0.80   -0.90   -0.90   -0.80   -0.40    0.20 ..." (nadir 0,1,2,..)
    assert g05.pcv_m("G01", 0.0) == pytest.approx(-0.0008)
    assert g05.pcv_m("G01", 4.5) == pytest.approx(-0.0001)  # mean of -0.40 and 0.20 mm
    assert g05.pco_axes == ("x", "y", "z")


@pytest.mark.shared
def test_igs05_1627_validity_periods(shared_data):
    atx = read_antex(shared_data / "antex" / "igs05_1627.atx")
    # lines 160-165: G01 = G032 until 2008-10-16 23:59:59.9999999;
    # lines 178-184: G01 = G037 from 2008-10-23, z offset 2220.00 mm (line 187)
    assert atx.satellite("G01", "2008-10-16T23:59:59").svn == "G032"
    g037 = atx.satellite("G01", "2008-11-01")
    assert g037.svn == "G037" and g037.pco_m("G02")[2] == pytest.approx(2.220)
    with pytest.raises(KeyError, match=r"G01 valid at 2008-10-20.*G032.*G037"):
        atx.satellite("G01", "2008-10-20")
    with pytest.raises(KeyError, match="G99.*PRN absent"):
        atx.satellite("G99", "2008-10-20")


@pytest.mark.shared
def test_igs05_1627_receiver_grid(shared_data):
    atx = read_antex(shared_data / "antex" / "igs05_1627.atx")
    ant = atx.receiver("LEIAR25.R4 LEIT")
    # igs05_1627.atx lines 9747-9750 (LEIAR25.R4 LEIT, G01):
    #   "      0.60      0.98    158.30                              NORTH / EAST / UP"
    #   "     0.0    0.00    0.14    0.60    1.31    2.13 ..."  (zenith 0,5,10,15,20)
    #   "     5.0    0.00    0.14    0.60    1.31    2.11 ..."
    np.testing.assert_allclose(ant.pco_m("G01"), [0.0006, 0.00098, 0.1583])
    assert ant.pcv_m("G01", 15.0, 0.0) == pytest.approx(0.00131)
    # centre of the cell az 0..5, zen 15..20: mean of 1.31, 2.13, 1.31, 2.11 mm
    assert ant.pcv_m("G01", 17.5, 2.5) == pytest.approx(1e-3 * (1.31 + 2.13 + 1.31 + 2.11) / 4)
    assert ant.dazi_deg == 5.0 and ant.to_dataset()["pcv_m"].shape == (2, 73, 19)


@pytest.mark.shared
def test_goce_leo_antenna_grid(shared_data):
    ant = read_antex(shared_data / "antex" / "GOCE_MAIN_0001.ATX").receiver("GOCE")
    # GOCE_MAIN_0001.ATX line 21: "GOCE                L15"; line 23: DAZI 1.0;
    # line 27: "     -0.18      3.51     81.11"; line 30: "     1.0    0.25    2.08    2.65 ..."
    assert ant.serial == "L15" and ant.dazi_deg == 1.0
    np.testing.assert_allclose(ant.pco_m("G01"), [-0.00018, 0.00351, 0.08111])
    ds = ant.to_dataset()
    assert ds["pcv_m"].shape == (2, 361, 91)
    assert ds["pcv_m"].sel(frequency="G01", azimuth_deg=1.0, zenith_deg=2.0) == \
        pytest.approx(0.00265)
    assert ant.pcv_m("G01", 1.5, 1.0) == pytest.approx(1e-3 * (2.08 + 2.65) / 2)


@pytest.mark.shared
def test_igs20_small_bds3_frequencies(shared_data):
    atx = read_antex(shared_data / "antex" / "igs20-small.atx")
    # igs20-small.atx lines 79-97: C19 = C201 (BEIDOU-3M-CAST) 2017-11-05 .. 2018-06-12,
    # C01 (B1C) "   -208.10     -2.70   1487.20", C05 (B2a) "   -212.60     -0.90   1096.50"
    c19 = atx.satellite("C19", "2018-01-01")
    assert c19.svn == "C201"
    assert c19.frequencies == ("C01", "C02", "C05", "C06", "C07", "C08")
    np.testing.assert_allclose(c19.pco_m("C01"), [-0.2081, -0.0027, 1.4872])
    np.testing.assert_allclose(c19.pco_m("C05"), [-0.2126, -0.0009, 1.0965])
    # lines 113-119: from 2018-06-14 08:47 C19 is C102 (BEIDOU-3SM-CAST)
    assert atx.satellite("C19", "2018-07-01").svn == "C102"


@pytest.mark.shared
@pytest.mark.parametrize("name", ["antex/igs05_1604.atx", "antex/igs08_1719.atx.gz",
                                  "antex/igs14-small.atx",
                                  "grace-a_2007-080/igs05_1402.atx.gz"])
def test_other_real_files_read(shared_data, name):
    atx = read_antex(shared_data / name)
    assert "G01" in atx.prns and len(atx) > 10
    assert atx.attrs["pcv_type"] == "A"


@pytest.mark.shared
def test_igs05_1627_reads_every_antenna(shared_data):
    """The whole file is read: one entry per "START OF ANTENNA" record (323) and the 56
    distinct GPS/GLONASS PRNs of its "TYPE / SERIAL NO" records (both counted in the text
    itself, ANTEX 1.4, Rothacher & Schmid 2010). Reading time: benchmarks/readers.py."""
    path = shared_data / "antex" / "igs05_1627.atx"
    text = path.read_text()
    prns = {line[20:23] for line in text.splitlines()
            if line[60:].startswith("TYPE / SERIAL NO") and line[20:21] in "GREC"
            and line[21:23].isdigit()}
    atx = read_antex(path)
    assert len(atx) == text.count("START OF ANTENNA") == 323
    assert set(atx.prns) == prns and len(prns) == 56


# --------------------------------------------------------------------------------------------
# Broken copies of igs14-small.atx (line numbers are those of the real file)


def _broken(shared_data, tmp_path, edit):
    lines = (shared_data / "antex" / "igs14-small.atx").read_text().splitlines()
    lines = edit(lines)
    path = tmp_path / "broken.atx"
    path.write_text("\n".join(lines) + "\n")
    return path


def _replace(lineno: int, old: str, new: str):
    def edit(lines):
        assert old in lines[lineno - 1]
        lines[lineno - 1] = lines[lineno - 1].replace(old, new, 1)
        return lines
    return edit


def _expect(path, line, field):
    with pytest.raises(FormatError) as info:
        read_antex(path)
    err = info.value
    assert err.line == line and field in err.field and "broken.atx" in str(err)
    return err


@pytest.mark.shared
def test_broken_truncated_inside_antenna(shared_data, tmp_path):
    # cut after line 24 (NORTH / EAST / UP of G02 of the first antenna)
    path = _broken(shared_data, tmp_path, lambda lines: lines[:24])
    _expect(path, 24, "END OF ANTENNA")


@pytest.mark.shared
def test_broken_missing_end_of_antenna(shared_data, tmp_path, caplog):
    # Issue 24: an antenna that the next START OF ANTENNA opens without END OF ANTENNA (as in
    # georust's igs14_small.atx) ends there, with a warning; at the end of the file it is an
    # error (truncated).
    lines = (shared_data / "antex" / "igs14-small.atx").read_text().splitlines()
    path = _broken(shared_data, tmp_path, lambda lines: lines[:26] + lines[27:])  # drop line 27
    with caplog.at_level(logging.WARNING, logger="leopod.io.antex"):
        atx = read_antex(path)
    assert len(atx.antennas) == len(read_antex(shared_data / "antex" / "igs14-small.atx")
                                    .antennas)
    assert "broken.atx:27: antenna opened at line 10 is not closed" in caplog.text
    last = max(k for k, line in enumerate(lines) if "END OF ANTENNA" in line)
    path = _broken(shared_data, tmp_path, lambda lines: lines[:last])
    err = _expect(path, last, "END OF ANTENNA")
    assert "not closed" in err.message


@pytest.mark.shared
def test_broken_zenith_grid(shared_data, tmp_path):
    # line 14: "     0.0  17.0   1.0      ZEN1 / ZEN2 / DZEN"
    _expect(_broken(shared_data, tmp_path, _replace(14, "  17.0   1.0", "  17.0   0.0")),
            14, "ZEN1 / ZEN2 / DZEN")
    _expect(_broken(shared_data, tmp_path, _replace(14, "  17.0   1.0", "  17.0   2.0")),
            14, "ZEN1 / ZEN2 / DZEN")


@pytest.mark.shared
def test_broken_pcv_value_count(shared_data, tmp_path):
    # line 21: "   NOAZI   -0.80   -0.90 ..." has 18 values (ZEN 0..17 by 1)
    err = _expect(_broken(shared_data, tmp_path, _replace(21, "   -0.80", "")), 21, "G01 NOAZI")
    assert "17 PCV values" in err.message and "18" in err.message


@pytest.mark.shared
def test_broken_non_numeric_and_nan(shared_data, tmp_path):
    err = _expect(_broken(shared_data, tmp_path, _replace(21, "   -0.90", "   -0.9x")),
                  21, "G01 NOAZI #2")
    assert "-0.9x" in err.message
    _expect(_broken(shared_data, tmp_path, _replace(21, "   -0.90", "     nan")), 21,
            "G01 NOAZI #2")
    # line 20: "    279.00      0.00   2319.50      NORTH / EAST / UP"
    _expect(_broken(shared_data, tmp_path, _replace(20, "    279.00", "    279.OO")), 20,
            "G01 NORTH")


@pytest.mark.shared
def test_broken_missing_header_record(shared_data, tmp_path):
    path = _broken(shared_data, tmp_path, lambda lines: lines[:1] + lines[2:])  # no PCV TYPE
    _expect(path, None, "PCV TYPE / REFANT")
    path = _broken(shared_data, tmp_path, lambda lines: lines[:8] + lines[9:])  # no END OF HEADER
    _expect(path, None, "END OF HEADER")
