"""Write station eccentricities as a SINEX SITE/ECCENTRICITY file (ILRS ``ecc_xyz.snx`` layout).

The output is read back by :func:`leopod.io.sinex.read_sinex_eccentricities`: a ``%=SNX 2.02``
header, the SITE/ECCENTRICITY block in the fixed columns of SINEX 2.02 (site code, point code,
solution, observation technique, validity interval, reference system ``UNE`` or ``XYZ``, three
components [m] in slots of 9 characters (a blank and F8.4 below 1 km; larger values take the
whole slot with fewer decimals, as the ILRS file does), and the ILRS CDP system-occupation
designator after column 80 when given) and ``%ENDSNX``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text
from leopod.io.sinex import _sinex_epoch

__all__ = ["write_sinex_eccentricities"]

_SLOT = 9
"""Characters per eccentricity component (SINEX 2.02 SITE/ECCENTRICITY: 1X, F8.4)."""
_MAX_ECC_M = 1e5


def _component(value: float) -> str:
    """The value in a 9-character slot with as many decimals (<= 4) as fit."""
    for decimals in range(4, -1, -1):
        text = f"{value:{_SLOT}.{decimals}f}"
        if len(text) <= _SLOT:
            return text
    raise ValueError(f"eccentricity {value} m does not fit the SINEX field")


def write_sinex_eccentricities(ds: xr.Dataset, path: str | Path, *, agency: str = "LEO",
                               technique: str = "L") -> None:
    """Write eccentricities in the schema of :func:`leopod.io.sinex.read_sinex_eccentricities`.

    Parameters
    ----------
    ds : xarray.Dataset
        Dimension ``record`` with ``site``, ``ref_system`` ("UNE" or "XYZ") and ``ecc_m``
        (record, component) [m]; optional ``pt`` ("A"), ``soln`` (1), ``valid_from``,
        ``valid_to`` (open), ``cdp_sod`` ("").
    path : str or Path
        Output file.
    agency : str
        3-character agency code of the header line.
    technique : str
        Observation technique code ("L" SLR).

    Raises
    ------
    ValueError
        Missing variable, no record, non-finite or too large (>= 100 km) eccentricity,
        unknown reference system, site code longer than 4 characters.
    """
    for name in ("site", "ref_system", "ecc_m"):
        if name not in ds.variables:
            raise ValueError(f"write_sinex_eccentricities needs the variable '{name}'")
    n = ds.sizes.get("record", 0)
    if n == 0:
        raise ValueError("write_sinex_eccentricities: no record to write")

    def get(name, default):
        return np.asarray(ds[name].values) if name in ds.variables else np.full(n, default)

    site = get("site", "").astype(str)
    system = get("ref_system", "").astype(str)
    ecc = np.asarray(ds["ecc_m"].values, dtype=float).reshape(n, 3)
    start = get("valid_from", np.datetime64("NaT")).astype("datetime64[ns]")
    end = get("valid_to", np.datetime64("NaT")).astype("datetime64[ns]")
    if not (np.isfinite(ecc).all() and np.all(np.abs(ecc) < _MAX_ECC_M)):
        raise ValueError("write_sinex_eccentricities: ecc_m must be finite and below 100 km")
    bad = [s for s in system if s not in ("UNE", "XYZ")]
    if bad:
        raise ValueError(f"write_sinex_eccentricities: reference system '{bad[0]}' is neither "
                         "UNE nor XYZ")
    bad = [s for s in site if not s or len(s) > 4 or " " in s]
    if bad:
        raise ValueError(f"write_sinex_eccentricities: site code '{bad[0]}' is not 1-4 "
                         "characters")
    lines = [f" {s:>4s} {p:>2s} {k:4d} {technique:1.1s} {_sinex_epoch(a)} {_sinex_epoch(b)} "
             f"{sys}" + "".join(_component(v) for v in e) + (f"        {sod}" if sod else "")
             for s, p, k, a, b, sys, e, sod in zip(
                 site, get("pt", "A").astype(str), get("soln", 1).astype(int), start, end,
                 system, ecc, get("cdp_sod", "").astype(str))]
    known = np.concatenate([start[~np.isnat(start)], end[~np.isnat(end)]])
    first = known.min() if known.size else np.datetime64("NaT")
    last = known.max() if known.size else np.datetime64("NaT")
    head = (f"%=SNX 2.02 {agency:<3.3s} {_sinex_epoch(first)} {agency:<3.3s} "
            f"{_sinex_epoch(first)} {_sinex_epoch(last)} {technique:1.1s} {n:05d} 0 X")
    out = [head, "+SITE/ECCENTRICITY",
           "*SITE PT SOLN T DATA_START__ DATA_END____ AXE MARKER->REFERENCE POINT (M)",
           *lines, "-SITE/ECCENTRICITY", "%ENDSNX"]
    write_text(path, "\n".join(out) + "\n")
