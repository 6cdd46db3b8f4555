"""Ingest of RINEX observations (leopod.ingest.canonical_observations): time systems and BDS
GEO exclusion.

Authorities: RINEX 3.04 Table A2 (TIME OF FIRST OBS: time system in columns 49-51,
compulsory in mixed files, default the system's own time in single-system files: BDT for
BDS); BDT = GPST - 14 s exactly (BDS-SIS-ICD-B1I-3.0 and IS-GPS-200, see
tests/time/test_scales.py); BDS GEO PRNs 1-5 and 59-63 (BDS-SIS-ICD-B1I-3.0, D2 message).
The real file is the georust/rinex fixture ALAC00ESP 2022-009 (RINEX 3.04, mixed, GPS time;
../shared/peer_fixtures/MANIFEST.md), which holds the BDS GEO C05 and the IGSO C06.
"""

from __future__ import annotations

import datetime as dt
from pathlib import Path

import numpy as np
import pytest

from leopod.ingest import canonical_observations
from leopod.io._text import FormatError
from leopod.io.rinex_obs import read_rinex_obs
from leopod.signals import GEO_SATELLITES, SystemSignals, is_geo

ALAC = "peer_fixtures/valid/obs/ALAC00ESP_R_20220090000_01D_30S_MO.rnx"
FIRST_OBS_LINE = 25  # "  2022     1     9     0     0    0.0000000     GPS         TIME OF FIRST OBS"
BDT_MINUS_GPST = dt.timedelta(seconds=-14)
BDS = SystemSignals.from_config({"phase": ["L2I", "L6I"], "code": ["C2I", "C6I"],
                                 "pod_code": ["C2I", "C6I"]})
GPS = SystemSignals.from_config({"phase": ["L1C", "L2W"], "code": ["C1C", "C2W"],
                                 "pod_code": ["C1C", "C2W"]})


@pytest.fixture(scope="module")
def alac_lines(shared) -> list[str]:
    return (shared / ALAC).read_text(encoding="latin-1").splitlines()


def _shift_epoch(line: str, delta: dt.timedelta) -> str:
    """A RINEX 3 epoch record ('> yyyy mm dd hh mm ss.sssssss ...') moved by ``delta``."""
    t = dt.datetime(*(int(line[a:b]) for a, b in ((2, 6), (7, 9), (10, 12), (13, 15),
                                                   (16, 18))))
    t += dt.timedelta(microseconds=round(float(line[18:29]) * 1e6)) + delta
    sec = t.second + t.microsecond * 1e-6
    return f"> {t:%Y %m %d %H %M}{sec:11.7f}" + line[29:]


def _retag(lines: list[str], code: str, delta: dt.timedelta) -> list[str]:
    """The file with ``code`` in the TIME OF FIRST OBS time-system field and every epoch
    record (and the TIME OF FIRST/LAST OBS dates) moved by ``delta``."""
    out = []
    for line in lines:
        label = line[60:].strip()
        if line.startswith(">"):
            line = _shift_epoch(line, delta)
        elif label in ("TIME OF FIRST OBS", "TIME OF LAST OBS"):
            moved = _shift_epoch("> " + " ".join(f"{int(x):02d}" for x in line[:30].split())
                                 + f"{float(line[30:43]):11.7f}", delta)
            y, mo, d, h, mi = (int(x) for x in moved[2:18].split())
            line = (f"{y:6d}{mo:6d}{d:6d}{h:6d}{mi:6d}{float(moved[18:29]):13.7f}     "
                    f"{code:<3s}".ljust(60) + line[60:])
        out.append(line)
    return out


