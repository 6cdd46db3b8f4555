"""Tests of leopod.io.dcb on CODE's monthly DCB files and on broken copies."""

from __future__ import annotations

import pytest

from leopod.io._text import FormatError, read_lines
from leopod.io.dcb import read_code_dcb

P1C1 = "products_2008-279_whu/P1C10810_RINEX.DCB.Z"
P2C2 = "products_2008-279_whu/P2C20810_RINEX.DCB.Z"


@pytest.mark.shared
def test_p1c1_satellites_stations_and_attrs(shared_data):
    ds = read_code_dcb(shared_data / P1C1)
    # P1C10810_RINEX.DCB line 1:
    # "CODE'S MONTHLY GNSS P1-C1 DCB SOLUTION, YEAR 2008, MONTH 10      20-APR-12 17:09"
    assert ds.attrs["dcb_type"] == "P1-C1"
    assert (ds.attrs["year"], ds.attrs["month"]) == (2008, 10)
    assert (ds.attrs["period_start"], ds.attrs["period_end"]) == ("2008-10-01", "2008-11-01")
    # line 8: "G01                          -0.916       0.139"
    assert ds.dcb_s.sel(sv="G01").item() == pytest.approx(-0.916e-9)
    assert ds.dcb_sigma_s.sel(sv="G01").item() == pytest.approx(0.139e-9)
    # line 43: "R07                          -0.326       0.125"
    assert ds.dcb_s.sel(sv="R07").item() == pytest.approx(-0.326e-9)
    # line 401: "R     ZIM2                   -2.694       0.040"
    zim2 = (ds.station == "ZIM2") & (ds.system == "R")
    assert ds.station_dcb_s.where(zim2, drop=True).item() == pytest.approx(-2.694e-9)
    assert ds.sizes["sv"] == 50 and ds.sizes["receiver"] == 350
    for name in ds.data_vars:
        assert ds[name].attrs["units"] == "s" and ds[name].attrs["long_name"]


@pytest.mark.shared
def test_p2c2(shared_data):
    ds = read_code_dcb(shared_data / P2C2)
    assert ds.attrs["dcb_type"] == "P2-C2"
    # P2C20810_RINEX.DCB line 15: "R07                         -10.904       0.088"
    assert ds.dcb_s.sel(sv="R07").item() == pytest.approx(-10.904e-9)
    # line 45: "G     ZIM2                   -0.019       0.008"
    assert ds.station_dcb_sigma_s.where(ds.station == "ZIM2", drop=True).item() == \
        pytest.approx(0.008e-9)
    assert "G01" not in ds.sv.values  # P2-C2 exists only for a few satellites


def test_constructed_p1p2_with_domes_and_second_block(tmp_path):
    # Constructed from the layout of the CODE files (not a real file): a P1-P2 file with a
    # Bernese station name + DOMES number and a trailing block that must be ignored.
    text = ("CODE'S MONTHLY GPS P1-P2 DCB SOLUTION, YEAR 2020, MONTH 12      04-JAN-21 06:46\n"
            + "-" * 80 + "\n\n"
            "DIFFERENTIAL (P1-P2) CODE BIASES FOR SATELLITES AND RECEIVERS:\n\n"
            "PRN / STATION NAME        VALUE (NS)  RMS (NS)\n"
            "***   ****************    *****.***   *****.***\n"
            "G01                          10.123       0.005\n"
            "G     ZECK 12351M001          7.962       0.035\n\n"
            "DIFFERENTIAL (INTER-FREQ) CODE BIASES FOR SATELLITES AND RECEIVERS:\n"
            "R     ABCD 12345M001          1.000       0.100\n")
    path = tmp_path / "P1P22012.DCB"
    path.write_text(text)
    ds = read_code_dcb(path)
    assert ds.attrs["dcb_type"] == "P1-P2" and ds.attrs["period_end"] == "2021-01-01"
    assert ds.dcb_s.sel(sv="G01").item() == pytest.approx(10.123e-9)
    assert list(ds.station.values) == ["ZECK 12351M001"]
    assert ds.station_dcb_s.item() == pytest.approx(7.962e-9)


# --------------------------------------------------------------------------------------------
# Broken copies of P2C20810_RINEX.DCB (line numbers of the decompressed file)


