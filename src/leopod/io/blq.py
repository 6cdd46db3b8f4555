"""Ocean tide loading coefficients in the BLQ format (Onsala Space Observatory loading service).

A BLQ file lists, per station, a name line and six lines of eleven numbers (constituents M2,
S2, N2, K2, K1, O1, P1, Q1, Mf, Mm, Ssa, in this order): three lines of amplitudes [m] of
the displacement components up (radial), west and south, then three lines of their Greenwich
phase lags [deg] in the same order. Lines starting with ``$$`` are comments. Format as
described by the IERS Conventions (2010), sec. 7.1.2, and the header of the files of the
loading service (H.-G. Scherneck, http://holt.oso.chalmers.se/loading/).

Dataset returned by :func:`read_blq`: dimensions ``site`` (file order), ``component``
(``up``, ``west``, ``south``) and ``constituent`` (:data:`BLQ_CONSTITUENTS`); variables
``amplitude_m`` and ``phase_deg`` (site, component, constituent). Site names are the first
blank-separated word of the name line, upper-case (e.g. ``"ONSA"``, ``"7090"``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import is_number, require_line_end
from leopod.io._text import FormatError, parse_float, read_lines

__all__ = ["BLQ_COMPONENTS", "BLQ_CONSTITUENTS", "read_blq"]

#: Constituents of a BLQ block, in file order.
BLQ_CONSTITUENTS = ("M2", "S2", "N2", "K2", "K1", "O1", "P1", "Q1", "MF", "MM", "SSA")
#: Displacement components of the three amplitude (and phase) lines, in file order.
BLQ_COMPONENTS = ("up", "west", "south")
_LINES_PER_SITE = 6
#: Physical range of the six lines (io._fields.RANGES): amplitudes [m], phase lags [deg].
_KINDS = ("loading_amplitude_m",) * 3 + ("phase_deg",) * 3


def _is_table_line(tokens: list[str]) -> bool:
    """True for a line of eleven numbers (a station name line never is one)."""
    return len(tokens) == len(BLQ_CONSTITUENTS) and all(is_number(t) for t in tokens)


def read_blq(path: str | Path) -> xr.Dataset:
    """Read the ocean loading coefficients of a BLQ file.

    Parameters
    ----------
    path : str or Path
        BLQ file (may be compressed).

    Returns
    -------
    xarray.Dataset
        Schema in the module docstring.

    Raises
    ------
    FormatError
        A station block with fewer than six lines or a line without eleven numbers, numbers
        where a station name is expected, a site given twice, or no station at all.
    """
    path = Path(path)
    lines = read_lines(path)
    require_line_end(lines, path)
    rows = [(ln, text.split()) for ln, text in enumerate(lines, start=1)
            if text.strip() and not text.lstrip().startswith("$$")]
    sites, values = [], []
    k = 0
    while k < len(rows):
        ln, tokens = rows[k]
        if _is_table_line(tokens):
            raise FormatError(path, ln, "station name", "numbers before any station name line")
        name = tokens[0].upper()
        if name in sites:
            raise FormatError(path, ln, "station name", f"site {name} appears twice")
        block = rows[k + 1:k + 1 + _LINES_PER_SITE]
        if len(block) < _LINES_PER_SITE:
            raise FormatError(path, ln, name, f"site {name} needs {_LINES_PER_SITE} lines of "
                              f"{len(BLQ_CONSTITUENTS)} numbers after its name")
        for bln, btok in block:
            if not _is_table_line(btok):
                raise FormatError(path, bln, name, f"{len(btok)} fields, expected "
                                  f"{len(BLQ_CONSTITUENTS)} numbers")
        sites.append(name)
        values.append([[parse_float(t, path, bln, name, kind=kind) for t in btok]
                       for (bln, btok), kind in zip(block, _KINDS)])
        k += 1 + _LINES_PER_SITE
    if not sites:
        raise FormatError(path, None, "station name", "no station block in the file")
    data = np.array(values, dtype=float)                      # (site, 6, 11)
    dims = ("site", "component", "constituent")
    return xr.Dataset(
        {"amplitude_m": (dims, data[:, :3], {"units": "m", "long_name":
                                             "ocean loading displacement amplitude"}),
         "phase_deg": (dims, data[:, 3:], {"units": "degree", "long_name":
                                           "Greenwich phase lag (lags positive)"})},
        coords={"site": np.array(sites, dtype=str), "component": list(BLQ_COMPONENTS),
                "constituent": list(BLQ_CONSTITUENTS)},
        attrs={"format": "BLQ", "source": path.name},
    )
