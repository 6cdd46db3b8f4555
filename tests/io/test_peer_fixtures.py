"""Regression test of every reader over the valid files other projects keep as test fixtures.

Authority: ``../shared/peer_fixtures/valid`` (files of georinex, gnssanalysis, Orekit, RTKLIB,
georust/rinex, gnss_lib_py, cssrlib-data; origin, commit and licence in its MANIFEST.md),
read from ../shared at test time and never copied here; skipped when absent. Every file is
read, except those in :data:`REFUSED`, which break a rule of their format specification and
are refused with a FormatError naming that rule's field (issue 24). Files that break a count
or comment rule while their values stay unambiguous are read with a logged warning (two ANTEX
files whose '# OF FREQUENCIES' disagrees with their antennas, two RINEX clock files with more
values than announced, an SP3 and Bias-SINEX files whose header counts disagree with a file
complete to its EOF / %=ENDBIA, DLR's '- ' comment lines, ANTEX antennas closed by the next
START OF ANTENNA, an SP3-a epoch line with 7 decimals, ILRS '%/*' SP3 comments, unannounced
continuation lines of clock records leopod does not read, a RINEX header position out of its
columns). Values of the files that
leopod used to refuse are spot-checked against the file text (file and line cited).
"""

from __future__ import annotations

import logging

import numpy as np
import pytest

from leopod.io import FormatError
from leopod.io.antex import read_antex
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.clock import read_rinex_clock
from leopod.io.crd import read_crd
from leopod.io.dcb import read_code_dcb
from leopod.io.icgem import read_icgem
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sinex import read_sinex_eccentricities, read_sinex_stations
from leopod.io.sp3 import read_sp3

READERS = {
    "obs": read_rinex_obs, "sp3": read_sp3, "clk": lambda p: read_rinex_clock(p, ("AS", "AR")),
    "atx": read_antex, "bia": read_bias_sinex, "snx": read_sinex_stations,
    "ecc": read_sinex_eccentricities, "crd_np": lambda p: read_crd(p, "normal_point"),
    "crd_fr": lambda p: read_crd(p, "full_rate"), "dcb": read_code_dcb,
    "icgem": lambda p: read_icgem(p, epoch="2003-07-02T12:00"),  # epoch: icgem2.0 only
}

#: Files refused on purpose: (folder/name) -> (line, field of the FormatError, the rule broken).
REFUSED = {
    "clk/issue845.clk": (None, "END OF HEADER", "RINEX clock: END OF HEADER is mandatory"),
    "obs/embe083.06o": (13, "SYS / # / OBS TYPES", "RINEX 3 sec. 5.1: observation codes have "
                        "3 characters ('C0' is not one)"),
    "obs/rovn0010.21o": (512, "epoch record", "RINEX 2.11: an epoch record announcing 20 "
                         "satellites must hold their 20 records (file cut short)"),
    "sp3/example-a-1.sp3": (40, "satellite", "SP3: every satellite of the records is listed "
                            "in the header (G03 is not)"),
    "sp3/example2.sp3a": (30, "record", "SP3: a data line starts with '*', 'P', 'V', 'EP', "
                          "'EV' or 'EOF'"),
    "sp3/igs19362.sp3c.gz": (1, "version", "SP3: the first line starts with '#a'..'#d'"),
    "sp3/issue895-hours-increment.sp3": (113, "epoch", "SP3: an epoch's hour is 0-23 (the file "
                                         "writes '2016  7  7 24  0' for 7 July 00:00, which "
                                         "ISO 8601 would read as 8 July: ambiguous)"),
}


def _files(shared):
    root = shared / "peer_fixtures" / "valid"
    if not root.is_dir():
        pytest.skip(f"peer fixtures not found: {root}")
    return root, sorted(f"{d.name}/{f.name}" for d in root.iterdir() if d.is_dir()
                        for f in d.iterdir())


@pytest.mark.shared
def test_every_valid_peer_fixture_is_read_or_refused_for_a_stated_rule(shared, caplog):
    root, names = _files(shared)
    assert len(names) == 82  # MANIFEST.md: 82 valid files
    read, refused = [], []
    for name in names:
        folder = name.split("/")[0]
        with caplog.at_level(logging.ERROR):
            try:
                READERS[folder](root / name)
                read.append(name)
            except FormatError as err:
                assert name in REFUSED, f"{name} refused: {err}"
                line, field, _rule = REFUSED[name]
                assert err.line == line, (name, err)
                if field is not None:
                    assert err.field == field, (name, err)
                refused.append(name)
    assert sorted(refused) == sorted(REFUSED)
    assert len(read) == 82 - len(REFUSED)


