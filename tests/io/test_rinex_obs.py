"""Tests of leopod.io.rinex_obs: real LEO files, georinex cross-check, writer round trips,
hand-built files with events, and broken copies.

Authorities: values typed from the real files (line quoted), the independent reader georinex,
and the RINEX 2.11 / 3.04 specifications for the hand-built files.
"""

from __future__ import annotations

import gzip
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from leopod.io._text import FormatError
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.rinex_obs_write import write_rinex_obs

GRACE_A = "grace-a_2007-080/graa0800.07o.gz"
GRACE_B = "grace-b_2010-208/GRCB2080.10D"
ICESAT = "format_fixtures/ice12720.07o"
GPS1B = "grace_l1b_fixture_2003-09-14/GPS1B_2003-09-14_A_00.rnx"


def _hl(text: str, label: str) -> str:
    """A header line: content in columns 1-60, label from column 61."""
    return f"{text:<60}{label}"


def _obs(value: float | None, lli: str = " ", ssi: str = " ") -> str:
    """One observation field as the specification defines it: F14.3, I1, I1."""
    return " " * 16 if value is None else f"{value:14.3f}{lli}{ssi}"


def _assert_error(excinfo, path: Path, line: int | None, field: str):
    """The FormatError names the file, the line and the field."""
    err = excinfo.value
    assert err.line == line
    assert err.field == field
    text = str(excinfo.value)
    assert path.name in text
    assert f"'{field}'" in text
    if line is not None:
        assert f":{line}:" in text


@pytest.fixture(scope="module")
def grace_a(shared_data) -> xr.Dataset:
    return read_rinex_obs(shared_data / GRACE_A)


@pytest.fixture(scope="module")
def grace_a_lines(shared_data) -> list[str]:
    return gzip.decompress((shared_data / GRACE_A).read_bytes()).decode("latin-1").splitlines()


# ------------------------------------------------------------------------------- real files


@pytest.mark.shared
def test_grace_a_day(grace_a):
    ds = grace_a
    assert ds.sizes["time"] == 8640
    assert ds.time.dtype == np.dtype("datetime64[ns]")
    assert ds.time.values[0] == np.datetime64("2007-03-21T00:00:00")
    assert ds.time.values[-1] == np.datetime64("2007-03-21T23:59:50")
    assert list(ds.sv.values) == sorted(ds.sv.values)
    assert ds.attrs["rinex_version"] == 2.10
    assert ds.attrs["marker_name"] == "GRACE A"
    assert ds.attrs["receiver_type"] == "RECTYPE"
    assert ds.attrs["time_system"] == "GPS"
    assert ds.attrs["interval_s"] == 10.0
    assert ds.attrs["obs_types_G"] == "L1 L2 P1 P2 C1"
    assert ds.attrs["approx_position_xyz_m"] == "0.0000 0.0000 0.0000"
    assert ds.attrs["filename"] == "graa0800.07o.gz"
    # graa0800.07o, line 24: " 07  3 21  0  0  0.0000000  0  9G 1G 5G 9G11G14G17G22G30G31"
    # line 25: " 125648581.66556  97908014.82856  23910130.01546  23910136.97546  23910129.84148"
    g01 = ds.sel(time="2007-03-21T00:00:00", sv="G01")
    expected = {"L1": (125648581.665, 5, 6), "L2": (97908014.828, 5, 6),
                "P1": (23910130.015, 4, 6), "P2": (23910136.975, 4, 6),
                "C1": (23910129.841, 4, 8)}
    for code, (value, lli, ssi) in expected.items():
        assert g01[code].item() == pytest.approx(value, abs=1e-9)
        assert g01[f"{code}_lli"].item() == lli
        assert g01[f"{code}_ssi"].item() == ssi
    assert int((ds["L1"].isel(time=0).notnull()).sum()) == 9
    assert ds["L1"].attrs["units"] == "1" and "cycles" in ds["L1"].attrs["long_name"]
    assert ds["P1"].attrs["units"] == "m"
    assert ds["L1_lli"].dtype == np.int8 and ds["L1_ssi"].dtype == np.int8
    assert int(ds["L1_lli"].sel(sv="G02").isel(time=0)) == -1  # absent observation
    assert (ds["epoch_flag"] == 0).all()
    assert ds["rx_clock_offset_s"].isnull().all()


