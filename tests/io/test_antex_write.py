"""Round trip of leopod.io.antex_write through leopod.io.antex.read_antex.

Authority: the ANTEX 1.4 format description (Rothacher and Schmid 2010) as the reader
implements it, and the real AIUB file ../shared/data/antex/GOCE_MAIN_0001.ATX (Jäggi et al.
2009): written back, it is read with the same PCO and PCV to the file's 0.01 mm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from leopod.io.antex import AntennaPattern, read_antex
from leopod.io.antex_write import antex_lines, write_antex

GOCE = Path(__file__).resolve().parents[3] / "shared" / "data" / "antex" / "GOCE_MAIN_0001.ATX"


def _pattern(dazi: float = 30.0) -> AntennaPattern:
    zen = np.arange(0.0, 91.0, 10.0)
    az = np.arange(0.0, 360.0 + dazi / 2, dazi)
    rng = np.random.default_rng(1)
    grid = {f: np.round(rng.normal(0, 0.01, (az.size, zen.size)), 5) for f in ("G01", "G02")}
    for g in grid.values():
        g[-1] = g[0]
    return AntennaPattern(
        kind="receiver", antenna_type="LEOPOD PCV", serial="", svn="", cospar_id="",
        valid_from=np.datetime64("NaT", "ns"), valid_until=np.datetime64("NaT", "ns"),
        zenith_deg=zen, dazi_deg=dazi, frequencies=("G01", "G02"),
        pco={"G01": np.array([0.001, -0.002, 0.1234]), "G02": np.array([0.0, 0.0, 0.11])},
        noazi={f: g[:-1].mean(axis=0) for f, g in grid.items()}, grid=grid, meta={})


def test_written_pattern_reads_back_to_the_format_resolution(tmp_path):
    p = _pattern()
    path = write_antex(tmp_path / "x.atx", [p], comments=["a test pattern"])
    back = read_antex(path).receiver("LEOPOD PCV")
    assert back.frequencies == p.frequencies and back.dazi_deg == p.dazi_deg
    np.testing.assert_allclose(back.zenith_deg, p.zenith_deg)
    for f in p.frequencies:
        np.testing.assert_allclose(back.pco_m(f), p.pco[f], atol=5e-6)
        np.testing.assert_allclose(back.grid[f], p.grid[f], atol=5e-6)
        np.testing.assert_allclose(back.noazi[f], p.noazi[f], atol=5e-6)
    assert back.meta["antex_version"] == 1.4


def test_records_have_their_labels_in_columns_61_to_80():
    lines = antex_lines([_pattern(90.0)])
    labelled = [ln for ln in lines if not ln.startswith("   NOAZI") and ln[:8].strip()
                .replace(".", "").isdigit() is False]
    assert all(len(ln) <= 80 and ln[60:].strip() for ln in labelled)
    assert lines[0][60:] == "ANTEX VERSION / SYST" and lines[-1][60:] == "END OF ANTENNA"
    assert sum(ln.startswith("   NOAZI") for ln in lines) == 2
    assert sum(ln[60:] == "START OF FREQUENCY" for ln in lines) == 2


def test_values_beyond_the_field_are_refused(tmp_path):
    p = _pattern()
    p.grid["G01"][0, 0] = 20.0          # 20 m does not fit F8.2 mm
    with pytest.raises(ValueError, match="G01 PCV grid"):
        write_antex(tmp_path / "x.atx", [p])


@pytest.mark.skipif(not GOCE.exists(), reason="needs ../shared/data/antex")
def test_real_goce_pattern_round_trip(tmp_path):
    goce = read_antex(GOCE).receiver("GOCE")
    back = read_antex(write_antex(tmp_path / "goce.atx", [goce])).receiver("GOCE")
    for f in goce.frequencies:
        np.testing.assert_allclose(back.pco_m(f), goce.pco_m(f), atol=5e-6)
        np.testing.assert_allclose(back.grid[f], goce.grid[f], atol=5e-6)
