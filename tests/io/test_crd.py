"""Tests of the ILRS CRD reader/writer against the real files in ../shared/data/slr.

Expected values are typed from the files (lines quoted); epochs follow the CRD rule "H4 start
date + seconds of day, the date advancing when the pass crosses midnight" (CRD 1.01/2.01).
"""

from __future__ import annotations

import datetime as dt
import gzip
import logging

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.io._text import FormatError
from leopod.io.crd import ilrs_id_to_cospar, read_crd
from leopod.io.crd_write import write_crd

PROD = dt.datetime(2024, 1, 2, 3)


def _ns(text: str) -> np.datetime64:
    return np.datetime64(text, "ns")


@pytest.fixture(scope="module")
def slr(shared_data):
    return shared_data / "slr"


# ------------------------------------------------------------------------------- real files
@pytest.mark.shared
def test_v1_normal_points_lageos1(slr):
    ds = read_crd(slr / "lageos1-test.npt")
    assert ds.sizes["point"] == 14
    assert ds.attrs["crd_versions"] == "1" and ds.attrs["n_sessions"] == 3
    assert ds.attrs["time_system"] == "UTC"
    p = ds.isel(point=0)
    # line 4: H4  1 2021 01 19 23 04 46 ...
    # line 16: 11 83098.3290105      .048305496438 PDAS 2  120      7   48.  -1.000 ...
    assert p.time.values == _ns("2021-01-19T23:04:58.329010500")
    assert p.tof_s.item() == 0.048305496438
    assert p.range_m.item() == pytest.approx(0.048305496438 * C_LIGHT_M_S / 2, rel=1e-15)
    assert p.np_window_s.item() == 120.0
    assert p.n_raw.item() == 7
    assert p.bin_rms_s.item() == pytest.approx(48e-12, rel=1e-12)
    assert p.bin_skew.item() == -1.0  # CRD 1 placeholder kept as written
    assert p.snr.isnull().item()
    assert p.epoch_event.item() == 2 and p.system_config.item() == "PDAS"
    # line 2: H2 KTZL       1893 18 01  4 ; line 3: H3 lageos1     7603901 1155     8820 0 1
    assert p.station.item() == "1893" and p.station_name.item() == "KTZL"
    assert p.system_number.item() == 18 and p.occupancy_number.item() == 1
    assert p.time_scale.item() == 4
    assert p.satellite.item() == "lageos1" and p.ilrs_id.item() == "7603901"
    assert p.cospar_id.item() == "1976-039A" and p.norad_id.item() == 8820
    # line 4 flags: 0 0 0 0 1 0 2 0
    assert p.station_delay_applied.item() == 1 and p.com_applied.item() == 0
    assert p.range_type.item() == 2 and p.data_release.item() == 0
    assert p.wavelength_nm.item() == 532.0  # line 5: C0 0  532.0 PDAS ...
    # lines 14 and 21: 20 82905.0 1018.0 271.25  44. 0 / 20 83860.0 1018.0 271.75  43. 0
    w = (83098.3290105 - 82905.0) / (83860.0 - 82905.0)
    assert p.pressure_hpa.item() == pytest.approx(1018.0)
    assert p.temperature_k.item() == pytest.approx(271.25 + 0.5 * w, abs=1e-9)
    assert p.humidity_pct.item() == pytest.approx(44.0 - w, abs=1e-9)
    for name in ds.data_vars:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs


@pytest.mark.shared
def test_day_rollover_graz_pass(slr):
    ds = read_crd(slr / "lageos1-test.npt")
    g = ds.isel(point=np.flatnonzero(ds.pass_id.values == 1))
    assert set(g.station.values) == {"7839"}
    # H4  1 2021  3  6 23 27 40 ...; "11 86250.143563567664" stays on 03-06,
    # "11   101.312063571997    0.044236844760" is after midnight: 2021-03-07
    assert g.time.values[2] == _ns("2021-03-06T23:57:30.143563568")
    assert g.time.values[3] == _ns("2021-03-07T00:01:41.312063572")
    assert g.tof_s.values[3] == 0.044236844760
    assert np.all(np.diff(g.time.values) > np.timedelta64(0))
    # line 31/32: 20 85000 970.07 ... / 20  1330 969.72 ... (the second is on 03-07)
    w = (86400 + 101.312063572 - 85000) / (86400 + 1330 - 85000)
    assert g.pressure_hpa.values[3] == pytest.approx(970.07 + w * (969.72 - 970.07), abs=1e-9)