@pytest.mark.shared
def test_grace_a_against_georinex(shared_data, grace_a):
    """Independent reader: georinex must give identical values and the same NaN pattern."""
    georinex = pytest.importorskip("georinex")
    with warnings.catch_warnings():  # georinex warns about xarray merge defaults
        warnings.simplefilter("ignore")
        ref = georinex.load(shared_data / GRACE_A, useindicators=True)
    ref = ref.reindex(sv=grace_a.sv.values)
    np.testing.assert_array_equal(ref.time.values, grace_a.time.values)
    for code in ("L1", "L2", "P1", "P2", "C1"):
        ours, theirs = grace_a[code].values, ref[code].values
        np.testing.assert_array_equal(np.isnan(ours), np.isnan(theirs))
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-6)
        present = ~np.isnan(ours)
        for ind in ("lli", "ssi"):
            if f"{code}{ind}" in ref:  # georinex keeps LLI of phases only (RINEX 2)
                want = np.nan_to_num(ref[f"{code}{ind}"].values[present])
                np.testing.assert_array_equal(grace_a[f"{code}_{ind}"].values[present], want)


@pytest.mark.shared
def test_grace_b_hatanaka_day(shared_data):
    ds = read_rinex_obs(shared_data / GRACE_B)
    assert ds.sizes["time"] == 8640
    assert ds.attrs["rinex_version"] == 2.20
    assert ds.attrs["marker_name"] == "GRACE B"
    assert ds.attrs["obs_types_G"] == "L1 L2 C1 P1 P2 LA SA S1 S2"
    # GRCB2080.10D decompressed, line 21: " 10 07 27 00 00 00.0000000  0  9 11 14 17 19 20 ..."
    # line 22: " 107576007.03748  83825474.87148  20471032.92149  20471033.58948  20471037.27648"
    # line 23: " 107576003.54249       669.00049       290.00048       320.00048"
    g11 = ds.sel(time="2010-07-27T00:00:00", sv="G11")
    expected = {"L1": (107576007.037, 4, 8), "L2": (83825474.871, 4, 8),
                "C1": (20471032.921, 4, 9), "P1": (20471033.589, 4, 8),
                "P2": (20471037.276, 4, 8), "LA": (107576003.542, 4, 9),
                "SA": (669.0, 4, 9), "S1": (290.0, 4, 8), "S2": (320.0, 4, 8)}
    for code, (value, lli, ssi) in expected.items():
        assert g11[code].item() == pytest.approx(value, abs=1e-9)
        assert (g11[f"{code}_lli"].item(), g11[f"{code}_ssi"].item()) == (lli, ssi)
    assert ds["SA"].attrs["units"] == "1"  # RINEX 2 signal strength: receiver units


@pytest.mark.shared
def test_icesat_fragment(shared_data):
    ds = read_rinex_obs(shared_data / ICESAT)
    assert ds.sizes == {"time": 4, "sv": 7}
    assert list(ds.sv.values) == ["G01", "G05", "G09", "G12", "G14", "G22", "G30"]
    assert ds.attrs["marker_type"] == "SPACEBORNE"
    assert ds.attrs["receiver_type"] == "BLACKJACK"
    # ice12720.07o, line 17: "    467614.70106    364374.76806  24554538.88000  24554544.98800 ..."
    # line 18: "    467614.71300        30.00000        40.00000       142.00000"
    g01 = ds.isel(time=0).sel(sv="G01")
    assert g01["L1"].item() == pytest.approx(467614.701, abs=1e-9)
    assert (g01["L1_lli"].item(), g01["L1_ssi"].item()) == (0, 6)
    assert g01["P1"].item() == pytest.approx(24554538.880, abs=1e-9)
    assert g01["SA"].item() == pytest.approx(142.0)
    assert g01["LA"].item() == pytest.approx(467614.713, abs=1e-9)
    # line 19: "  -9534398.75908  -7429403.18808 ..." (G05, negative phase)
    assert ds["L1"].isel(time=0).sel(sv="G05").item() == pytest.approx(-9534398.759, abs=1e-9)
    assert ds.time.values[-1] == np.datetime64("2007-09-29T00:00:30")


