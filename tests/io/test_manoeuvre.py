"""Tests of leopod.io.manoeuvre (reader) and leopod.io.manoeuvre_write (writer).

Authority: the format of the module docstring (one line per burn: start, end, RTN acceleration,
velocity change = acceleration x duration); a round trip must give the burns back to the
written precision (11 significant digits, microsecond epochs).
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.io._text import FormatError
from leopod.io.manoeuvre import Manoeuvre, read_manoeuvres
from leopod.io.manoeuvre_write import write_manoeuvres

T = np.datetime64("2022-07-14T12:00:00", "ns")
BURNS = (Manoeuvre(T, T + np.timedelta64(60, "s"), (0.0, 5.0e-5, -1.0e-6)),
         Manoeuvre(T + np.timedelta64(2907, "s"), T + np.timedelta64(2967, "s"),
                   (1.0e-7, -5.0e-5, 0.0)))


def test_round_trip(tmp_path):
    path = tmp_path / "manoeuvres.txt"
    write_manoeuvres(path, BURNS, satellite="lt1-b")
    burns, header = read_manoeuvres(path)
    assert header["satellite"] == "lt1-b" and header["time system"] == "GPS"
    assert len(burns) == 2
    for got, want in zip(burns, BURNS):
        assert got.start == want.start and got.end == want.end
        np.testing.assert_allclose(got.acc_rtn_m_s2, want.acc_rtn_m_s2, rtol=1e-10)
    # the velocity change of a 60-s burn of 5e-5 m/s2 along-track: 3 mm/s
    np.testing.assert_allclose(burns[0].dv_rtn_m_s, [0.0, 3.0e-3, -6.0e-5], rtol=1e-10)


def test_empty_list_round_trips(tmp_path):
    path = tmp_path / "none.txt"
    write_manoeuvres(path, (), satellite="lt1-a")
    burns, header = read_manoeuvres(path)
    assert burns == () and header["satellite"] == "lt1-a"


def _write(tmp_path, lines):
    path = tmp_path / "bad.txt"
    path.write_text("\n".join(["# leopod manoeuvre file 1.0", *lines]) + "\n")
    return path


@pytest.mark.parametrize(("line", "field"), [
    ("2022-07-14T12:00:00 2022-07-14T12:01:00 0 5e-5 0 0 0.003", "record"),
    ("2022-07-14T12:00:00 2022-07-14T11:59:00 0 5e-5 0 0 -0.003 0", "end"),
    ("2022-07-14X12:00:00 2022-07-14T12:01:00 0 5e-5 0 0 0.003 0", "start"),
    ("2022-07-14T12:00:00 2022-07-14T12:01:00 0 x 0 0 0.003 0", "acc_T"),
    ("2022-07-14T12:00:00 2022-07-14T12:01:00 0 5e-5 0 0 0.004 0", "dv_R dv_T dv_N"),
])
def test_bad_lines_name_line_and_field(tmp_path, line, field):
    path = _write(tmp_path, ["# satellite: x", line])
    with pytest.raises(FormatError) as err:
        read_manoeuvres(path)
    assert err.value.line == 3 and err.value.field == field
    assert str(path) in str(err.value)


def test_overlapping_burns_are_rejected(tmp_path):
    path = _write(tmp_path, ["2022-07-14T12:00:00 2022-07-14T12:01:00 0 5e-5 0 0 0.003 0",
                             "2022-07-14T12:00:30 2022-07-14T12:01:30 0 5e-5 0 0 0.003 0"])
    with pytest.raises(FormatError) as err:
        read_manoeuvres(path)
    assert err.value.line == 3 and err.value.field == "start"
    with pytest.raises(ValueError, match="overlapping"):
        write_manoeuvres(tmp_path / "w.txt", BURNS[::-1], satellite="x")


def test_missing_identification(tmp_path):
    path = tmp_path / "plain.txt"
    path.write_text("2022-07-14T12:00:00 2022-07-14T12:01:00 0 5e-5 0 0 0.003 0\n")
    with pytest.raises(FormatError, match="identification"):
        read_manoeuvres(path)
