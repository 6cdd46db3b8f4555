"""Tests of leopod.io.icgem: the five real .gfc models and broken copies."""

from __future__ import annotations

import numpy as np
import pytest
from _helpers import assert_format_error, write_lines

from leopod.io import FormatError
from leopod.io.icgem import read_icgem

HEADER = [
    "a test model",  # 1
    "product_type              gravity_field",  # 2
    "modelname                 TEST",  # 3
    "earth_gravity_constant    0.3986004415E+15",  # 4
    "radius                    0.6378136300E+07",  # 5
    "max_degree                2",  # 6
    "errors                    formal",  # 7
    "norm                      fully_normalized",  # 8
    "tide_system               tide_free",  # 9
    "end_of_head ==========",  # 10
]
DATA = [
    "gfc    0    0  1.000000000000e+00  0.000000000000e+00  0.0e+00  0.0e+00",  # 11
    "gfc    2    0 -4.841694573200D-04  0.000000000000D+00  1.1e-10  0.0e+00",  # 12
    "gfc    2    1 -2.066155090741e-10  1.384413891380e-09  7.1e-12  7.3e-12",  # 13
    "gfc    2    2  2.439383573283e-06 -1.400273703859e-06  7.2e-12  7.4e-12",  # 14
]


def _gravity(shared):
    return shared / "models" / "gravity"


def _write(tmp_path, lines, name="test.gfc"):
    return write_lines(tmp_path, lines, name)


_assert_error = assert_format_error


# ------------------------------------------------------------------------------ real files


@pytest.mark.shared
def test_egm2008(shared):
    ds = read_icgem(_gravity(shared) / "EGM2008_120.gfc")
    assert ds.sizes == {"n": 121, "m": 121}
    assert ds.attrs["modelname"] == "EGM2008"
    assert ds.attrs["gm_m3_s2"] == 0.3986004415e15
    assert ds.attrs["radius_m"] == 0.63781363e07
    assert ds.attrs["max_degree"] == 120
    assert ds.attrs["tide_system"] == "tide_free"
    assert ds.attrs["errors"] == "calibrated"
    assert ds.attrs["norm"] == "fully_normalized"
    assert ds.attrs["time_variable_terms"] == ""
    # line 22: "gfc     0    0    1.0d0    0.0d0    0.0d0    0.0d0"
    assert ds.C.sel(n=0, m=0).item() == 1.0
    # line 23: "gfc     2    0   -0.484165143790815e-03    0.000000000000000e+00
    #           0.7481239490e-11    0.0000000000e+00"
    assert ds.C.sel(n=2, m=0).item() == -0.484165143790815e-03
    assert ds.sigma_C.sel(n=2, m=0).item() == 0.7481239490e-11
    # last line: "gfc   120  120   -0.650974846637476e-09   -0.147710757794803e-08 ..."
    assert ds.S.sel(n=120, m=120).item() == -0.147710757794803e-08
    assert (ds.C.sel(n=1).values == 0).all()  # degree 1 is not in the file
    assert ds.C.sel(n=2, m=3).item() == 0.0  # m > n
    assert ds.C.attrs["units"] == "1"


@pytest.mark.shared
def test_ggm05s_fortran_exponents(shared):
    ds = read_icgem(_gravity(shared) / "GGM05S.gfc")
    assert ds.attrs["max_degree"] == 180 and ds.attrs["tide_system"] == "zero_tide"
    # line 39: "gfc    2    0 -4.841694573200D-04  0.000000000000D+00  1.17430D-10  0.00000D+00"
    assert ds.C.sel(n=2, m=0).item() == -4.841694573200e-04
    assert ds.sigma_C.sel(n=2, m=0).item() == 1.17430e-10


@pytest.mark.shared
def test_itu_grace16_and_jgm3_headers(shared):
    itu = read_icgem(_gravity(shared) / "ITU_GRACE16.gfc")
    assert itu.attrs["tide_system"] == "zero_tide"  # written "zero tide" in the file
    assert itu.attrs["radius_m"] == 6.3781364600000000e06
    # line 75: "gfc      2    0 -0.484169523233887E-03  0.000000000000000E+00 ..."
    assert itu.C.sel(n=2, m=0).item() == -0.484169523233887e-03
    jgm3 = read_icgem(_gravity(shared) / "JGM3.gfc")
    assert jgm3.attrs["tide_system"] == "unknown" and jgm3.attrs["max_degree"] == 70
    # line 20: "gfc    2    0 -0.484169548456e-03  0.000000000000e+00 0.46600000e-10 ..."
    assert jgm3.C.sel(n=2, m=0).item() == -0.484169548456e-03


@pytest.mark.shared
def test_eigen6s_time_variable_terms(shared):
    ds = read_icgem(_gravity(shared) / "eigen-6s.gfc")
    assert ds.attrs["max_degree"] == 240
    assert ds.attrs["time_variable_terms"] == "gfct trnd acos asin"
    assert ds.attrs["t0"] == "2005-01-01"
    np.testing.assert_array_equal(ds.period.values, [1.0, 0.5])
    # line 79: "gfct   2    0 -4.84165299820e-04 0.000000000000e+00 1.9551e-13 0.0000e+00 20050101"
    assert ds.C.sel(n=2, m=0).item() == -4.84165299820e-04
    assert ds.sigma_C.sel(n=2, m=0).item() == 1.9551e-13
    # line 80: "trnd   2    0 -1.26059939709e-11 ..."
    assert ds.trnd_C.sel(n=2, m=0).item() == -1.26059939709e-11
    assert ds.trnd_C.attrs["units"] == "year-1"
    # lines 81-84: acos/asin of C20 for periods 1.0 and 0.5 years
    np.testing.assert_array_equal(ds.acos_C.sel(n=2, m=0).values,
                                  [4.10019292536e-11, 3.33920225943e-11])
    np.testing.assert_array_equal(ds.asin_C.sel(n=2, m=0).values,
                                  [5.32367408468e-11, -2.44369818145e-11])
    assert (ds.trnd_C.sel(n=60).values == 0).all()  # time-variable part only to d/o 50