@pytest.mark.shared
def test_code_2021_osb_with_wrong_record_count_is_read(shared, caplog):
    # COD0MGXFIN_20210780000_01D_01D_OSB.BIA line 1: "%=BIA ... 6888" while the complete file
    # (closed by %=ENDBIA) holds 6844 records; line 70:
    # " OSB  G063 G01           C1C       2021:078:00000 2021:079:00000 ns   -1.4928  0.0064"
    root, _ = _files(shared)
    with caplog.at_level(logging.WARNING, logger="leopod.io.bias_sinex"):
        ds = read_bias_sinex(root / "bia/COD0MGXFIN_20210780000_01D_01D_OSB.BIA.gz")
    assert ds.sizes["bias"] == 6844 and ds.attrs["n_estimates"] == 6888
    assert "6888" in caplog.text and "6844" in caplog.text
    first = ds.isel(bias=0)
    assert (str(first["prn"].values), str(first["obs1"].values)) == ("G01", "C1C")
    assert first["value_s"].item() == pytest.approx(-1.4928e-9, rel=1e-12)
    assert first["sigma_s"].item() == pytest.approx(0.0064e-9, rel=1e-12)
    assert first["start"].values == np.datetime64("2021-03-19T00:00:00", "ns")  # 2021 day 78


@pytest.mark.shared
def test_sinex_with_dashed_solution_numbers(shared):
    # igs10P1565_wocov.snx line 3077: " ABMF  A ---- P 10:002:00000 10:010:86370 ..." (SOLN
    # "----", SINEX 2.02 Appendix I: empty fields are filled with "-"); line 3449:
    # "     1 STAX   ABMF  A    1 10:006:43185 m    2 .29197857175080492E+7 .5945077E-2"
    root, _ = _files(shared)
    ds = read_sinex_stations(root / "snx/igs10P1565_wocov.snx.gz")
    abmf = ds.isel(solution=int(np.flatnonzero(ds["site"].values == "ABMF")[0]))
    assert abmf["pos_m"].values[0] == pytest.approx(2919785.7175080492, abs=1e-9)
    assert abmf["sigma_pos_m"].values[0] == pytest.approx(0.5945077e-2, rel=1e-12)
    assert abmf["valid_from"].values == np.datetime64("2010-01-02T00:00:00", "ns")
    assert abmf["valid_to"].values == np.datetime64("2010-01-10T23:59:30", "ns")


@pytest.mark.shared
def test_sinex_header_with_blank_agency(shared):
    # JAX0MGXFIN_20202440000_01D_000_SOL.SNX line 1:
    # "%=SNX 2.02     20:246:43630     20:244:00000 20:244:86100 P   405 2 S E"
    # (agency columns 12-14 and 29-31 blank; SINEX 2.02 header line is fixed-column); line
    # 808: "     1 STAX   ABPO  A ---- 20:244:00000 m    1  4.09721653707627e+06 1.96429e-03"
    root, _ = _files(shared)
    ds = read_sinex_stations(root / "snx/JAX0MGXFIN_20202440000_01D_000_SOL.SNX.gz")
    assert ds.attrs["agency"] == ""
    assert ds.attrs["creation_epoch"] == "2020-09-02T12:07:10"
    assert ds.attrs["data_start"] == "2020-08-31T00:00:00"
    assert ds.attrs["data_end"] == "2020-08-31T23:55:00"
    abpo = ds.isel(solution=int(np.flatnonzero(ds["site"].values == "ABPO")[0]))
    assert abpo["pos_m"].values[0] == pytest.approx(4.09721653707627e6, abs=1e-6)


@pytest.mark.shared
def test_rinex2_obs_scale_factor_applied(shared):
    # ice12720-scaled.07o lines 14-15: "    10     1    LA ... OBS SCALE FACTOR",
    # "   100     2    S1    S2 ... OBS SCALE FACTOR" (RINEX 2.11 Table A1: "factor to divide
    # stored observations with before use"); the unscaled twin ice12720.07o holds the same
    # observations divided by the factors.
    root, _ = _files(shared)
    scaled = read_rinex_obs(root / "obs/ice12720-scaled.07o")
    plain = read_rinex_obs(root / "obs/ice12720.07o")
    assert scaled.attrs["scale_factors_applied"] == "LA/10 S1/100 S2/100"
    for code in plain.data_vars:
        if plain[code].dtype.kind == "f":
            np.testing.assert_allclose(scaled[code].values, plain[code].values, rtol=1e-12,
                                       equal_nan=True, err_msg=code)


