"""Tests of leopod.io.fes: the IERS FES2004 coefficient file and broken copies.

Authority: the lines of the file itself (quoted beside each check), its header (unit 1e-11 as
corrected by the IERS Conventions Centre on 23 September 2011) and the Doodson-number coding
(Doodson 1921; IERS Conventions 2010, sec. 6.2.1).
"""

from __future__ import annotations

import numpy as np
import pytest
from _helpers import assert_format_error, write_lines

from leopod.io import FormatError
from leopod.io.fes import doodson_multipliers, read_fes_cnm

HEADER = [
    " Coefficients to compute variations in normalized Stokes coefficients (unit = 10^-11)",  # 1
    "Ocean tide model: FES2004 normalized model (fev. 2004) up to (100,100)",  # 2
    "Doodson Darw  l   m    DelC+     DelS+       DelC-     DelS- ",  # 3
]
DATA = [
    " 55.565 Om1   2   0  -6.58128   0.00000    -0.00000  -0.00000",  # 4
    "255.555 M2    2   0  -0.00298 -15.54137     0.00000   0.00000",  # 5
    "255.555 M2    2   1 -12.07164  -4.38919    -3.09008   1.50139",  # 6
    "255.555 M2    3   3   1.00000   2.00000     3.00000   4.00000",  # 7
]


def _fes(shared):
    return shared / "models" / "ocean_tides" / "fes2004_Cnm-Snm.dat"


# ------------------------------------------------------------------------------ real file


@pytest.mark.shared
def test_real_file(shared):
    ds = read_fes_cnm(_fes(shared))
    assert list(ds.wave.values) == ["Om1", "Om2", "Sa", "Ssa", "Mm", "Mf", "Mtm", "Msq", "Q1",
                                    "O1", "P1", "K1", "2N2", "N2", "M2", "S2", "K2", "M4"]
    assert ds.sizes["n"] == ds.sizes["m"] == 101
    assert ds.attrs["unit_in_file"] == 1e-11
    assert ds.attrs["max_degree_file"] == 100
    # "255.555 M2    2   2 -39.36214  46.75729     9.57270   5.24459"
    m2 = ds.sel(wave="M2", n=2, m=2)
    np.testing.assert_allclose([m2.C_plus, m2.S_plus, m2.C_minus, m2.S_minus],
                               [-39.36214e-11, 46.75729e-11, 9.57270e-11, 5.24459e-11],
                               rtol=1e-14)
    # " 55.565 Om1   2   0  -6.58128   0.00000    -0.00000  -0.00000"
    assert ds.C_plus.sel(wave="Om1", n=2, m=0).item() == pytest.approx(-6.58128e-11, rel=1e-14)
    # "455.555 M4  100 100  -0.00064  -0.00036     0.00025  -0.00035" (last line)
    assert ds.S_minus.sel(wave="M4", n=100, m=100).item() == pytest.approx(-0.35e-14, rel=1e-12)
    # long-period waves from FES2002 stop at degree 50 ("up to (50,50)" in the header)
    assert np.all(ds.C_plus.sel(wave="Sa", n=slice(51, None)) == 0)
    assert ds.C_plus.sel(wave="Sa", n=50, m=0).item() == pytest.approx(0.00034e-11)
    assert np.all(np.triu(ds.C_plus.sel(wave="M2").values, k=1) == 0)       # m > n
    assert list(ds.doodson.sel(wave=["Om1", "Sa", "M4"]).values) == ["055.565", "056.554",
                                                                      "455.555"]
    np.testing.assert_array_equal(ds.doodson_multipliers.sel(wave="Sa"), [0, 0, 1, 0, 0, -1])
    np.testing.assert_array_equal(ds.doodson_multipliers.sel(wave="2N2"), [2, -2, 0, 2, 0, 0])


@pytest.mark.shared
def test_real_file_truncated(shared):
    full = read_fes_cnm(_fes(shared))
    low = read_fes_cnm(_fes(shared), max_degree=30)
    assert low.sizes["n"] == 31 and low.attrs["max_degree"] == 30
    assert low.attrs["max_degree_file"] == 100
    np.testing.assert_array_equal(low.C_minus.values,
                                  full.C_minus.sel(n=slice(0, 30), m=slice(0, 30)).values)


# ------------------------------------------------------------------------------ synthetic


def test_doodson_multipliers():
    np.testing.assert_array_equal(doodson_multipliers("255.555"), [2, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(doodson_multipliers("55.565"), [0, 0, 0, 0, 1, 0])
    np.testing.assert_array_equal(doodson_multipliers("145,545"), [1, -1, 0, 0, -1, 0])
    np.testing.assert_array_equal(doodson_multipliers("162.556"), [1, 1, -3, 0, 0, 1])
    for bad in ("255.55", "M2", "1255.555"):
        with pytest.raises(ValueError, match="Doodson"):
            doodson_multipliers(bad)


def test_small_file(tmp_path):
    ds = read_fes_cnm(write_lines(tmp_path, HEADER + DATA, "fes.dat"))
    assert list(ds.wave.values) == ["Om1", "M2"]
    assert ds.sizes["n"] == 4
    assert ds.C_minus.sel(wave="M2", n=3, m=3).item() == pytest.approx(3e-11)
    assert ds.S_plus.sel(wave="M2", n=2, m=0).item() == pytest.approx(-15.54137e-11)
    assert ds.C_plus.sel(wave="Om1", n=3, m=3).item() == 0.0
    assert ds.attrs["description"].startswith("Coefficients to compute")


@pytest.mark.parametrize("lines, line, field", [
    (HEADER[:2] + DATA, None, "Doodson"),                                   # no column line
    ([HEADER[1], HEADER[2]] + DATA, None, "unit"),                          # no unit
    (HEADER + DATA[:2] + ["255.555 M2    2   1 -12.07164  -4.38919    -3.09008"], 6, "record"),
    (HEADER + DATA[:2] + ["255.5x5 N2    2   1 -12.07164  -4.38919    -3.09008   1.5"], 6,
     "Doodson"),
    (HEADER + DATA[:2] + ["245.655 M2    2   1 -12.07164  -4.38919    -3.09008   1.5"], 6,
     "Doodson"),                                                           # M2 renumbered
    (HEADER + DATA[:2] + ["255.555 M2    2   3 -12.07164  -4.38919    -3.09008   1.5"], 6, "m"),
    (HEADER + DATA[:2] + ["255.555 M2    2   x -12.07164  -4.38919    -3.09008   1.5"], 6, "m"),
    (HEADER + DATA[:2] + ["255.555 M2    2   1 -12.07164  -4.3891a    -3.09008   1.5"], 6,
     "DelS+"),
    (HEADER + DATA + [DATA[2]], 8, "record"),                               # given twice
    (HEADER, None, "record"),                                               # no records
])
def test_bad_files(tmp_path, lines, line, field):
    path = write_lines(tmp_path, lines, "bad.dat")
    with pytest.raises(FormatError) as excinfo:
        read_fes_cnm(path)
    assert_format_error(excinfo, path, line, field)