@pytest.mark.shared
def test_max_degree_truncation(shared):
    ds = read_icgem(_gravity(shared) / "EGM2008_120.gfc", max_degree=10)
    assert ds.sizes == {"n": 11, "m": 11} and ds.attrs["max_degree"] == 10
    assert ds.attrs["max_degree_file"] == 120
    assert ds.C.sel(n=2, m=0).item() == -0.484165143790815e-03
    with pytest.raises(ValueError, match="max_degree"):
        read_icgem(_gravity(shared) / "EGM2008_120.gfc", max_degree=121)


# ------------------------------------------------------------------------------ small files


def test_small_model(tmp_path):
    ds = read_icgem(_write(tmp_path, HEADER + DATA))
    assert ds.C.values.shape == (3, 3)
    assert ds.C.sel(n=2, m=2).item() == 2.439383573283e-06
    assert np.isnan(ds.sigma_C.sel(n=1, m=0).item())  # not given
    assert ds.attrs["gm_m3_s2"] == 3.986004415e14


def test_unnormalized_model_is_normalized(tmp_path):
    header = [line.replace("fully_normalized", "unnormalized") for line in HEADER]
    data = [DATA[0], "gfc    2    0 -1.0826e-03  0.0  0.0  0.0", DATA[2], DATA[3]]
    ds = read_icgem(_write(tmp_path, header + data))
    # Heiskanen & Moritz (1967) eq. 1-91: C20_normalised = C20 / sqrt(5)
    assert ds.C.sel(n=2, m=0).item() == pytest.approx(-1.0826e-03 / np.sqrt(5), rel=1e-14)
    # C22_normalised = C22 * sqrt(4! / (2 * 5 * 0!)) = C22 * sqrt(2.4)
    assert ds.C.sel(n=2, m=2).item() == pytest.approx(2.439383573283e-06 * np.sqrt(2.4),
                                                      rel=1e-14)
    assert ds.attrs["norm_in_file"] == "unnormalized"


# ------------------------------------------------------------------------------ broken files


def test_missing_end_of_head(tmp_path):
    path = _write(tmp_path, HEADER[:-1])
    with pytest.raises(FormatError) as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, None, "end_of_head")


def test_missing_mandatory_keyword(tmp_path):
    path = _write(tmp_path, HEADER[:4] + HEADER[5:] + DATA)
    with pytest.raises(FormatError, match="mandatory") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, None, "radius")


def test_non_numeric_coefficient(tmp_path):
    data = list(DATA)
    data[2] = data[2].replace("1.384413891380e-09", "1.3844x3891380e-09")
    path = _write(tmp_path, HEADER + data)
    with pytest.raises(FormatError, match="not a number") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 13, "S")


def test_nan_coefficient(tmp_path):
    data = list(DATA)
    data[3] = data[3].replace("2.439383573283e-06", "NaN")
    path = _write(tmp_path, HEADER + data)
    with pytest.raises(FormatError, match="finite") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 14, "C")


def test_truncated_record(tmp_path):
    path = _write(tmp_path, HEADER + DATA[:3] + [DATA[3][:45]])  # sigmas lost, S cut
    with pytest.raises(FormatError, match="5 fields, expected 7") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 14, "gfc")


def test_truncated_file(tmp_path):
    path = _write(tmp_path, HEADER + DATA[:3])  # C22/S22 missing
    with pytest.raises(FormatError, match="max_degree 2 has 2 of its 3 orders") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 13, "L")


def test_order_above_degree(tmp_path):
    data = DATA + ["gfc    1    2  1.0e-10  0.0  0.0  0.0"]
    path = _write(tmp_path, HEADER + data)
    with pytest.raises(FormatError, match="order 2") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 15, "M")


def test_duplicate_coefficient(tmp_path):
    path = _write(tmp_path, HEADER + DATA + [DATA[1]])
    with pytest.raises(FormatError, match="twice") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 15, "gfc")


def test_unknown_key(tmp_path):
    path = _write(tmp_path, HEADER + DATA + ["gcf    2    1  1.0e-10  0.0  0.0  0.0"])
    with pytest.raises(FormatError, match="unknown record key") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 15, "key")


def test_icgem20_time_variable_rejected(tmp_path):
    header = HEADER[:1] + ["format                    icgem2.0"] + HEADER[1:]
    data = DATA + ["gfct   2    0 -4.8e-04  0.0  1.0e-13  0.0  20020815.0817  20030601.0000"]
    path = _write(tmp_path, header + data)
    with pytest.raises(FormatError, match="icgem2.0") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 16, "gfct")


def test_different_reference_epochs_rejected(tmp_path):
    data = [DATA[0],
            "gfct   2    0 -4.8e-04  0.0  1.0e-13  0.0  20050101",
            "gfct   2    1 -2.0e-10  1.3e-09  1.0e-13  1.0e-13  20060101",
            DATA[3]]
    path = _write(tmp_path, HEADER + data)
    with pytest.raises(FormatError, match="20060101") as excinfo:
        read_icgem(path)
    _assert_error(excinfo, path, 13, "t0")