@pytest.mark.shared
def test_v2_normal_points_lageos2(slr):
    ds = read_crd(slr / "lageos2_201802.npt.v2C")
    assert ds.sizes["point"] == 300  # 300 records '11'
    assert ds.attrs["n_sessions"] == 37  # 37 records 'h4'
    assert ds.attrs["crd_versions"] == "2"
    p = ds.isel(point=0)
    # line 4: h4 1 2018 2 1 15 14 58 ...
    # line 16: 11 54927.620161400002 0.044106029140 std 2 120.0 1457 70.0 0.319 2.496 -12.0
    #          1.2 0 5.7
    assert p.time.values == _ns("2018-02-01T15:15:27.620161400")
    assert p.tof_s.item() == 0.044106029140
    assert p.n_raw.item() == 1457
    assert p.bin_rms_s.item() == pytest.approx(70.0e-12, rel=1e-12)
    assert p.bin_skew.item() == 0.319 and p.bin_kurtosis.item() == 2.496
    assert p.bin_peak_minus_mean_s.item() == pytest.approx(-12.0e-12, rel=1e-12)
    assert p.return_rate_pct.item() == 1.2 and p.snr.item() == 5.7
    # line 2: h2 CHAL 9998 19 01 4 WPLTN ; line 3: h3 lageos2 9207002 5986 22195 0 1 1
    assert p.station.item() == "9998" and p.station_name.item() == "CHAL"
    assert p.cospar_id.item() == "1992-070B" and p.norad_id.item() == 22195
    # line 15: 20 56940.000 998.90 259.10 80 0 (the only met record of the session)
    assert p.pressure_hpa.item() == 998.90 and p.temperature_k.item() == 259.10
    assert p.humidity_pct.item() == 80.0
    assert np.all(ds.pass_id.values[1:] >= ds.pass_id.values[:-1])


@pytest.mark.shared
def test_crd201_specification_samples(slr):
    ds = read_crd(slr / "crd201_all_samples")
    assert ds.attrs["crd_versions"] == "1,2"
    jason = ds.isel(point=np.flatnonzero(ds.satellite.values == "jason1"))
    # line 108: h3 jason1 105501 4378 26997 0 1 1 ; h4 ... 2008  3 25  0 45 17 ...
    assert jason.ilrs_id.values[0] == "0105501" and jason.cospar_id.values[0] == "2001-055A"
    # line 120: 11  2726.697640514675     0.013737698432 std  2   15      1   72.7 ... 0 20.7
    assert jason.time.values[0] == _ns("2008-03-25T00:45:26.697640515")
    assert jason.tof_s.values[0] == 0.013737698432
    assert jason.np_window_s.values[0] == 15.0 and jason.snr.values[0] == 20.7
    # line 121 (2804.507921286791) between lines 118 (20  2716.000 801.73 286.76 35.)
    # and 123 (20  2822.000 801.73 286.56 35.)
    w = (2804.507921286791 - 2716.0) / (2822.0 - 2716.0)
    assert jason.temperature_k.values[1] == pytest.approx(286.76 - 0.2 * w, abs=1e-9)
    # two-colour Zimmerwald: line 72/73 C0 0 846.000 std1 / C0 0 423.000 std2,
    # line 77: 11 27343.5080895 0.051405458691 std2 ...
    k = np.flatnonzero(ds.tof_s.values == 0.051405458691)[0]
    assert ds.system_config.values[k] == "std2" and ds.wavelength_nm.values[k] == 423.0
    assert set(ds.wavelength_nm.values[ds.station.values == "7810"]) >= {846.0, 423.0}
    # line 273: h2 YARL       7090  5 13 3       ILRS  (time scale 3 = UTC(USNO))
    assert set(ds.time_scale.values[ds.station_name.values == "YARL"]) == {3}
    # YARL line: 11  8357.400568200001 ... 1.33 0 na  -> snr NaN
    assert np.isnan(ds.snr.values[ds.station_name.values == "YARL"]).all()