@pytest.mark.shared
def test_rinex3_sys_scale_factor_applied(shared):
    # bbbb0000.00o line 34: "R 1000   4 L1C S1C C1C L2C ... SYS / SCALE FACTOR"; line 68,
    # first epoch (2018-01-29 00:00:00): "R10  19186904.493 9 102277032.32809   54.500 ..."
    # (C1C L1C S1C ...): C1C is read as 19186904.493 / 1000, S2C (not scaled) as written.
    # Orekit's RinexObservationParserTest reads the same 19186.904493 and S2C 49.250.
    root, _ = _files(shared)
    ds = read_rinex_obs(root / "obs/bbbb0000.00o")
    r10 = ds.sel(sv="R10").isel(time=0)
    assert r10["C1C"].item() == pytest.approx(19186.904493, abs=1e-9)
    assert r10["L1C"].item() == pytest.approx(102277.032328, abs=1e-9)  # F14.3 + LLI 0 SSI 9
    assert r10["S2C"].item() == pytest.approx(49.250, abs=1e-12)
    g30 = ds.sel(sv="G30").isel(time=0)
    assert g30["C1C"].item() == pytest.approx(20422534.056, abs=1e-6)  # GPS: no factor


@pytest.mark.shared
def test_icgem_gravity_constant_of_another_body(shared):
    # GrazLGM300c.truncated lines 31-34: "gravity_constant 4.9028010560e+12", "radius
    # 1.7380000000e+06", "max_degree 12" (lunar model: ICGEM writes gravity_constant)
    root, _ = _files(shared)
    ds = read_icgem(root / "icgem/GrazLGM300c.truncated")
    assert ds.attrs["gm_m3_s2"] == 4.9028010560e12
    assert ds.attrs["radius_m"] == 1.738e6
    assert ds.attrs["max_degree"] == 12


@pytest.mark.shared
def test_lenient_reading_of_peer_files_with_a_documented_warning(shared, caplog):
    """Files that break a count or comment rule but whose values are unambiguous are read,
    with a warning naming the line (issue 24: "a warning with lenient reading is kinder")."""
    root, _ = _files(shared)
    with caplog.at_level(logging.WARNING):
        # com19402.clk line 331: "AS G16  2017 03 14 00 00  0.000000  2
        # 0.288119516655E-04  0.697888811575E-10  E" (a trailing flag after the 2 values)
        clk = read_rinex_clock(root / "clk/com19402.clk")
        assert clk["clk_s"].sel(sv="G16").values[0] == 0.288119516655e-4
        # mit19044_truncated_300.clk line 34: "AS G19  2016 07 07 00 00 30.000000  1
        # -0.525123304077E-03  0.200000000000E-09": count 1, the bias is read, not the sigma
        clk = read_rinex_clock(root / "clk/mit19044_truncated_300.clk")
        g19 = clk.sel(sv="G19", time="2016-07-07T00:00:30")
        assert g19["clk_s"].item() == -0.525123304077e-3
        assert np.isnan(g19["clk_sigma_s"].item())
        # GFZ0MGXRAP_20201380000_01D_05M_ORB.SP3: line 1 declares 288 epochs, the file holds 3
        # and ends with EOF (line 316); line 315: "PR24  17507.081667 -15039.877151
        # 10867.565310 ..." at the last epoch (line 219: 2020 5 17 0 10 0)
        sp3 = read_sp3(root / "sp3/GFZ0MGXRAP_20201380000_01D_05M_ORB.SP3")
        assert sp3.sizes["time"] == 3
        np.testing.assert_allclose(sp3["pos_m"].sel(sv="R24").values[-1],
                                   [17507081.667, -15039877.151, 10867565.310], atol=1e-6)
        # DLR0MGXFIN_..._DSB_trunc_sat.BSX: "- " sentences inside +FILE/COMMENT (lines 13-24);
        # line 52: " DSB  G063 G01           C1C  C1W  2021:274:00000 2021:275:00000 ns
        # -1.0454      0.0117"; %=BIA announces 246696 records, the truncated copy holds 266
        dsb = read_bias_sinex(root / "bia/DLR0MGXFIN_20212740000_03L_01D_DSB_trunc_sat.BSX")
        assert dsb.sizes["bias"] == 266
        assert dsb["value_s"].values[0] == pytest.approx(-1.0454e-9, rel=1e-12)
        assert str(dsb["obs2"].values[0]) == "C1W"
    for text in ("com19402.clk:331", "mit19044_truncated_300.clk:34", "declares 288 epochs",
                 "DSB_trunc_sat.BSX:13", "246696"):
        assert text in caplog.text


