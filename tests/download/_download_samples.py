"""Real product files of ../shared/data and corrupted variants of them, for the download tests."""

from __future__ import annotations

import gzip
from pathlib import Path

import unlzw3

# The complete real day (GRACE-A 2007-03-21 = 2007-080, GPS week 1419 day 3) and the WHU
# product set of 2008-10-05 (2008-279, week 1500 day 0): ../shared/data/MANIFEST.md.
GRACE_A_DAY = "2007-080"
WHU_DAY = "2008-279"
COD_SP3_GZ = "grace-a_2007-080/cod14193.sp3.gz"
COD_CLK_GZ = "grace-a_2007-080/cod14193.clk.gz"
WHU_CLK_Z = "products_2008-279_whu/whp15000.clk.Z"
WHU_BIA_Z = "products_2008-279_whu/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z"
GRACE_B_CRX = "grace-b_2010-208/GRCB2080.10D"
GRACE_B_DAY = "2010-208"

HTML_PAGE = (b"<!DOCTYPE html>\n<html><head><title>Earthdata Login</title></head>\n"
             b"<body>Please log in</body></html>\n")


def plain(path: Path) -> bytes:
    """Decompressed content of a .gz or .Z file (gzip module / unlzw3, independent of leopod)."""
    raw = path.read_bytes()
    if path.name.endswith(".gz"):
        return gzip.decompress(raw)
    if path.name.endswith(".Z"):
        return unlzw3.unlzw(raw)
    return raw


def bias_with_nan(shared_data: Path) -> tuple[bytes, int]:
    """The WHU Bias-SINEX text with the first estimated value replaced by 'nan' (the
    PRIDE-PPPAR#56 failure), and the 1-based line number of that record."""
    lines = plain(shared_data / WHU_BIA_Z).decode("latin-1").splitlines(keepends=True)
    k = next(i for i, ln in enumerate(lines) if ln.startswith(" OSB "))
    line = lines[k]
    lines[k] = line[:70] + "nan".rjust(21) + line[91:]
    return "".join(lines).encode("latin-1"), k + 1


def sp3_first_hours(shared_data: Path, hours: int) -> bytes:
    """The CODE SP3 of 2007-080 keeping only the epochs of the first ``hours`` hours (header
    epoch count adjusted, EOF kept): a well-formed file that does not cover the day."""
    lines = plain(shared_data / COD_SP3_GZ).decode("latin-1").splitlines(keepends=True)
    out, epochs = [], 0
    keep = True
    for line in lines:
        if line.startswith("*"):
            keep = int(line[14:16]) < hours
            epochs += keep
        if line.startswith("EOF"):
            keep = True
        if keep:
            out.append(line)
    first = out[0]
    out[0] = first[:32] + f"{epochs:7d}" + first[39:]
    return "".join(out).encode("latin-1")