@pytest.mark.shared
def test_full_rate_records(slr):
    ds = read_crd(slr / "champ_201709-small.frd", record="full_rate")
    assert ds.sizes["point"] == 4 and ds.attrs["record"] == "full_rate"
    p = ds.isel(point=0)
    # H4  0 2017 09 26 03 55 41 ...
    # 10 14487.343206247217   0.003603959600  IDAA 2 2 0 0     0
    assert p.time.values == _ns("2017-09-26T04:01:27.343206247")
    assert p.tof_s.item() == 0.003603959600
    assert p.data_type.item() == 0 and p.filter_flag.item() == 2
    assert p.receive_amplitude.item() == 0 and p.transmit_amplitude.item() == -1
    assert p.wavelength_nm.item() == 532.10  # C0 0 532.10 IDAA IDAB IDAJ IDAV
    assert p.cospar_id.item() == "2000-039B"  # H3 champ       0003902 ...
    # 20 14353.388283000000 923.74 289.42 28.1 0 (only met record)
    assert p.pressure_hpa.item() == 923.74
    samples = read_crd(slr / "crd201_all_samples", record="full_rate")
    # line 8: 10 55432.0414338 0.047960587856 std1 2 0 0 0 -na na
    q = samples.isel(point=0)
    assert q.time.values == _ns("2006-11-13T15:23:52.041433800")
    assert q.receive_amplitude.item() == -1 and q.transmit_amplitude.item() == -1


@pytest.mark.shared
def test_wrong_record_kind_gives_empty_dataset(slr, caplog):
    with caplog.at_level(logging.WARNING, logger="leopod.io.crd"):
        ds = read_crd(slr / "champ_201709-small.frd")
    assert ds.sizes["point"] == 0 and "tof_s" in ds and "no record 11" in caplog.text
    with pytest.raises(ValueError, match="record must be"):
        read_crd(slr / "champ_201709-small.frd", record="quicklook")


@pytest.mark.shared
def test_gzip_copy_reads_the_same(slr, tmp_path):
    src = slr / "lageos1-test.npt"
    gz = tmp_path / "lageos1-test.npt.gz"
    gz.write_bytes(gzip.compress(src.read_bytes()))
    assert read_crd(gz).identical(read_crd(src).assign_attrs(source=gz.name))


def test_ilrs_id_to_cospar():
    assert ilrs_id_to_cospar("7603901") == "1976-039A"
    assert ilrs_id_to_cospar("0003902") == "2000-039B"
    assert ilrs_id_to_cospar("0105509") == "2001-055J"  # I is skipped
    assert ilrs_id_to_cospar("0105525") == "2001-055AA"
    assert ilrs_id_to_cospar("0000000") == ""
    assert ilrs_id_to_cospar("12345") == ""


# ------------------------------------------------------------------------------- round trips
@pytest.mark.shared
@pytest.mark.parametrize("version", [1, 2])
@pytest.mark.parametrize("name", ["lageos2_201802.npt.v2C", "lageos1-test.npt"])
def test_write_read_round_trip(slr, tmp_path, name, version):
    ds = read_crd(slr / name)
    out = tmp_path / "rt.npt"
    write_crd(ds, out, version=version, production_time=PROD)
    back = read_crd(out)
    assert back.attrs["crd_versions"] == str(version)
    np.testing.assert_array_equal(back.time.values, ds.time.values)  # 1 ns
    np.testing.assert_array_equal(back.tof_s.values, ds.tof_s.values)  # 1 ps, exact
    for name_ in ("station", "station_name", "satellite", "ilrs_id", "cospar_id", "norad_id",
                  "n_raw", "system_config", "wavelength_nm", "time_scale", "range_type",
                  "system_number", "occupancy_number", "station_delay_applied", "epoch_event"):
        np.testing.assert_array_equal(back[name_].values, ds[name_].values, err_msg=name_)
    tol = 0.05e-12 if version == 1 else 0.5e-15
    np.testing.assert_allclose(back.bin_rms_s.values, ds.bin_rms_s.values, atol=tol)
    for name_, res in (("pressure_hpa", 0.005), ("temperature_k", 0.005)):
        np.testing.assert_allclose(back[name_].values, ds[name_].values, atol=res + 1e-9)
    np.testing.assert_allclose(back.humidity_pct.values, ds.humidity_pct.values,
                               atol=0.5 if version == 1 else 0.05 + 1e-9)
    if version == 2:
        np.testing.assert_array_equal(np.isnan(back.snr.values), np.isnan(ds.snr.values))


