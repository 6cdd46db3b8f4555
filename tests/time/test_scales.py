"""Time scales, leap seconds, two-part Julian dates and EOP interpolation."""

import erfa
import numpy as np
import pytest

from leopod.time.eop import (
    EarthOrientation,
    default_earth_orientation,
    jd_ut1,
    libration_eop,
    ocean_tide_eop,
)
from leopod.time.scales import (
    gps_to_tai,
    gps_to_tt,
    gps_to_utc,
    jd_tai,
    jd_tt,
    julian_centuries_tt,
    tai_minus_utc_s,
    to_gps_time,
    utc_to_gps,
)

UAS_RAD = erfa.DAS2R * 1e-6
MAS_RAD = erfa.DAS2R * 1e-3


def _t(*labels):
    return np.array(labels, dtype="datetime64[ns]")


@pytest.fixture(scope="module")
def eop_daily():
    """C04 + finals without the sub-daily terms (the daily table itself is interpolated)."""
    return EarthOrientation.from_iers_data(subdaily=False)


# ----------------------------------------------------------------- time scales
def test_gpst_to_tt_offset_is_exactly_51_184_s():
    # Definition: TT = TAI + 32.184 s (IAU 1991), GPST = TAI - 19 s (IS-GPS-200).
    t = _t("2007-03-21T12:34:56.123456789", "2024-02-29T23:59:59.999999999")
    assert np.all(gps_to_tt(t) - t == np.timedelta64(51_184_000_000, "ns"))
    assert np.all(gps_to_tai(t) - t == np.timedelta64(19_000_000_000, "ns"))
    (a1, a2), (b1, b2) = jd_tt(t), jd_tai(t)
    np.testing.assert_allclose(((a1 - b1) + (a2 - b2)) * 86400.0, 32.184, rtol=0, atol=1e-10)


@pytest.mark.parametrize("gps,dat", [
    ("1999-06-01T00:00:00", 32.0),          # IERS Bulletin C: 32 s from 1999-01-01
    ("2007-03-21T00:00:00", 33.0),          # 33 s from 2006-01-01
    ("2008-12-31T23:59:59", 33.0),
    ("2009-01-01T00:00:15", 34.0),          # 34 s from 2009-01-01T00:00:00 UTC (= 00:00:15 GPST)
    ("2016-12-31T23:59:59", 36.0),
    ("2017-01-01T00:00:18", 37.0),          # 37 s since 2017-01-01 (Bulletin C 53, 2017)
    ("2025-06-01T00:00:00", 37.0),
])
def test_tai_minus_utc_at_known_dates(gps, dat):
    assert tai_minus_utc_s(_t(gps))[0] == dat


def test_utc_round_trip_and_leap_second_boundary():
    # Bulletin C 52: TAI-UTC = 36 s until 2016-12-31T23:59:60 UTC, then 37 s; GPST = TAI - 19 s.
    utc = _t("2016-12-31T23:59:59", "2017-01-01T00:00:00", "2007-04-05T12:00:00")
    gps = utc_to_gps(utc)
    np.testing.assert_array_equal(gps, _t("2017-01-01T00:00:16", "2017-01-01T00:00:18",
                                          "2007-04-05T12:00:14"))
    np.testing.assert_array_equal(gps_to_utc(gps), utc)
    # the inserted second 23:59:60 (GPST 00:00:17) cannot be shown: labelled like the next one
    assert gps_to_utc(_t("2017-01-01T00:00:17"))[0] == np.datetime64("2017-01-01T00:00:00")


def test_two_part_julian_date_keeps_nanoseconds():
    t = _t("2007-03-21T12:00:00.000000123")
    jd1, jd2 = jd_tt(t)
    # jd1: TT midnight 2007-03-21 = JD 2454180.5 (erfa.cal2jd); jd2 = fraction of the TT day
    assert jd1[0] == sum(erfa.cal2jd(2007, 3, 21))
    seconds = jd2[0] * 86400.0 - (43200.0 + 51.184)
    assert seconds == pytest.approx(123e-9, abs=1e-10)


def test_gps_time_before_1972_is_rejected():
    with pytest.raises(ValueError, match="1972"):
        tai_minus_utc_s(_t("1970-06-01T00:00:00"))


# ----------------------------------------------------------------- EOP tables
def test_value_at_a_table_epoch_equals_the_c04_record(eop_daily):
    # IERS 20 C04 record of 2007-04-05 (MJD 54195), 0h UTC = 00:00:14 GPST.
    v = eop_daily.at(_t("2007-04-05T00:00:14"))
    assert v.xp_rad[0] == pytest.approx(0.033219 * erfa.DAS2R, abs=1e-15)
    assert v.yp_rad[0] == pytest.approx(0.483159 * erfa.DAS2R, abs=1e-15)
    assert v.dut1_s[0] == pytest.approx(-0.0714242, abs=1e-12)
    assert v.dx_rad[0] == pytest.approx(0.000208 * erfa.DAS2R, abs=1e-15)
    assert v.dy_rad[0] == pytest.approx(-0.000281 * erfa.DAS2R, abs=1e-15)
    assert v.lod_s[0] == pytest.approx(0.0013813, abs=1e-12)