@pytest.mark.shared
def test_grace_l1b_rinex(shared_data):
    ds = read_rinex_obs(shared_data / GPS1B)
    # GPS1B_2003-09-14_A_00.rnx, line 21: " 03 09 14 00 00 00.0000000  0 10 01 04 05 07 ..."
    # (satellites without system letter = GPS); line 22: " 108222103.42248  84328941.43848 ..."
    assert ds.sizes["sv"] == 10 and ds.sv.values[0] == "G01"
    first = ds.isel(time=0).sel(sv="G01")
    assert first["L1"].item() == pytest.approx(108222103.422, abs=1e-9)
    assert (first["L1_lli"].item(), first["L1_ssi"].item()) == (4, 8)
    # line 23: " 108222102.91449       629.00049 ..." -> LA, SA
    assert first["SA"].item() == 629.0 and first["SA_ssi"].item() == 9
    assert int(ds["L1"].isel(time=1).notnull().sum()) == 8


@pytest.mark.shared
def test_systems_filter(shared_data):
    ds = read_rinex_obs(shared_data / ICESAT, systems="E")
    assert ds.sizes["sv"] == 0 and ds.sizes["time"] == 4
    with pytest.raises(ValueError, match="unknown satellite systems"):
        read_rinex_obs(shared_data / ICESAT, systems=["X"])


# -------------------------------------------------------------------------------- writer


@pytest.mark.shared
@pytest.mark.parametrize("version,suffix", [(2.11, "07o"), (3.04, "rnx.gz")])
def test_round_trip_grace_a(tmp_path, grace_a, version, suffix):
    out = write_rinex_obs(grace_a, tmp_path / f"graa.{suffix}", version=version,
                          header={"marker_type": "SPACEBORNE", "comments": ["round trip"]})
    back = read_rinex_obs(out)
    names = {"L1": "L1C", "L2": "L2W", "P1": "C1W", "P2": "C2W", "C1": "C1C"}  # RINEX 3.04 5.3
    assert back.attrs["rinex_version"] == version
    np.testing.assert_array_equal(back.time.values, grace_a.time.values)
    np.testing.assert_array_equal(back.sv.values, grace_a.sv.values)
    for code, code3 in names.items():
        name = code if version < 3 else code3
        np.testing.assert_allclose(back[name].values, grace_a[code].values, rtol=0, atol=1e-6)
        for ind in ("lli", "ssi"):
            np.testing.assert_array_equal(back[f"{name}_{ind}"].values,
                                          grace_a[f"{code}_{ind}"].values)