def _synthetic(n_pass=2):
    """Two passes of a simulated LEO with minimal variables, one crossing midnight."""
    t0 = [_ns("2023-01-01T23:55:00.123456789"), _ns("2023-01-02T14:00:00")]
    times = np.concatenate([t + np.arange(5) * np.timedelta64(150, "s") for t in t0[:n_pass]])
    n = times.size
    return xr.Dataset(
        {"tof_s": ("point", np.linspace(0.004, 0.006, n)),
         "pass_id": ("point", np.repeat(np.arange(n_pass), 5)),
         "station": ("point", np.full(n, "7839")),
         "satellite": ("point", np.full(n, "swarma")),
         "ilrs_id": ("point", np.full(n, "1306702")),
         "wavelength_nm": ("point", np.full(n, 532.0))},
        coords={"time": ("point", times)},
    )


def test_write_minimal_dataset_and_defaults(tmp_path):
    ds = _synthetic()
    out = tmp_path / "sim.npt"
    write_crd(ds, out, production_time=PROD)
    text = out.read_text().splitlines()
    assert text[0] == "H1 CRD  2 2024  1  2  3"
    assert text[3].startswith("H4  1 2023  1  1 23 55  0 2023  1  2  0  5  1")
    assert text[-1] == "H9" and text.count("H8") == 2
    back = read_crd(out)
    np.testing.assert_array_equal(back.time.values, ds.time.values)
    ps = [float(f"{x:.12f}") for x in ds.tof_s.values]  # written to 1 ps
    np.testing.assert_array_equal(back.tof_s.values, ps)
    assert list(back.pass_id.values) == [0] * 5 + [1] * 5
    assert set(back.cospar_id.values) == {"2013-067B"}
    assert set(back.station_name.values) == {"7839"} and set(back.time_scale.values) == {4}
    assert np.isnan(back.pressure_hpa.values).all() and (back.n_raw.values == -1).all()


def test_write_errors(tmp_path):
    ds = _synthetic()
    with pytest.raises(ValueError, match="ilrs_id"):
        write_crd(ds.drop_vars("ilrs_id"), tmp_path / "x.npt")
    with pytest.raises(ValueError, match="4-digit"):
        write_crd(ds.assign(station=("point", np.full(10, "78390"))), tmp_path / "x.npt")
    with pytest.raises(ValueError, match="version"):
        write_crd(ds, tmp_path / "x.npt", version=3)
    long = ds.assign(pass_id=("point", np.zeros(10, dtype=int)))
    with pytest.raises(ValueError, match="shorter than 12 h"):
        write_crd(long, tmp_path / "x.npt")
    with pytest.raises(ValueError, match="CRD 1 allows 4"):
        write_crd(ds.assign(system_config=("point", np.full(10, "long5"))),
                  tmp_path / "x.npt", version=1)
    with pytest.raises(ValueError, match="finite"):
        write_crd(ds.assign(tof_s=ds.tof_s.where(ds.tof_s < 0.005)), tmp_path / "x.npt")


# ------------------------------------------------------------------------------- broken copies
@pytest.fixture()
def v2_lines(slr):
    return (slr / "lageos2_201802.npt.v2C").read_text().splitlines()


