"""Tests of leopod.io.space_weather: the real CelesTrak file, MSIS inputs, broken copies."""

from __future__ import annotations

import numpy as np
import pytest
from _helpers import assert_format_error, write_lines

from leopod.io import FormatError
from leopod.io.space_weather import msis_inputs, read_space_weather

HEADER = ("DATE,BSRN,ND,KP1,KP2,KP3,KP4,KP5,KP6,KP7,KP8,KP_SUM,AP1,AP2,AP3,AP4,AP5,AP6,AP7,AP8,"
          "AP_AVG,CP,C9,ISN,F10.7_OBS,F10.7_ADJ,F10.7_DATA_TYPE,F10.7_OBS_CENTER81,"
          "F10.7_OBS_LAST81,F10.7_ADJ_CENTER81,F10.7_ADJ_LAST81")
# Lines 18067-18070 of the CelesTrak SW-All.csv in ../shared (typed copies)
ROWS = [
    "2007-03-18,2369,21,7,3,7,7,13,13,7,7,63,3,2,3,3,5,5,3,3,3,0.1,0,0,70.5,69.8,OBS,72.8,78.8,72.1,76.8",
    "2007-03-19,2369,22,0,7,3,10,3,3,3,7,37,0,3,2,4,2,2,2,3,2,0.0,0,0,70.1,69.5,OBS,72.8,78.7,72.2,76.7",
    "2007-03-20,2369,23,0,0,0,0,3,3,3,3,13,0,0,0,0,2,2,2,2,1,0.0,0,0,72.6,72.0,OBS,72.9,78.6,72.3,76.7",
    "2007-03-21,2369,24,0,0,7,3,7,3,0,0,20,0,0,3,2,3,2,0,0,1,0.0,0,0,72.8,72.3,OBS,73.0,78.5,72.4,76.6",
]
PRM = "2041-10-01,2837,1,,,,,,,,,,,,,,,,,,,,,10,69.8,70.0,PRM,68.8,69.0,69.2,70.5"  # line 25215


def _file(shared):
    return shared / "models" / "space_weather" / "SW-All.csv"


def _write(tmp_path, rows, name="sw.csv", header=HEADER):
    return write_lines(tmp_path, [header, *rows], name)


# ------------------------------------------------------------------------------ real file


@pytest.fixture(scope="module")
def sw_real(shared):
    return read_space_weather(_file(shared))


@pytest.mark.shared
def test_real_file_values(sw_real):
    # 25215 lines = header + 25214 rows, 1957-10-01 to 2041-10-01 (monthly predictions at the end)
    assert sw_real.sizes == {"date": 25214, "slot": 8}
    assert sw_real.date.values[0] == np.datetime64("1957-10-01")
    day = sw_real.sel(date="2007-03-21")
    # line 18070: 2007-03-21,2369,24,0,0,7,3,7,3,0,0,20,0,0,3,2,3,2,0,0,1,0.0,0,0,72.8,72.3,OBS,
    #             73.0,78.5,72.4,76.6
    assert day.bartels_rotation.item() == 2369 and day.bartels_day.item() == 24
    np.testing.assert_allclose(day.kp.values, [0.0, 0.0, 0.7, 0.3, 0.7, 0.3, 0.0, 0.0])
    assert day.kp_sum.item() == pytest.approx(2.0)
    np.testing.assert_array_equal(day.ap.values, [0, 0, 3, 2, 3, 2, 0, 0])
    assert day.ap_daily.item() == 1.0
    assert day.cp.item() == 0.0 and day.c9.item() == 0.0 and day.isn.item() == 0.0
    assert day.f107_obs_sfu.item() == 72.8 and day.f107_adj_sfu.item() == 72.3
    assert day.f107_data_type.item() == "OBS"
    assert day.f107_obs_center81_sfu.item() == 73.0 and day.f107_obs_last81_sfu.item() == 78.5
    assert day.f107_adj_center81_sfu.item() == 72.4 and day.f107_adj_last81_sfu.item() == 76.6
    # line 25215 (PRM, geomagnetic fields blank): 2041-10-01,2837,1,,,...,,10,69.8,70.0,PRM,...
    last = sw_real.isel(date=-1)
    assert last.date.values == np.datetime64("2041-10-01")
    assert np.isnan(last.kp.values).all() and np.isnan(last.ap_daily.item())
    assert last.f107_data_type.item() == "PRM" and last.f107_obs_sfu.item() == 69.8
    assert sw_real.ap.attrs["units"] == "2 nT" and sw_real.attrs["time_system"] == "UTC"