def _synthetic_mixed() -> xr.Dataset:
    """GPS + BDS-3 (B1C/B2a pilot: C1P L1P C5P L5P) observations, 3 decimals exactly."""
    rng = np.random.default_rng(5)
    times = np.datetime64("2023-07-08T00:00:00", "ns") + np.arange(6) * np.timedelta64(30, "s")
    svs = ["C21", "C45", "G03", "G17"]
    ranges = rng.uniform(2.0e7, 4.0e7, (6, 4))
    data = {}
    codes = {"G": ("C1C", "L1C", "C2W", "L2W"), "C": ("C1P", "L1P", "C5P", "L5P")}
    lam = {"1": 0.190293672798, "2": 0.244210213425, "5": 0.254828048791}
    for system, names in codes.items():
        for code in names:
            value = ranges + rng.uniform(-5, 5, ranges.shape) if code[0] == "C" \
                else ranges / lam[code[1]] + 1.0e6
            value = np.round(value, 3)
            value[:, [not sv.startswith(system) for sv in svs]] = np.nan
            data[code] = (("time", "sv"), value)
            lli = np.where(np.isnan(value), -1, 0).astype(np.int8)
            ssi = np.where(np.isnan(value), -1, 7).astype(np.int8)
            if code[0] == "L":
                lli[2, :] = np.where(np.isnan(value[2]), -1, 1)
            data[f"{code}_lli"], data[f"{code}_ssi"] = (("time", "sv"), lli), (("time", "sv"), ssi)
    data["C5P"][1][4, 1] = np.nan  # one missing B2a code observation
    data["C5P_lli"][1][4, 1] = data["C5P_ssi"][1][4, 1] = -1
    data["epoch_flag"] = (("time",), np.array([0, 0, 1, 0, 0, 0], dtype=np.int8))
    data["rx_clock_offset_s"] = (("time",), np.array([1.25e-4, np.nan, 0, 0, 0, -3.5e-7]))
    return xr.Dataset(data, coords={"time": times, "sv": svs},
                      attrs={"time_system": "GPS", "interval_s": 30.0,
                             "obs_types_G": " ".join(codes["G"]),
                             "obs_types_C": " ".join(codes["C"])})


def test_synthetic_gps_bds3_round_trip(tmp_path):
    ds = _synthetic_mixed()
    path = write_rinex_obs(ds, tmp_path / "mixed.rnx", header={"marker_name": "SIM-LEO"})
    text = path.read_text().splitlines()
    assert text[0][40] == "M" and text[0][60:] == "RINEX VERSION / TYPE"
    assert _hl("C    4 C1P L1P C5P L5P", "SYS / # / OBS TYPES") in text
    back = read_rinex_obs(path)
    assert back.attrs["marker_name"] == "SIM-LEO"
    assert back.attrs["obs_types_C"] == "C1P L1P C5P L5P"
    np.testing.assert_array_equal(back.time.values, ds.time.values)
    np.testing.assert_array_equal(back.sv.values, ds.sv.values)
    for name, var in ds.data_vars.items():
        if var.dtype == np.int8:
            np.testing.assert_array_equal(back[name].values, var.values, err_msg=name)
        else:
            np.testing.assert_allclose(back[name].values, var.values, rtol=0, atol=1e-9,
                                       err_msg=name)
    only_c = read_rinex_obs(path, systems=["C"])
    assert list(only_c.sv.values) == ["C21", "C45"]
    assert "C1C" not in only_c and "L5P" in only_c


def test_writer_v2_many_satellites_read_by_georinex(tmp_path):
    """14 satellites and 7 types: both RINEX 2 continuation rules, checked by georinex."""
    georinex = pytest.importorskip("georinex")
    rng = np.random.default_rng(1)
    svs = [f"G{k:02d}" for k in range(1, 15)]
    codes = ("L1", "L2", "C1", "P1", "P2", "S1", "S2")
    times = np.datetime64("2020-01-01T00:00:00", "ns") + np.arange(3) * np.timedelta64(10, "s")
    data = {c: (("time", "sv"), np.round(rng.uniform(1e3, 1e8, (3, 14)), 3)) for c in codes}
    data["P2"][1][1, 3] = np.nan
    ds = xr.Dataset(data, coords={"time": times, "sv": svs})
    path = write_rinex_obs(ds, tmp_path / "many.20o", version=2.11)
    lines = path.read_text().splitlines()
    epoch = next(k for k, line in enumerate(lines) if line.startswith(" 20  1  1"))
    assert lines[epoch + 1].startswith(" " * 32 + "G13G14")
    ours = read_rinex_obs(path)
    with warnings.catch_warnings():  # georinex warns about xarray merge defaults
        warnings.simplefilter("ignore")
        ref = georinex.load(path).reindex(sv=ours.sv.values)
    for code in codes:
        np.testing.assert_allclose(ours[code].values, ds[code].values, rtol=0, atol=1e-9)
        np.testing.assert_allclose(ref[code].values, ds[code].values, rtol=0, atol=1e-9)