def _bds_only(lines: list[str]) -> list[str]:
    """A BDS-only file ('C' in RINEX VERSION / TYPE) from a mixed one: other systems' type
    records and satellite records dropped, epoch counts rewritten."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        if i == 0:
            out.append(line[:40] + "C: BDS".ljust(20) + line[60:])
        elif line[60:].strip() == "SYS / # / OBS TYPES" and line[0] != "C":
            pass
        elif line.startswith(">"):
            count = int(line[32:35])
            recs = [r for r in lines[i + 1:i + 1 + count] if r.startswith("C")]
            out.append(line[:32] + f"{len(recs):3d}" + line[35:])
            out.extend(recs)
            i += count
        else:
            out.append(line)
        i += 1
    return out


def _write(tmp_path: Path, name: str, lines: list[str]) -> Path:
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")
    return path


# ---------------------------------------------------------------------------- time systems
def test_bdt_tagged_file_ingests_to_the_gps_epochs_within_1us(shared, alac_lines, tmp_path):
    """Done-when of issue 20: the same observations written with a BDT header and epochs
    14 s earlier ingest to the GPST epochs of the original to better than 1 microsecond."""
    cfg = {"G": GPS, "C": BDS}
    gps = canonical_observations(read_rinex_obs(shared / ALAC), cfg)
    path = _write(tmp_path, "alac_bdt.rnx", _retag(alac_lines, "BDT", BDT_MINUS_GPST))
    raw = read_rinex_obs(path)
    assert raw.attrs["time_system"] == "BDT" and raw.attrs["time_system_line"] == FIRST_OBS_LINE
    # the reader keeps the labels as written: 14 s before GPST (the test can fail)
    lag = (gps.time.values[0] - raw.time.values[0]).astype("timedelta64[ns]").astype(np.int64)
    assert lag == 14_000_000_000
    bdt = canonical_observations(raw, cfg)
    err_ns = np.abs((bdt.time.values - gps.time.values).astype(np.int64))
    assert bdt.sizes["time"] == gps.sizes["time"] == 3 and err_ns.max() < 1_000
    assert bdt.attrs["time_system"] == "GPS" and bdt.attrs["time_system_file"] == "BDT"
    np.testing.assert_array_equal(bdt.C2I.values, gps.C2I.values)
    assert gps.attrs["time_system_file"] == "GPS"


def test_bds_only_file_with_blank_time_system_is_bdt(shared, alac_lines, tmp_path):
    """RINEX 3.04 Table A2: in a pure BDS file a blank time-system field means BDT."""
    cfg = {"C": BDS}
    gps = canonical_observations(read_rinex_obs(shared / ALAC), cfg)
    lines = _bds_only(_retag(alac_lines, "", BDT_MINUS_GPST))
    first_obs = next(x for x in lines if x[60:].strip() == "TIME OF FIRST OBS")
    assert first_obs[48:51] == "   " and first_obs.startswith("  2022     1     8    23    59")
    raw = read_rinex_obs(_write(tmp_path, "alac_c.rnx", lines))
    assert raw.attrs["file_system"] == "C" and {s[0] for s in raw.sv.values} == {"C"}
    assert raw.attrs["time_system"] == "BDT" and raw.attrs["time_system_line"] == 0
    bdt = canonical_observations(raw, cfg)
    err_ns = np.abs((bdt.time.values - gps.time.values).astype(np.int64))
    assert err_ns.max() < 1_000
    np.testing.assert_array_equal(bdt.L2I.values, gps.L2I.values)


def test_galileo_time_is_gps_time(shared, alac_lines, tmp_path):
    """GST labels equal GPST labels (Galileo OS SIS ICD 2.0): a GAL tag changes nothing."""
    cfg = {"G": GPS}
    gps = canonical_observations(read_rinex_obs(shared / ALAC), cfg)
    gal = canonical_observations(read_rinex_obs(_write(
        tmp_path, "alac_gal.rnx", _retag(alac_lines, "GAL", dt.timedelta(0)))), cfg)
    np.testing.assert_array_equal(gal.time.values, gps.time.values)
    assert gal.attrs["time_system_file"] == "GAL"


def test_glonass_time_is_refused_naming_file_line_and_field(alac_lines, tmp_path):
    """GLONASS time is UTC(SU) + 3 h (RINEX 3.04 sec. 3.1): leopod does not ingest it."""
    path = _write(tmp_path, "alac_glo.rnx", _retag(alac_lines, "GLO", dt.timedelta(0)))
    raw = read_rinex_obs(path)  # a legal file: the reader reads it
    with pytest.raises(ValueError) as err:
        canonical_observations(raw, {"G": GPS})
    text = str(err.value)
    assert f"alac_glo.rnx:{FIRST_OBS_LINE}" in text and "TIME OF FIRST OBS" in text
    assert "GLONASS" in text


def test_unknown_time_system_is_a_format_error(alac_lines, tmp_path):
    path = _write(tmp_path, "alac_xyz.rnx", _retag(alac_lines, "XYZ", dt.timedelta(0)))
    with pytest.raises(FormatError) as err:
        read_rinex_obs(path)
    assert err.value.line == FIRST_OBS_LINE
    assert err.value.field == "TIME OF FIRST OBS time system"
    assert "alac_xyz.rnx" in str(err.value) and "'XYZ'" in str(err.value)


# --------------------------------------------------------------------------- BDS GEO
def test_geo_list_is_the_bds_geo_prns():
    """BDS-SIS-ICD-B1I-3.0: PRN 1-5 and 59-63 are the GEO satellites (D2 message)."""
    assert GEO_SATELLITES["C"] == {f"C{p:02d}" for p in (1, 2, 3, 4, 5, 59, 60, 61, 62, 63)}
    assert all(is_geo(s) for s in ("C01", "C05", "C59", "C63"))
    assert not any(is_geo(s) for s in ("C06", "C58", "C64", "G01", "E05"))


@pytest.mark.parametrize("exclude", [True, False])
def test_exclude_geo_drops_c05_only(shared, exclude):
    """ALAC 2022-009 tracks the GEO C05 and the IGSO C06: ``exclude_geo`` drops C05 only."""
    cfg = {"G": GPS, "C": SystemSignals.from_config({**BDS.__dict__, "exclude_geo": exclude})}
    obs = canonical_observations(read_rinex_obs(shared / ALAC), cfg)
    svs = set(obs.sv.values.tolist())
    assert ("C05" in svs) is not exclude
    assert {"C06", "C09", "G01"} <= svs
    assert obs.attrs["excluded_geo"] == ("C05" if exclude else "")


def test_exclude_geo_is_a_schema_default():
    """The schema is the source of the default: GEO satellites are kept unless asked."""
    assert BDS.exclude_geo is False