@pytest.mark.shared
def test_msis_inputs_hand_computed(sw_real):
    # Hand computation from lines 18068-18070 (2007-03-19..21) at 2007-03-21 13:30 UTC
    # (3-hour interval 12-15 UT): F10.7 of 03-20 = 72.6, centred 81-day mean of 03-21 = 73.0,
    # Ap(03-21) = 1, ap 12-15/9-12/6-9/3-6 UT = 3, 2, 3, 0; mean of 03-20 03-24 UT .. 03-21
    # 00-03 UT = (0+0+0+2+2+2+2 + 0)/8 = 1; mean of 03-19 03-24 UT .. 03-20 00-03 UT
    # = (3+2+4+2+2+2+3 + 0)/8 = 2.25.
    f107, f107a, ap = msis_inputs(sw_real, np.datetime64("2007-03-21T13:30"))
    assert f107[0] == 72.6 and f107a[0] == 73.0
    np.testing.assert_allclose(ap[0], [1.0, 3.0, 2.0, 3.0, 0.0, 1.0, 2.25])


@pytest.mark.shared
@pytest.mark.filterwarnings("ignore:There is data that was either interpolated")
def test_msis_inputs_match_pymsis_reader(sw_real, shared, monkeypatch):
    # Independent reader of the same file: pymsis.utils.get_f107_ap (pymsis 0.13), pointed at
    # ../shared instead of its download location (restored by monkeypatch). The epochs include
    # 2006-12-07, the day after a 573.4 sfu radio burst (line 17965), replaced in both by the
    # 81-day mean (91.4).
    utils = pytest.importorskip("pymsis.utils")
    monkeypatch.setattr(utils._SPACE_WEATHER, "path", _file(shared))
    monkeypatch.setattr(utils._SPACE_WEATHER, "data", None)
    times = np.array(["2007-03-21T00:00", "2007-03-21T13:30", "2007-03-22T23:59:59",
                      "2003-10-30T07:10", "2006-12-07T05:00"], dtype="datetime64[ns]")
    f107, f107a, ap = msis_inputs(sw_real, times)
    ref_f107, ref_f107a, ref_ap = utils.get_f107_ap(times)
    np.testing.assert_allclose(f107, ref_f107, rtol=0, atol=1e-9)
    np.testing.assert_allclose(f107a, ref_f107a, rtol=0, atol=1e-9)
    np.testing.assert_allclose(ap, ref_ap, rtol=0, atol=1e-9)
    assert f107[-1] == 91.4


@pytest.mark.shared
def test_msis_inputs_outside_daily_data(sw_real):
    with pytest.raises(ValueError, match="no daily record"):
        msis_inputs(sw_real, np.datetime64("2030-06-01T00:00"))  # monthly predictions only
    with pytest.raises(ValueError, match="no daily record"):
        msis_inputs(sw_real, np.datetime64("1957-10-02T12:00"))  # needs 1957-09-29


# ------------------------------------------------------------------------- synthetic files


def test_small_file_and_missing_day(tmp_path):
    sw = read_space_weather(_write(tmp_path, [*ROWS, PRM]))
    assert sw.sizes["date"] == 5
    f107, f107a, ap = msis_inputs(sw, np.datetime64("2007-03-21T13:30"))
    assert (f107[0], f107a[0]) == (72.6, 73.0)
    np.testing.assert_allclose(ap[0], [1.0, 3.0, 2.0, 3.0, 0.0, 1.0, 2.25])
    with pytest.raises(ValueError, match="2007-03-17"):  # 03-20 needs 03-17 (57 h before)
        msis_inputs(sw, np.datetime64("2007-03-20T12:00"))


@pytest.mark.parametrize(
    ("rows", "header", "line", "field"),
    [
        (ROWS, HEADER.replace("KP1", "KP0"), 1, "header"),
        ([ROWS[0], ROWS[1] + ",1"], HEADER, 3, "row"),
        ([ROWS[0], ROWS[1].replace("2007-03-19", "2007-02-30")], HEADER, 3, "DATE"),
        ([ROWS[1], ROWS[0]], HEADER, 3, "DATE"),
        ([ROWS[0], ROWS[1].replace(",0,7,3,10,", ",0,x,3,10,")], HEADER, 3, "KP2"),
        ([ROWS[0], ROWS[1].replace(",0,7,3,10,", ",0,97,3,10,")], HEADER, 3, "KP2"),
        ([ROWS[0], ROWS[1].replace(",37,0,3,", ",37,-1,3,")], HEADER, 3, "AP1"),
        ([ROWS[0], ROWS[1].replace("70.1,69.5", "-70.1,69.5")], HEADER, 3, "F10.7_OBS"),
        ([ROWS[0], ROWS[1].replace("OBS", "XYZ")], HEADER, 3, "F10.7_DATA_TYPE"),
        ([ROWS[0], ROWS[1].replace("2369,22", "2369,")], HEADER, 3, "ND"),
    ],
    ids=["header", "fields", "date", "order", "number", "kp-range", "ap-negative",
         "f107-negative", "type", "blank-int"],
)
def test_bad_rows(tmp_path, rows, header, line, field):
    path = _write(tmp_path, rows, header=header)
    with pytest.raises(FormatError) as excinfo:
        read_space_weather(path)
    assert_format_error(excinfo, path, line, field)