@pytest.mark.shared
def test_writer_refusals(tmp_path, shared_data):
    ds = _synthetic_mixed()
    with pytest.raises(ValueError, match="supports systems"):
        write_rinex_obs(ds, tmp_path / "x.11o", version=2.11)
    with pytest.raises(ValueError, match="can write"):
        write_rinex_obs(ds, tmp_path / "x.rnx", version=3.05)
    with pytest.raises(ValueError, match="unknown header keys"):
        write_rinex_obs(ds, tmp_path / "x.rnx", header={"marker": "X"})
    big = ds.copy(deep=True)
    big["L1C"][0, 2] = 1.0e10
    with pytest.raises(ValueError, match="F14.3"):
        write_rinex_obs(big, tmp_path / "x.rnx")
    icesat = read_rinex_obs(shared_data / ICESAT)
    with pytest.raises(ValueError, match="'LA'"):  # RINEX 2.20 LEO type: no RINEX 3 name
        write_rinex_obs(icesat, tmp_path / "x.rnx")
    assert not list(tmp_path.iterdir())  # nothing half-written


# ------------------------------------------------------------ hand-built files with events


def _v2_file(tmp_path: Path) -> Path:
    """RINEX 2.11 file with flags 0, 4 (new obs types), 1, 6, 5 and a receiver clock."""
    head = [_hl("     2.11           OBSERVATION DATA    G (GPS)", "RINEX VERSION / TYPE"),
            _hl("SIM", "MARKER NAME"),
            _hl("     2    C1    L1", "# / TYPES OF OBSERV"),
            _hl("  2007     3    21     0     0    0.0000000     GPS", "TIME OF FIRST OBS"),
            _hl("", "END OF HEADER")]
    body = [" 07  3 21  0  0  0.0000000  0  2G01G05".ljust(68) + f"{1.23456e-4:12.9f}",
            _obs(23910130.015, "0", "7") + _obs(125648581.665, "1", "6"),
            _obs(22981850.195) + _obs(None),
            "                            4  2",
            _hl("     3    C1    L1    S1", "# / TYPES OF OBSERV"),
            _hl("observation types change here", "COMMENT"),
            " 07  3 21  0  0 10.0000000  1  1G01",
            _obs(23911192.190) + _obs(125654165.483, " ", "5") + _obs(45.0),
            " 07  3 21  0  0 20.0000000  6  1G01",
            _obs(0.0) + _obs(1.0) + _obs(0.0),
            " 07  3 21  0  0 25.0000000  5  0",
            " 07  3 21  0  0 30.0000000  0  1  1",
            _obs(23912192.190) + _obs(125659165.483) + _obs(46.0)]
    path = tmp_path / "events.07o"
    path.write_text("\n".join(head + body) + "\n")
    return path