def _write(tmp_path, lines, name="broken.npt"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def _expect(path, line, field, *words):
    with pytest.raises(FormatError) as err:
        read_crd(path)
    msg = str(err.value)
    assert path.name in msg and err.value.line == line and err.value.field == field, msg
    for w in words:
        assert w in msg, msg
    return err.value


@pytest.mark.shared
def test_truncated_mid_record(v2_lines, tmp_path):
    # line 17: 11 55016.185001400001 0.043352169422 std 2 120.0 2973 67.8 ... cut after 4 fields
    lines = v2_lines[:16] + ["11 55016.185001400001 0.043352169422 std"]
    _expect(_write(tmp_path, lines), 17, "11", "fields")


@pytest.mark.shared
def test_missing_h4(v2_lines, tmp_path):
    lines = v2_lines[:3] + v2_lines[4:]  # drop line 4 (h4): line 15 '20 ...' is now line 14
    _expect(_write(tmp_path, lines), 14, "H4", "record 20", "before any H4")


@pytest.mark.shared
def test_missing_h2(v2_lines, tmp_path):
    lines = v2_lines[:1] + v2_lines[2:]  # drop h2: the h4 is now line 3
    _expect(_write(tmp_path, lines), 3, "H2", "without a preceding H2")


@pytest.mark.shared
def test_non_numeric_and_nan_time_of_flight(v2_lines, tmp_path):
    lines = list(v2_lines)
    lines[17] = lines[17].replace("0.042694613343", "0.04269x613343")  # line 18
    _expect(_write(tmp_path, lines), 18, "11 time of flight", "0.04269x613343")
    lines[17] = lines[17].replace("0.04269x613343", "nan")
    _expect(_write(tmp_path, lines), 18, "11 time of flight", "not a finite")
    lines[17] = lines[17].replace(" nan ", " na ")  # 'na' is not allowed for a mandatory field
    _expect(_write(tmp_path, lines), 18, "11 time of flight")


@pytest.mark.shared
def test_bad_seconds_of_day(v2_lines, tmp_path):
    lines = list(v2_lines)
    lines[18] = lines[18].replace("56209.259001400002", "96209.259001400002")  # line 19
    _expect(_write(tmp_path, lines), 19, "11 seconds of day", "96209.259001400002")
    lines[18] = lines[18].replace("96209.259001400002", "56209.25900:400002")
    _expect(_write(tmp_path, lines), 19, "11 seconds of day")


@pytest.mark.shared
def test_bad_optional_field_and_header_values(v2_lines, tmp_path):
    lines = list(v2_lines)
    lines[15] = lines[15].replace(" 1457 ", " 14x7 ")  # line 16, number of raw ranges
    _expect(_write(tmp_path, lines), 16, "11 number of raw ranges", "14x7")
    lines = list(v2_lines)
    lines[1] = "h2 CHAL 9998 19 01 5 WPLTN"  # time scale 5 is not defined
    _expect(_write(tmp_path, lines), 2, "H2 epoch time scale", "5")
    lines = list(v2_lines)
    lines[0] = "h1 CRD 3 2018 2 1 17"
    _expect(_write(tmp_path, lines), 1, "H1 format version")
    lines = list(v2_lines)
    lines[3] = "h4 1 2018 2 30 15 14 58 2018 2 1 15 48 57 0 0 0 0 1 0 2 0"  # 30 February
    _expect(_write(tmp_path, lines), 4, "H4 start")
    lines = list(v2_lines)
    lines[12] = "77 unknown record"
    _expect(_write(tmp_path, lines), 13, "77", "unknown record")
    lines = list(v2_lines)
    lines[14] = "20 56940.000 998.90 NaN 80 0"  # line 15, met temperature
    _expect(_write(tmp_path, lines), 15, "20 temperature", "finite")
    _expect(_write(tmp_path, ["00 only a comment"]), None, "H1", "no H1")


@pytest.mark.shared
def test_data_after_h8(v2_lines, tmp_path):
    k = v2_lines.index("h8")
    lines = v2_lines[:k + 1] + [v2_lines[15]] + v2_lines[k + 1:]
    _expect(_write(tmp_path, lines), k + 2, "H4", "after H8")


@pytest.mark.shared
def test_session_without_h8_is_kept_with_warning(v2_lines, tmp_path, caplog):
    k = v2_lines.index("h8")  # first session ends at line k+1
    path = _write(tmp_path, v2_lines[:k])  # cut after a complete record: no h8, no h9
    with caplog.at_level(logging.WARNING, logger="leopod.io.crd"):
        ds = read_crd(path)
    assert ds.sizes["point"] == 6
    assert "line 4 is not closed by H8" in caplog.text