@pytest.mark.shared
def test_more_lenient_reading_of_peer_files(shared, caplog):
    root, _ = _files(shared)
    with caplog.at_level(logging.WARNING):
        # igs14_small.atx: the GALILEO-2 E04 antenna of line 512 is closed by the START OF
        # ANTENNA of line 679; its frequencies E05 and E07 are read
        atx = read_antex(root / "atx/igs14_small.atx.gz")
        e04 = [a for a in atx.antennas if a.serial == "E04"]
        assert len(atx.antennas) == 6 and e04[0].frequencies == ("E05", "E07")
        # emr08874.sp3 line 23: "*  1997  1  9  0  0   .0000000" (30 columns, SP3-a wants 31);
        # line 24: "P  1  15216.987064  21732.838988   1335.487660     10.539895"
        emr = read_sp3(root / "sp3/emr08874.sp3.gz")
        assert emr["time"].values[0] == np.datetime64("1997-01-09T00:00:00", "ns")
        np.testing.assert_allclose(emr["pos_m"].sel(sv="G01").values[0],
                                   [15216987.064, 21732838.988, 1335487.660], atol=1e-6)
        # issue895-no-eof.sp3 line 19: "%/* ilrsa.orb.lageos1.220101.v70.sp3 Reference TRF:
        # SLRF2008" (ILRS comment lines)
        ilrs = read_sp3(root / "sp3/issue895-no-eof.sp3")
        assert ilrs.attrs["comments"].startswith("ilrsa.orb.lageos1.220101.v70.sp3")
        # USNO1.txt lines 36-37: "DR USNO 1994 07 14 20 59  0.000000  2 ..." followed by an
        # unannounced continuation line; line 35: "AS G16 ... 2   -0.123456789012E+00
        # -0.123456789012E+01"
        usno = read_rinex_clock(root / "clk/USNO1.txt", ("AS", "AR"))
        assert usno["clk_s"].sel(sv="G16").values[0] == -0.123456789012
        # demo.10o line 13: "   4789028.4701    176610.0133   4195017.0310" (shifted by one
        # column from the F14.4 fields of APPROX POSITION XYZ)
        demo = read_rinex_obs(root / "obs/demo.10o")
        assert demo.attrs["approx_position_xyz_m"] == "4789028.4701 176610.0133 4195017.0310"
    for text in ("igs14_small.atx.gz:679", "issue895-no-eof.sp3:19", "USNO1.txt:37",
                 "demo.10o:13"):
        assert text in caplog.text


@pytest.mark.shared
def test_icgem2_piecewise_model_evaluated_at_an_epoch(shared):
    # EIGEN-6S4-v2-truncated (format icgem2.0, Ince et al. 2019): C10 on the interval
    # 20030101.0000-20040101.0000, lines 87-92: gfct 6.87432297897E-11, trnd -4.96847579522E-12,
    # acos/asin 1.0 y 7.82241505823E-11 / -3.41050412917E-12, acos/asin 0.5 y
    # -3.35798492155E-11 / -2.07233495045E-11
    root, _ = _files(shared)
    path = root / "icgem/EIGEN-6S4-v2-truncated.gz"
    with pytest.raises(FormatError, match="need an epoch") as err:
        read_icgem(path)
    assert err.value.line == 75
    ds = read_icgem(path, epoch="2003-07-02T12:00")
    dt = 182.5 / 365.25  # years since t0 = 2003-01-01
    w1, w2 = 2 * np.pi * dt / 1.0, 2 * np.pi * dt / 0.5
    want = (6.87432297897e-11 - 4.96847579522e-12 * dt
            + 7.82241505823e-11 * np.cos(w1) - 3.41050412917e-12 * np.sin(w1)
            - 3.35798492155e-11 * np.cos(w2) - 2.07233495045e-11 * np.sin(w2))
    assert ds["C"].values[1, 0] == pytest.approx(want, rel=1e-12)
    assert ds["sigma_C"].values[1, 0] == 1.1030e-13  # the gfct record's
    assert ds.attrs["epoch"].startswith("2003-07-02T12:00")
    assert ds.attrs["evaluated_terms"] == "gfct trnd acos asin"