def _v3_file(tmp_path: Path, version: str = "3.04") -> Path:
    """RINEX 3/4 mixed file with a flag-4 redefinition of the BDS observation types."""
    head = [_hl(f"{version:>9}           OBSERVATION DATA    M", "RINEX VERSION / TYPE"),
            _hl("G    2 C1C L1C", "SYS / # / OBS TYPES"),
            _hl("C    2 C1P L1P", "SYS / # / OBS TYPES"),
            _hl("  2023     1     1     0     0    0.0000000     GPS", "TIME OF FIRST OBS"),
            _hl("", "END OF HEADER")]
    body = ["> 2023 01 01 00 00  0.0000000  0  2" + " " * 6 + f"{1.23456e-7:15.12f}",
            "G01" + _obs(23910130.015, " ", "7") + _obs(125648581.665, "1", "6"),
            "C30" + _obs(40000000.123) + _obs(210000000.456, " ", "9"),
            ">                              4  1",
            _hl("C    2 C1P C5P", "SYS / # / OBS TYPES"),
            "> 2023 01 01 00 00 30.0000000  0  2",
            "G01" + _obs(23910130.515) + _obs(125648584.165),
            "C30" + _obs(40000001.123) + _obs(40000002.5)]
    path = tmp_path / "events.rnx"
    path.write_text("\n".join(head + body) + "\n")
    return path


def test_v2_events_and_flags(tmp_path):
    ds = read_rinex_obs(_v2_file(tmp_path))
    np.testing.assert_array_equal(ds.time.values, np.array(
        ["2007-03-21T00:00:00", "2007-03-21T00:00:10", "2007-03-21T00:00:30"],
        dtype="datetime64[ns]"))
    assert list(ds["epoch_flag"].values) == [0, 1, 0]
    assert ds.attrs["n_events"] == 2 and ds.attrs["n_cycle_slip_epochs"] == 1
    assert ds["rx_clock_offset_s"].values[0] == pytest.approx(1.23456e-4, abs=1e-15)
    assert np.isnan(ds["rx_clock_offset_s"].values[1])
    assert ds["L1"].sel(sv="G01").values == pytest.approx([125648581.665, 125654165.483,
                                                           125659165.483])
    assert list(ds["L1_lli"].sel(sv="G01").values) == [1, 0, 0]
    assert list(ds["L1_ssi"].sel(sv="G01").values) == [6, 5, 0]
    assert list(ds["C1_lli"].sel(sv="G05").values) == [0, -1, -1]
    assert np.isnan(ds["L1"].sel(sv="G05").values).all()
    assert np.isnan(ds["S1"].values[0]).all() and ds["S1"].values[1, 0] == 45.0


@pytest.mark.parametrize("version", ["3.02", "3.04", "3.05", "4.00"])
def test_v3_events_and_type_change(tmp_path, version):
    ds = read_rinex_obs(_v3_file(tmp_path, version))
    assert ds.attrs["rinex_version"] == float(version)
    assert ds.sizes == {"time": 2, "sv": 2}
    assert ds.attrs["n_events"] == 1
    assert ds["rx_clock_offset_s"].values[0] == pytest.approx(1.23456e-7, abs=1e-18)
    assert ds["L1P"].sel(sv="C30").values[0] == pytest.approx(210000000.456)
    assert np.isnan(ds["L1P"].sel(sv="C30").values[1])
    assert ds["C5P"].sel(sv="C30").values[1] == pytest.approx(40000002.5)
    assert (ds["L1P_ssi"].sel(sv="C30").values[0], ds["L1C_lli"].sel(sv="G01").values[0]) \
        == (9, 1)
    assert np.isnan(ds["L1P"].sel(sv="G01")).all()
    assert ds["C1C"].attrs["units"] == "m"


# ----------------------------------------------------------------------------- broken copies


def _write_lines(tmp_path: Path, name: str, lines: list[str]) -> Path:
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.shared
def test_truncated_mid_epoch(tmp_path, shared_data):
    lines = (shared_data / ICESAT).read_text().splitlines()
    # ice12720.07o: the epoch of line 16 announces 7 satellites (2 lines each, lines 17-30)
    path = _write_lines(tmp_path, "trunc.07o", lines[:25])
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 16, "epoch record")
    assert "ends after line 25" in str(exc.value)


def test_truncated_v3(tmp_path):
    lines = _v3_file(tmp_path).read_text().splitlines()
    path = _write_lines(tmp_path, "trunc.rnx", lines[:-1])
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, len(lines) - 2, "epoch record")


