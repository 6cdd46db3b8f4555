"""Tests of the SINEX station / eccentricity reader and writer on real ILRS files.

Expected values are typed from the files (lines quoted); epochs follow the SINEX 2.02 rule
YY:DOY:SSSSS with YY < 50 -> 20YY.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.io._text import FormatError
from leopod.io.sinex import (
    read_sinex_eccentricities,
    read_sinex_stations,
    station_eccentricities,
    station_eccentricity,
    station_position,
    station_positions,
)
from leopod.io.sinex_write import write_sinex_stations

SLRF2020 = "SLRF2020_POS+VEL_2023.10.02.snx"
SLRF2014 = "SLRF2014_POS+VEL_2030.0_180504.snx"


def _ns(text: str) -> np.datetime64:
    return np.datetime64(text, "ns")


@pytest.fixture(scope="module")
def slr(shared_data):
    return shared_data / "slr"


@pytest.fixture(scope="module")
def slrf2020(slr):
    return read_sinex_stations(slr / SLRF2020)


def _row(ds, site, soln=1):
    i = np.flatnonzero((ds.site.values == site) & (ds.soln.values == soln))
    assert i.size == 1
    return ds.isel(solution=i[0])


# ------------------------------------------------------------------------------- stations
@pytest.mark.shared
def test_slrf2020_values(slrf2020):
    ds = slrf2020
    assert ds.attrs["format"] == "SINEX 2.02" and ds.attrs["agency"] == "IGN"
    assert list(ds.xyz.values) == ["x", "y", "z"]
    r = _row(ds, "7090")
    # line 1040: 205 STAX   7090  A    1 15:001:00000 m    2 -.238900777005032E+07 0.69543E-03
    # line 1041/1042: STAY 0.504332948581405E+07, STAZ -.307852397088064E+07
    np.testing.assert_array_equal(r.pos_m.values,
                                  [-2389007.77005032, 5043329.48581405, -3078523.97088064])
    assert r.sigma_pos_m.values[0] == 0.69543e-3
    # lines 1043-1045: VELX -.468239683104311E-01, VELY 0.797007645988301E-02,
    #                  VELZ 0.509599889854529E-01
    np.testing.assert_array_equal(r.vel_m_y.values,
                                  [-0.0468239683104311, 0.00797007645988301, 0.0509599889854529])
    assert r.ref_epoch.values == _ns("2015-01-01")
    # line 639: 7090  A    1 C 83:011:70773 00:000:00000 02:007:23100
    assert r.valid_from.values == _ns("1983-01-11T19:39:33")
    assert np.isnat(r.valid_to.values)
    # line 193: 7090  A 50107M001 L Yarragadee MOBLAS-5    115 20 48.2 -29 -2-47.3   242.0 ...
    assert r.domes.item() == "50107M001" and r.description.item() == "Yarragadee MOBLAS-5"
    assert r.approx_lon_deg.item() == pytest.approx(115 + 20 / 60 + 48.2 / 3600, abs=1e-12)
    assert r.approx_lat_deg.item() == pytest.approx(-(29 + 2 / 60 + 47.3 / 3600), abs=1e-12)
    assert r.approx_height_m.item() == 242.0
    for name in ds.data_vars:
        assert "long_name" in ds[name].attrs
        assert "units" in ds[name].attrs or ds[name].dtype.kind == "M"


@pytest.mark.shared
def test_slrf2020_reads_every_solution(slr):
    # reading time: benchmarks/readers.py
    ds = read_sinex_stations(slr / SLRF2020)
    assert ds.sizes["solution"] == 227  # 1362 STA/VEL parameters / 6
    assert np.isfinite(ds.pos_m.values).all() and np.isfinite(ds.vel_m_y.values).all()


@pytest.mark.shared
def test_station_position_propagates_and_picks_solution(slrf2020):
    r = _row(slrf2020, "7090")
    # 2015-01-01 -> 2023-01-01 is 2922 d = 8 Julian years
    expected = r.pos_m.values + 8.0 * r.vel_m_y.values
    np.testing.assert_allclose(station_position(slrf2020, "7090", "2023-01-01"), expected,
                               rtol=0, atol=1e-9)
    # line 610: 1868  A    1 C 93:311:32081 03:158:03672 ...
    # line 611: 1868  A    2 C 03:271:36854 00:000:00000 ...
    # line 866: 31 STAX   1868  A    1 15:001:00000 m    2 -.294854505348155E+07
    # line 872: 37 STAX   1868  A    2 15:001:00000 m    2 -.294854566037533E+07
    p1 = station_position(slrf2020, "1868", np.datetime64("2015-01-01"), pt="A")
    assert p1[0] == pytest.approx(-2948545.66037533, abs=1e-9)  # solution 2 (at ref epoch)
    p0 = station_position(slrf2020, "1868", "2000-01-01T00:00:00")
    # line 869: VELX 1868 A 1 -.210984110088682E-01; 2000-01-01 is 5479 d before 2015-01-01
    dt_years = -5479 / 365.25
    assert p0[0] == pytest.approx(-2948545.05348155 - 0.0210984110088682 * dt_years, abs=1e-8)
    with pytest.raises(KeyError, match="1868.*2003-08-01"):  # gap between the solutions
        station_position(slrf2020, "1868", "2003-08-01")
    with pytest.raises(KeyError, match="9999"):
        station_position(slrf2020, "9999", "2020-01-01")


def _one_by_one(lookup, ds, sites, epochs):
    """``lookup`` of each (site, epoch); None where it raises KeyError."""
    out = []
    for site, epoch in zip(sites, epochs, strict=True):
        try:
            out.append(lookup(ds, site, epoch))
        except KeyError:
            out.append(None)
    return out


#: Sites and epochs of the lookups above, in mixed order, with a gap and an unknown site.
_MANY = (["1868", "7090", "1868", "9999", "7090", "1868"],
         ["2000-01-01", "2023-01-01", "2003-08-01", "2020-01-01", "1990-11-12T23:59:59",
          "2015-01-01"])


@pytest.mark.shared
def test_station_positions_of_many_points_are_the_single_lookups(slrf2020):
    sites, epochs = _MANY
    many = station_positions(slrf2020, sites, np.array(epochs, dtype="datetime64[ns]"))
    for got, one in zip(many, _one_by_one(station_position, slrf2020, sites, epochs),
                        strict=True):
        if one is None:
            assert np.isnan(got).all()
        else:
            np.testing.assert_array_equal(got, one)
    assert np.isnan(many[[2, 3], 0]).all() and np.isfinite(many[[0, 1, 4, 5]]).all()


@pytest.mark.shared
def test_station_eccentricities_of_many_points_are_the_single_lookups(slr):
    ds = read_sinex_eccentricities(slr / "ecc_xyz.snx")
    sites, epochs = ["7090", "7090", "7307", "7090"], ["2023-01-01", "1987-04-20",
                                                      "1988-08-01", "1990-11-12T23:59:59"]
    ecc, systems = station_eccentricities(ds, sites, np.array(epochs, dtype="datetime64[ns]"))
    for got, system, one in zip(ecc, systems, _one_by_one(station_eccentricity, ds, sites,
                                                          epochs), strict=True):
        if one is None:
            assert np.isnan(got).all() and system == ""
        else:
            np.testing.assert_array_equal(got, one[0])
            assert system == one[1]
    assert systems.tolist().count("") == 1


@pytest.mark.shared
def test_slrf2014_open_end_50_000(slr):
    ds = read_sinex_stations(slr / SLRF2014)
    assert ds.attrs["format"] == "SINEX 2.01"
    r = _row(ds, "7090")
    # line 619: 7090  A    1 C 83:011:58876 50:000:00000 99:007:13417  (50:000 = open end)
    assert r.valid_from.values == _ns("1983-01-11T16:21:16") and np.isnat(r.valid_to.values)
    # line 1013: 205 STAX   7090  A    1 10:001:00000 m    2 -.238900753398029E+07 0.51901E-03
    assert r.pos_m.values[0] == -2389007.53398029
    assert r.ref_epoch.values == _ns("2010-01-01")


@pytest.mark.shared
def test_ilrs_daily_solution_without_velocities(shared_data):
    ds = read_sinex_stations(shared_data / "swarm-a_2023-001" / "ilrsa.pos+eop.230101.v170.snx")
    assert ds.sizes["solution"] == 15 and ds.attrs["format"] == "SINEX 2.00"
    r = _row(ds, "1873")
    # SOLUTION/ESTIMATE line 152: 1 STAX   1873  A    1 22:363:43200 m    2 0.378390204296484E+07
    # (not the SOLUTION/APRIORI value 0.378390000000000E+07 of line 82)
    assert r.pos_m.values[0] == 3783902.04296484
    assert r.sigma_pos_m.values[0] == 0.136901
    assert r.ref_epoch.values == _ns("2022-12-29T12:00:00")
    assert np.isnan(r.vel_m_y.values).all()
    # line 46: 7839  A    1 L 22:360:00321 23:001:85105 22:363:42713 -> constant position
    r = _row(ds, "7839")
    np.testing.assert_array_equal(station_position(ds, "7839", "2022-12-30"), r.pos_m.values)
    # line 50: 1873 data span 22:360:61983-22:360:65425 only
    with pytest.raises(KeyError, match="1873"):
        station_position(ds, "1873", "2022-12-29T12:00")


@pytest.mark.shared
@pytest.mark.parametrize("name", [SLRF2020, SLRF2014])
def test_write_read_round_trip(slr, tmp_path, name):
    ds = read_sinex_stations(slr / name)
    out = tmp_path / "stations.snx"
    write_sinex_stations(ds, out)
    back = read_sinex_stations(out)
    for var in ("site", "pt", "soln", "domes", "pos_m", "vel_m_y", "sigma_pos_m",
                "ref_epoch", "valid_from", "valid_to"):
        np.testing.assert_array_equal(back[var].values, ds[var].values, err_msg=var)
    np.testing.assert_allclose(back.approx_lat_deg.values, ds.approx_lat_deg.values,
                               atol=0.05 / 3600)


def test_write_minimal_dataset(tmp_path):
    ds = xr.Dataset(
        {"site": ("solution", ["7839", "7090"]),
         "pos_m": (("solution", "xyz"), [[4194426.5, 1162694.0, 4647246.6],
                                         [-2389008.1, 5043329.5, -3078523.6]]),
         "ref_epoch": ("solution", np.array(["2023-01-01T00:00:00.4"] * 2,
                                            dtype="datetime64[ns]"))},
        coords={"xyz": ["x", "y", "z"]},
    )
    out = tmp_path / "sim.snx"
    write_sinex_stations(ds, out)
    back = read_sinex_stations(out)
    np.testing.assert_array_equal(back.pos_m.values, ds.pos_m.values)
    assert (back.ref_epoch.values == _ns("2023-01-01")).all()  # 1 s resolution
    assert np.isnat(back.valid_from.values).all() and np.isnan(back.vel_m_y.values).all()
    np.testing.assert_array_equal(station_position(back, "7090", "2030-01-01"), ds.pos_m[1])
    with pytest.raises(ValueError, match="ref_epoch"):
        write_sinex_stations(ds.drop_vars("ref_epoch"), out)
    with pytest.raises(ValueError, match="1-4 characters"):
        write_sinex_stations(ds.assign(site=("solution", ["78390", "7090"])), out)


# ------------------------------------------------------------------------------- eccentricities
@pytest.mark.shared
def test_eccentricities_xyz(slr):
    ds = read_sinex_eccentricities(slr / "ecc_xyz.snx")
    assert ds.attrs["ref_system"] == "XYZ" and list(ds.component.values) == ["x", "y", "z"]
    assert ds.sizes["record"] == 554
    # line 927: 7090  A    1 L 14:080:00000 00:000:00000 XYZ  -1.2073   2.5034  -1.5509  70900513
    ecc, system = station_eccentricity(ds, "7090", "2023-01-01")
    np.testing.assert_array_equal(ecc, [-1.2073, 2.5034, -1.5509])
    assert system == "XYZ"
    # line 917: 7090  A    1 L 89:217:00000 90:316:86399 XYZ  -1.1990   2.5070  -1.5400
    ecc, _ = station_eccentricity(ds, "7090", "1990-11-12T23:59:59")
    np.testing.assert_array_equal(ecc, [-1.1990, 2.5070, -1.5400])
    # lines 913/914: validity ends 87:106:86399 and restarts 87:113:00000 -> gap on 1987-04-20
    with pytest.raises(KeyError, match="7090.*1987-04-20"):
        station_eccentricity(ds, "7090", "1987-04-20")
    # line 1098: 7307  A    1 L 88:200:00000 88:261:86399 XYZ2996.43502761.4890-1364.643
    # (values fill their 9 columns)
    i = np.flatnonzero((ds.site.values == "7307") & (ds.pt.values == "A"))[0]
    np.testing.assert_array_equal(ds.ecc_m.values[i], [2996.4350, 2761.4890, -1364.643])
    assert ds.cdp_sod.values[i] == "73071701"
    assert ds.valid_to.values[i] == _ns("1988-09-17T23:59:59")


@pytest.mark.shared
def test_eccentricity_block_with_untagged_title_line(shared_data):
    # ilrsa file line 74: "SITE PT SOLN T DATA_START__ ..." (no leading '*')
    ds = read_sinex_eccentricities(shared_data / "swarm-a_2023-001" /
                                   "ilrsa.pos+eop.230101.v170.snx")
    assert list(ds.site.values) == ["1873", "1889", "1890"]
    assert (ds.cdp_sod.values == "").all()


_UNE = """%=SNX 2.02 JCT 23:073:72000 JCT 68:041:00000 23:060:00000 L 00553 0 X
+SITE/ECCENTRICITY
*SITE PT SOLN T DATA_START__ DATA_END____ UNE U_______ N_______ E_______
 7300  A    1 L 89:010:00000 89:083:00000 UNE  -0.6140-516.4230-565.4650
 7304  A    1 L 90:336:00000 91:038:00000 {sys}   1.8990-114.0920 152.6220