def _broken(shared_data, tmp_path, edit):
    lines = edit(read_lines(shared_data / P2C2))
    path = tmp_path / "broken.DCB"
    path.write_text("\n".join(lines) + "\n")
    return path


def _expect(path, line, field):
    with pytest.raises(FormatError) as info:
        read_code_dcb(path)
    err = info.value
    assert err.line == line and err.field == field and "broken.DCB" in str(err)
    return err


def _set(lineno, text):
    def edit(lines):
        lines[lineno - 1] = text
        return lines
    return edit


@pytest.mark.shared
def test_broken_truncated_row(shared_data, tmp_path):
    # line 15 "R07                         -10.904       0.088" cut before the RMS
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[:14] + [lines[14][:36]]),
            15, "RMS (NS)")


@pytest.mark.shared
def test_broken_non_numeric_nan_and_bad_row(shared_data, tmp_path):
    err = _expect(_broken(shared_data, tmp_path,
                          _set(15, "R07                         -10.9O4       0.088")),
                  15, "VALUE (NS)")
    assert "-10.9O4" in err.message
    _expect(_broken(shared_data, tmp_path,
                    _set(15, "R07                             nan       0.088")),
            15, "VALUE (NS)")
    _expect(_broken(shared_data, tmp_path,
                    _set(15, "R7                          -10.904       0.088")),
            15, "PRN / STATION NAME")
    _expect(_broken(shared_data, tmp_path,
                    _set(15, "G07                           0.371       0.002")),
            15, "PRN")  # G07 is already on line 8


@pytest.mark.shared
def test_broken_missing_headers(shared_data, tmp_path):
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[:3] + lines[4:]),
            None, "DIFFERENTIAL (..) CODE BIASES")
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[:5] + lines[6:]),
            None, "PRN / STATION NAME")
    _expect(_broken(shared_data, tmp_path, lambda lines: lines[:6] + lines[7:]), 7, "***")


# --- writer (leopod.io.dcb_write): read back by the reader above ------------------------------


def test_writer_round_trip(tmp_path):
    import numpy as np
    import xarray as xr

    from leopod.io.dcb_write import write_code_dcb

    ds = xr.Dataset({"dcb_s": ("sv", [-0.916e-9, 1.182e-9, 12.345e-9]),
                     "dcb_sigma_s": ("sv", [0.139e-9, 0.002e-9, np.nan])},
                    coords={"sv": ["G01", "G04", "G30"]}, attrs={"dcb_type": "P1-C1"})
    write_code_dcb(ds, tmp_path / "p1c1.dcb")
    back = read_code_dcb(tmp_path / "p1c1.dcb")
    assert back.attrs["dcb_type"] == "P1-C1"
    assert list(back.sv.values) == ["G01", "G04", "G30"]
    # three decimals of ns (F13.3 of CODE's files)
    np.testing.assert_allclose(back.dcb_s.values, ds.dcb_s.values, rtol=0, atol=5e-13)
    np.testing.assert_allclose(back.dcb_sigma_s.values, [0.139e-9, 0.002e-9, 0.0], atol=5e-13)
    with pytest.raises(ValueError, match="dcb_type"):
        write_code_dcb(ds.assign_attrs(dcb_type="P1C1"), tmp_path / "bad.dcb")
    with pytest.raises(ValueError, match="no finite"):
        write_code_dcb(ds.assign(dcb_s=ds.dcb_s * np.nan), tmp_path / "nan.dcb")


@pytest.mark.shared
def test_writer_reproduces_code_file_values(shared_data, tmp_path):
    """Write the satellite rows of CODE's P1C10810_RINEX.DCB and read them back unchanged."""
    import numpy as np

    from leopod.io.dcb_write import write_code_dcb

    real = read_code_dcb(shared_data / P1C1)
    write_code_dcb(real[["dcb_s", "dcb_sigma_s"]], tmp_path / "copy.dcb")
    back = read_code_dcb(tmp_path / "copy.dcb")
    np.testing.assert_array_equal(back.sv.values, real.sv.values)
    np.testing.assert_allclose(back.dcb_s.values, real.dcb_s.values, rtol=0, atol=1e-15)