@pytest.mark.shared
@pytest.mark.parametrize("label", ["END OF HEADER", "# / TYPES OF OBSERV"])
def test_missing_header_record(tmp_path, shared_data, label):
    lines = [ln for ln in (shared_data / ICESAT).read_text().splitlines() if label not in ln]
    path = _write_lines(tmp_path, "nohead.07o", lines)
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, None, label)


def test_missing_v3_types_and_not_obs(tmp_path):
    lines = _v3_file(tmp_path).read_text().splitlines()
    path = _write_lines(tmp_path, "a.rnx", [ln for ln in lines if "OBS TYPES" not in ln[60:]])
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, None, "SYS / # / OBS TYPES")
    nav = [lines[0][:20] + "N: GNSS NAV DATA    " + lines[0][40:]] + lines[1:]
    path = _write_lines(tmp_path, "b.rnx", nav)
    with pytest.raises(FormatError, match="not an observation file") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 1, "RINEX VERSION / TYPE")
    path = _write_lines(tmp_path, "c.rnx", lines[1:])
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 1, "RINEX VERSION / TYPE")


@pytest.mark.shared
@pytest.mark.parametrize("bad,message", [("2298185x.210", "is not a number"),
                                         ("         nan", "is not a finite number"),
                                         ("  1_000.000 ", "is not a number"),
                                         ("229 8185.210", "is not a number")])
def test_bad_observation_field(tmp_path, grace_a_lines, bad, message):
    lines = list(grace_a_lines)
    # graa0800.07o line 26 (G05, first epoch): P2 is the 4th field, columns 49-62
    assert lines[25][48:62] == "  22981857.210"
    lines[25] = lines[25][:48] + f"{bad:>14}" + lines[25][62:]
    path = _write_lines(tmp_path, "bad.07o", lines)
    with pytest.raises(FormatError, match=message) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 26, "P2")
    assert "G05" in str(exc.value)


@pytest.mark.shared
def test_bad_indicator(tmp_path, grace_a_lines):
    lines = list(grace_a_lines)
    lines[24] = lines[24][:30] + "x" + lines[24][31:]  # L2 LLI of G01, line 25
    path = _write_lines(tmp_path, "ind.07o", lines[:33])  # header + first epoch
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 25, "L2 LLI")


@pytest.mark.shared
@pytest.mark.parametrize("column,text,field", [(4, "13", "month"), (7, "3x", "day"),
                                               (7, "30", "day"),  # 2007-03-30 is fine
                                               (28, "9", "epoch flag"),
                                               (29, " 10", "number of satellites"),
                                               (29, "  8", "number of satellites")])
def test_bad_epoch_record(tmp_path, grace_a_lines, column, text, field):
    lines = list(grace_a_lines[:43])  # header and the first two epochs
    lines[23] = lines[23][:column] + text + lines[23][column + len(text):]
    path = _write_lines(tmp_path, "epoch.07o", lines)
    if text == "30":
        assert read_rinex_obs(path).time.values[0] == np.datetime64("2007-03-30")
        lines[23] = lines[23][:4] + " 2" + lines[23][6:]  # 2007-02-30 is not a date
        path = _write_lines(tmp_path, "epoch.07o", lines)
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 24, field)


def test_v3_satellite_count_and_duplicates(tmp_path):
    lines = _v3_file(tmp_path).read_text().splitlines()
    more = list(lines)
    more[5] = more[5][:32] + "  3" + more[5][35:]  # announces 3, two records follow
    path = _write_lines(tmp_path, "count.rnx", more)
    with pytest.raises(FormatError, match="announces 3 satellites but only 2") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 9, "number of satellites")
    dup = list(lines)
    dup[7] = "G01" + dup[7][3:]
    path = _write_lines(tmp_path, "dup.rnx", dup)
    with pytest.raises(FormatError, match="twice") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 8, "satellite")
    bad = list(lines)
    bad[11] = "X30" + bad[11][3:]
    path = _write_lines(tmp_path, "sat.rnx", bad)
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 12, "satellite")