def test_ut1_is_continuous_across_the_2008_leap_second(eop_daily):
    # Leap second 2008-12-31T23:59:60 UTC (Bulletin C 36); C04: UT1-UTC = +0.4071649 s on
    # 2009-01-01 0h, so just before the leap second UT1-UTC = 0.4071649 - 1 s.
    # UT1 must advance by 1 s per second (|LOD| ~ 1 ms/day) while UT1-UTC jumps by +1 s.
    t = np.datetime64("2009-01-01T00:00:10", "ns") + np.arange(11) * np.timedelta64(1, "s")
    v = eop_daily.at(t)
    jd1, jd2 = jd_ut1(t, v)
    step_s = np.diff((jd1 - jd1[0]) + jd2) * 86400.0
    np.testing.assert_allclose(step_s, 1.0, rtol=0, atol=1e-6)
    jumps = np.diff(v.dut1_s)
    assert np.count_nonzero(np.abs(jumps) > 0.5) == 1
    assert jumps.max() == pytest.approx(1.0, abs=1e-6)
    assert v.dut1_s[0] == pytest.approx(0.4071649 - 1.0, abs=1e-6)
    assert v.dut1_s[-1] == pytest.approx(0.4071649, abs=1e-6)


def test_epoch_outside_the_table_raises():
    with pytest.raises(ValueError, match="outside the EOP table"):
        default_earth_orientation().at(_t("2150-01-01T00:00:00"))


def test_interpolated_eop_close_to_sofa_cookbook_values():
    # SOFA "Tools for Earth Attitude", sec. 5: IERS values for 2007-04-05 12:00 UTC
    # (x_p 0.0349282", y_p 0.4833163", UT1-UTC -0.072073685 s, dX06 0.1750 mas,
    # dY06 -0.2259 mas). Later IERS series (20 C04) differ by a few 0.1 mas, 0.01 ms.
    v = default_earth_orientation().at(_t("2007-04-05T12:00:14"))
    assert v.xp_rad[0] == pytest.approx(0.0349282 * erfa.DAS2R, abs=0.5 * MAS_RAD)
    assert v.yp_rad[0] == pytest.approx(0.4833163 * erfa.DAS2R, abs=0.5 * MAS_RAD)
    assert v.dut1_s[0] == pytest.approx(-0.072073685, abs=2e-5)
    assert v.dx_rad[0] == pytest.approx(0.1750 * MAS_RAD, abs=0.2 * MAS_RAD)
    assert v.dy_rad[0] == pytest.approx(-0.2259 * MAS_RAD, abs=0.2 * MAS_RAD)


def test_subdaily_terms_are_added(eop_daily):
    # Ocean tides + libration reach ~0.5 mas in the pole and ~0.05 ms in UT1
    # (IERS Conventions 2010, Tables 8.2, 8.3, 5.1): the difference must be of that size.
    t = np.datetime64("2007-03-21T00:00:00", "ns") + np.arange(48) * np.timedelta64(1, "h")
    full, daily = default_earth_orientation().at(t), eop_daily.at(t)
    dx = np.abs(full.xp_rad - daily.xp_rad).max() / MAS_RAD
    dut = np.abs(full.dut1_s - daily.dut1_s).max()
    assert 0.1 < dx < 1.0
    assert 10e-6 < dut < 100e-6


@pytest.mark.shared
def test_finals2000a_file_matches_its_record(shared_data):
    # Bulletin-A record of 2007-04-05 in ../shared/data/eop/finals2000A.all:
    # x 0.033178", y 0.483095", UT1-UTC -0.0714227 s, LOD 1.4020 ms, dX 0.142, dY -0.259 mas.
    eop = EarthOrientation.from_finals(shared_data / "eop" / "finals2000A.all", subdaily=False)
    v = eop.at(_t("2007-04-05T00:00:14"))
    assert v.xp_rad[0] == pytest.approx(0.033178 * erfa.DAS2R, abs=1e-15)
    assert v.yp_rad[0] == pytest.approx(0.483095 * erfa.DAS2R, abs=1e-15)
    assert v.dut1_s[0] == pytest.approx(-0.0714227, abs=1e-12)
    assert v.lod_s[0] == pytest.approx(1.4020e-3, abs=1e-12)
    assert v.dx_rad[0] == pytest.approx(0.142 * MAS_RAD, abs=1e-15)
    assert v.dy_rad[0] == pytest.approx(-0.259 * MAS_RAD, abs=1e-15)


# ----------------------------------------------------------------- sub-daily models
def _args(mjd):
    """TT centuries and GMST for an MJD used as both TT and UT1 (as the IERS test cases do)."""
    mjd = np.array([mjd])
    return (mjd - 51544.5) / 36525.0, erfa.gmst06(2400000.5, mjd, 2400000.5, mjd)


