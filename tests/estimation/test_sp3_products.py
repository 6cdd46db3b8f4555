"""The POD's SP3 products (leopod.estimation.outputs.sp3_dataset with io.sp3_write).

Authorities: the SP3-d specification (Hilla 2016: record accuracy exponents σ = base**n mm,
base 1.25 in the %f line), and the daily-product convention of IGS/ILRS orbit files (a daily
file holds 00:00 to before 24:00, so consecutive days concatenate without duplicate epochs).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.estimation.outputs import sp3_dataset
from leopod.io.sp3 import read_sp3
from leopod.io.sp3_write import write_sp3


def _arc_orbit(sigma_m: float) -> xr.Dataset:
    # a 30-h arc at 30 s centred on 2019-01-02, as the POD writes it
    t = np.arange(np.datetime64("2019-01-01T21:00", "ns"), np.datetime64("2019-01-03T03:00:01"),
                  np.timedelta64(30, "s"))
    pos = np.column_stack([7.0e6 + np.arange(t.size), np.zeros(t.size), np.zeros(t.size)])
    vel = np.tile([0.0, 7.5e3, 0.0], (t.size, 1))
    return xr.Dataset({"pos_itrf_m": (("time", "xyz"), pos),
                       "vel_itrf_m_s": (("time", "xyz"), vel),
                       "sigma_itrf_m": (("time", "xyz"), np.full((t.size, 3), sigma_m))},
                      coords={"time": t, "xyz": ["x", "y", "z"]})


def test_the_daily_file_holds_its_day_and_the_arc_file_the_arc(tmp_path):
    orbit = _arc_orbit(0.01)
    write_sp3(sp3_dataset(orbit, "L01", day=np.datetime64("2019-01-02")), tmp_path / "d.sp3")
    write_sp3(sp3_dataset(orbit, "L01"), tmp_path / "a.sp3")
    day, arc = read_sp3(tmp_path / "d.sp3"), read_sp3(tmp_path / "a.sp3")
    assert day.time.values[0] == np.datetime64("2019-01-02T00:00", "ns")
    assert day.time.values[-1] == np.datetime64("2019-01-02T23:59:30", "ns")
    assert day.sizes["time"] == 2880
    assert arc.sizes["time"] == orbit.sizes["time"] == 3601
    # the records of the day are those of the arc
    np.testing.assert_array_equal(day.pos_m.values, arc.pos_m.sel(time=day.time).values)


def test_record_accuracies_come_from_the_formal_sigmas(tmp_path):
    # 10 mm: n = round(log(10) / log(1.25)) = 10, read back as 1.25**10 mm = 9.31 mm
    write_sp3(sp3_dataset(_arc_orbit(0.010), "L01", day=np.datetime64("2019-01-02")),
              tmp_path / "d.sp3")
    sig = read_sp3(tmp_path / "d.sp3").pos_sigma_m.values
    np.testing.assert_allclose(sig, 1.25**10 * 1e-3, rtol=1e-12)


def test_output_epochs_start_on_the_first_grid_epoch_of_the_data():
    # analytic: data from 00:00:30 on a 10-s grid start at 00:00:30 (in float seconds
    # 00:00:30 is 30.000000000000004 s after midnight, which started the GRACE-A 2007-080
    # SP3 at 00:00:40); data from 00:00:31 start at the next grid epoch
    from leopod.estimation.outputs import output_epochs

    day = np.datetime64("2007-03-21T00:00", "ns")
    end = np.datetime64("2007-03-21T23:59:30", "ns")
    t = output_epochs(day + np.timedelta64(30, "s"), end, 10.0)
    assert t[0] == day + np.timedelta64(30, "s") and t[-1] == end and t.size == 8635
    t = output_epochs(day + np.timedelta64(31, "s"), end, 30.0)
    assert t[0] == day + np.timedelta64(60, "s")
    assert np.all(np.diff(t) == np.timedelta64(30, "s"))


def test_arc_output_epochs_extend_the_data_to_the_day_within_the_margin():
    # analytic: GRACE-A 2007-080 data from 00:00:30 to 23:59:30, a one-day arc, 10-s output:
    # with the default 60-s margin the orbit covers the day (00:00:00 to 23:59:50, 8640
    # epochs);
    # without a margin, the data span; a 30-h arc whose data fill it ends before its end
    from leopod.estimation.arc import arc_output_epochs

    day = np.datetime64("2007-03-21T00:00", "ns")
    one_day = np.timedelta64(1, "D")
    obs = np.arange(day + np.timedelta64(30, "s"), day + np.timedelta64(86371, "s"),
                    np.timedelta64(30, "s"))
    t = arc_output_epochs(obs, day, day + one_day, 10.0, 60.0)
    assert t[0] == day and t[-1] == day + one_day - np.timedelta64(10, "s") and t.size == 8640
    t = arc_output_epochs(obs, day, day + one_day, 10.0, 0.0)
    assert t[0] == obs[0] and t[-1] == obs[-1]
    # data ending 20 min before 24:00 are extended by the margin only
    t = arc_output_epochs(obs[obs < day + np.timedelta64(85200, "s")], day, day + one_day,
                          30.0, 60.0)
    assert t[-1] == day + np.timedelta64(85200 - 30 + 60, "s")
    start, end = day - np.timedelta64(3, "h"), day + one_day + np.timedelta64(3, "h")
    obs30h = np.arange(start, end, np.timedelta64(30, "s"))
    t = arc_output_epochs(obs30h, start, end, 30.0, 60.0)
    np.testing.assert_array_equal(t, obs30h)