@pytest.mark.parametrize("flag", ["0", "4"])
def test_v3_negative_satellite_count_is_an_error_not_a_hang(tmp_path, flag):
    """Issue 24: an epoch record (or event, flag 4) announcing -1 satellites made the scanner
    stand still; the count (RINEX 3.04 Table A3, I3) must be >= 0."""
    lines = _v3_file(tmp_path).read_text().splitlines()
    lines[5] = lines[5][:31] + flag + " -1" + lines[5][35:]
    path = _write_lines(tmp_path, "neg.rnx", lines)
    with pytest.raises(FormatError, match="negative") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 6, "number of satellites")


@pytest.mark.shared
def test_v2_negative_satellite_count_is_an_error_not_a_hang(tmp_path, grace_a_lines):
    lines = list(grace_a_lines[:43])
    lines[23] = lines[23][:28] + "4 -1" + lines[23][32:]
    path = _write_lines(tmp_path, "neg.07o", lines)
    with pytest.raises(FormatError, match="negative") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 24, "number of satellites")


@pytest.mark.shared
def test_rinex2_time_system_field(tmp_path, grace_a, grace_a_lines):
    """RINEX 2.11 Table A1: TIME OF FIRST OBS time system (A3, columns 49-51); GPS when blank
    in a GPS file; an identifier outside GPS/GLO/GAL (and the RINEX 3 ones) is refused."""
    assert grace_a.attrs["time_system"] == "GPS"
    k = next(i for i, x in enumerate(grace_a_lines) if x[60:].strip() == "TIME OF FIRST OBS")
    lines = list(grace_a_lines[:43])
    lines[k] = lines[k][:48] + "ABC" + lines[k][51:]
    path = _write_lines(tmp_path, "tsys.07o", lines)
    with pytest.raises(FormatError, match="'ABC' is not a RINEX time system") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, k + 1, "TIME OF FIRST OBS time system")


@pytest.mark.parametrize("year", ["3000", "1600"])
def test_v3_year_outside_datetime64_range_is_an_error(tmp_path, year):
    """Issue 24: a year outside datetime64[ns] wrapped silently; the contract's years are
    1900-2199 (leopod.io._fields.YEARS)."""
    lines = _v3_file(tmp_path).read_text().splitlines()
    lines[5] = lines[5][:2] + year + lines[5][6:]
    path = _write_lines(tmp_path, "year.rnx", lines)
    with pytest.raises(FormatError, match="outside 1900-2199") as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, 6, "year")


def test_damaged_gzip_stream_is_a_format_error(tmp_path):
    """Issue 24: a corrupt deflate stream raised zlib.error instead of FormatError."""
    data = bytearray(gzip.compress(_v3_file(tmp_path).read_bytes()))
    data[12:20] = b"\xff" * 8  # inside the deflate data, after the 10-byte gzip header
    path = tmp_path / "bad.rnx.gz"
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError) as exc:
        read_rinex_obs(path)
    _assert_error(exc, path, None, "gzip")


@pytest.mark.parametrize("name, system, expected", [
    ("default_time_system2.10o", "R", "GLO"),   # RINEX 2.11 GLONASS file, field blank
    ("default_time_system3.10o", "E", "GAL")])  # RINEX 3.01 Galileo file, field blank
def test_blank_time_system_defaults_to_the_systems_own(shared, name, system, expected):
    """RINEX 2.11 Table A1 / 3.04 Table A2: in a single-system file a blank time system is
    that system's time (georinex fixtures, ../shared/peer_fixtures/MANIFEST.md)."""
    ds = read_rinex_obs(shared / "peer_fixtures" / "valid" / "obs" / name)
    assert ds.attrs["file_system"] == system
    assert ds.attrs["time_system"] == expected and ds.attrs["time_system_line"] == 0