def test_ocean_tide_terms_against_ortho_eop_test_case():
    # IERS Conventions 2010 software ORTHO_EOP test case, MJD 47100:
    # dx = -162.8386373 µas, dy = 117.7907526 µas, dUT1 = -23.3909237 µs. The tabulated
    # 71-term model agrees with ORTHO_EOP to "a few µas and a few tenths of µs" (TN36 sec. 8.2).
    dx, dy, dut1 = ocean_tide_eop(*_args(47100.0))
    assert dx[0] / UAS_RAD == pytest.approx(-162.8386373279636530, abs=1.0)
    assert dy[0] / UAS_RAD == pytest.approx(117.7907525842668974, abs=1.0)
    assert dut1[0] * 1e6 == pytest.approx(-23.39092370609808214, abs=0.1)


def test_libration_terms_against_iers_test_cases():
    # PMSDNUT2 test case (IERS Conventions 2010 software), MJD 54335:
    # dx = 24.83144238273364834 µas, dy = -14.09240692041837661 µas.
    dx, dy, _ = libration_eop(*_args(54335.0))
    assert dx[0] / UAS_RAD == pytest.approx(24.83144238273364834, abs=1e-5)
    assert dy[0] / UAS_RAD == pytest.approx(-14.09240692041837661, abs=1e-5)
    # UTLIBR test cases: MJD 44239.1 -> 2.441143834386761746 µs,
    # MJD 55227.4 -> -2.655705844335680244 µs.
    for mjd, expected_us in ((44239.1, 2.441143834386761746), (55227.4, -2.655705844335680244)):
        assert libration_eop(*_args(mjd))[2][0] * 1e6 == pytest.approx(expected_us, abs=1e-5)


def test_julian_centuries_tt_at_j2000():
    # J2000.0 = 2000-01-01T12:00:00 TT = 11:58:55.816 UTC = 11:59:08.816 GPST (IERS 2010 ch. 5).
    assert julian_centuries_tt(_t("2000-01-01T11:59:08.816"))[0] == 0.0
    assert julian_centuries_tt(_t("2100-01-01T11:59:08.816"))[0] == pytest.approx(1.0, abs=1e-15)


# ------------------------------------------------------------------ GNSS time systems -> GPST
def test_bdt_offset_follows_from_the_bds_start_epoch():
    """BDT started at 2006-01-01 00:00:00 UTC (BDS-SIS-ICD-B1I-3.0, time system); GPST started
    at 1980-01-06 00:00:00 UTC (IS-GPS-200) and has counted every leap second since (IERS
    Bulletin C: TAI-UTC = 33 s from 2006-01-01). So the BDT label 2006-01-01T00:00:00 is the
    GPS label of that UTC instant, and the offset is the same 14 s at any later epoch."""
    start_gps = utc_to_gps(_t("2006-01-01T00:00:00"))
    assert to_gps_time(_t("2006-01-01T00:00:00"), "BDT")[0] == start_gps[0]
    later = _t("2022-01-09T00:00:00.1234567", "2030-06-30T23:59:59")
    shift = (to_gps_time(later, "BDT") - later).astype(np.int64)
    np.testing.assert_array_equal(shift, 14_000_000_000)  # exact, leap-second free


def test_gst_labels_equal_gpst_from_the_galileo_start_epoch():
    """GST started at 1999-08-22 00:00:00 UT, 13 s ahead of UTC (Galileo OS SIS ICD 2.0, GST
    definition): the GST label 1999-08-22T00:00:13 is the GPS label of that UTC instant
    (GPST - UTC = 13 s then: TAI-UTC = 32 s, IERS Bulletin C)."""
    start_gps = utc_to_gps(_t("1999-08-22T00:00:00"))
    assert to_gps_time(_t("1999-08-22T00:00:13"), "GAL")[0] == start_gps[0]
    t = _t("2023-07-08T12:00:00")
    assert to_gps_time(t, "GST")[0] == t[0] and to_gps_time(t, " gps ")[0] == t[0]


def test_tai_tt_utc_labels_to_gps():
    """TAI = GPST + 19 s, TT = TAI + 32.184 s (IERS Conventions 2010, ch. 10): the inverse of
    gps_to_tai / gps_to_tt / gps_to_utc."""
    t = _t("2016-12-31T23:59:50", "2017-01-01T00:00:30")
    np.testing.assert_array_equal(to_gps_time(gps_to_tai(t), "TAI"), t)
    np.testing.assert_array_equal(to_gps_time(gps_to_tt(t), "TT"), t)
    np.testing.assert_array_equal(to_gps_time(gps_to_utc(t), "UTC"), t)


@pytest.mark.parametrize("system, words", [("GLO", "UTC(SU) + 3 h"), ("QZS", "QZSS"),
                                           ("IRN", "IRNSS"), ("XYZ", "unknown time system")])
def test_unsupported_time_systems_are_refused_with_the_reason(system, words):
    with pytest.raises(ValueError, match=r"time system") as err:
        to_gps_time(_t("2023-01-01"), system)
    assert words in str(err.value) and f"'{system}'" in str(err.value)