-SITE/ECCENTRICITY
%ENDSNX
"""


def test_eccentricities_une_and_mixed(tmp_path):
    path = tmp_path / "une.snx"
    path.write_text(_UNE.format(sys="UNE"))
    ds = read_sinex_eccentricities(path)
    assert ds.attrs["ref_system"] == "UNE" and list(ds.component.values) == ["u", "n", "e"]
    ecc, system = station_eccentricity(ds, "7300", "1989-02-01")
    np.testing.assert_array_equal(ecc, [-0.6140, -516.4230, -565.4650])
    assert system == "UNE"
    path.write_text(_UNE.format(sys="XYZ"))
    ds = read_sinex_eccentricities(path)
    assert ds.attrs["ref_system"] == "mixed" and list(ds.ref_system.values) == ["UNE", "XYZ"]
    path.write_text(_UNE.format(sys="ABC"))
    with pytest.raises(FormatError, match="ABC") as err:
        read_sinex_eccentricities(path)
    assert err.value.line == 5 and "une.snx" in str(err.value)


# ------------------------------------------------------------------------------- broken copies
@pytest.fixture()
def lines2020(slr):
    return (slr / SLRF2020).read_text().splitlines()


def _write(tmp_path, lines):
    path = tmp_path / "broken.snx"
    path.write_text("\n".join(lines) + "\n")
    return path


def _expect(path, line, field, *words, reader=read_sinex_stations):
    with pytest.raises(FormatError) as err:
        reader(path)
    msg = str(err.value)
    assert path.name in msg and err.value.line == line and err.value.field == field, msg
    for w in words:
        assert w in msg, msg


@pytest.mark.shared
def test_truncated_in_estimate_block(lines2020, tmp_path):
    lines = lines2020[:1039] + [lines2020[1039][:60]]  # line 1040 cut in its value
    _expect(_write(tmp_path, lines), 1040, "-SOLUTION/ESTIMATE", "not closed")
    lines = lines2020[:-1]  # no %ENDSNX
    _expect(_write(tmp_path, lines), len(lines), "%ENDSNX")


@pytest.mark.shared
def test_missing_blocks_and_header(lines2020, tmp_path):
    lines = lines2020[:118] + lines2020[601:]  # drop +SITE/ID ... -SITE/ID (lines 119-601)
    _expect(_write(tmp_path, lines), None, "SITE/ID", "missing")
    lines = ["%=XYZ"] + lines2020[1:]
    _expect(_write(tmp_path, lines), 1, "%=SNX")
    _expect(_write(tmp_path, lines2020), None, "SITE/ECCENTRICITY",
            reader=read_sinex_eccentricities)


@pytest.mark.shared
def test_non_numeric_nan_and_bad_fields(lines2020, tmp_path):
    lines = list(lines2020)
    lines[1039] = lines[1039].replace("-.238900777005032E+07", "-.2389007x7005032E+07")
    _expect(_write(tmp_path, lines), 1040, "STAX ESTIMATED VALUE", "-.2389007x7005032E+07")
    lines[1039] = lines2020[1039].replace("-.238900777005032E+07", "                  NaN")
    _expect(_write(tmp_path, lines), 1040, "STAX ESTIMATED VALUE", "finite")
    lines[1039] = lines2020[1039].replace("15:001:00000", "15:400:00000")
    _expect(_write(tmp_path, lines), 1040, "REF_EPOCH", "15:400:00000")
    lines[1039] = lines2020[1039].replace(" m    2 ", " mm   2 ")
    _expect(_write(tmp_path, lines), 1040, "UNIT", "mm")
    lines = list(lines2020)
    lines[638] = lines[638].replace("83:011:70773", "83:011:7O773")  # letter O
    _expect(_write(tmp_path, lines), 639, "DATA_START")
    lines = list(lines2020)
    lines[192] = lines[192].replace("115 20 48.2", "115 2x 48.2")
    _expect(_write(tmp_path, lines), 193, "APPROX_LON")


@pytest.mark.shared
def test_incomplete_or_duplicated_solution(lines2020, tmp_path):
    lines = lines2020[:1041] + lines2020[1042:]  # drop line 1042 (STAZ 7090)
    _expect(_write(tmp_path, lines), 1040, "STAZ", "7090")
    lines = lines2020[:1042] + lines2020[1043:]  # drop line 1043 (VELX 7090)
    _expect(_write(tmp_path, lines), 1040, "VELX/VELY/VELZ", "7090")
    lines = lines2020[:1040] + [lines2020[1039]] + lines2020[1040:]  # STAX twice
    _expect(_write(tmp_path, lines), 1041, "STAX", "twice")
