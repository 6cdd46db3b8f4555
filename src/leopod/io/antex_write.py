"""Writer of ANTEX 1.4 files with receiver antennas (e.g. an in-flight estimated LEO pattern).

The record layout is that of "ANTEX: The Antenna Exchange Format, Version 1.4" (Rothacher and
Schmid 2010), read back by :func:`leopod.io.antex.read_antex` into the same
:class:`~leopod.io.antex.AntennaPattern` (PCO to 0.01 mm, PCV to 0.01 mm, the format's
resolution). Values are metres in the pattern and millimetres in the file. Each frequency gets
its ``NOAZI`` row and, when the pattern has an azimuth grid (``dazi_deg > 0``), one row per
azimuth from 0 to 360° inclusive.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from leopod.io._text import write_text
from leopod.io.antex import AntennaPattern

__all__ = ["antex_lines", "write_antex"]

_M_TO_MM = 1e3
_MAX_MM = 9999.99
"""Largest magnitude an F8.2 field holds [mm]."""


def _record(data: str, label: str) -> str:
    """One header-style record: data in columns 1-60, the label in 61-80."""
    if len(data) > 60:
        raise ValueError(f"ANTEX record {label!r}: data {data!r} longer than 60 columns")
    return f"{data:<60s}{label}"


def _mm(values_m: np.ndarray, what: str) -> np.ndarray:
    mm = np.asarray(values_m, dtype=float) * _M_TO_MM
    if not np.all(np.isfinite(mm)) or np.any(np.abs(mm) > _MAX_MM):
        raise ValueError(f"{what}: values must be finite and within ±{_MAX_MM} mm")
    return mm


def _row(label: str, values_mm: np.ndarray) -> str:
    return label + "".join(f"{v:8.2f}" for v in values_mm)


def _antenna_lines(p: AntennaPattern, method: str, agency: str, date: str) -> list[str]:
    if p.kind != "receiver":
        raise ValueError(f"antenna {p.antenna_type!r}: only receiver antennas are written")
    zen = np.asarray(p.zenith_deg, dtype=float)
    dzen = zen[1] - zen[0]
    lines = [
        _record("", "START OF ANTENNA"),
        _record(f"{p.antenna_type:<20.20s}{p.serial:<20.20s}", "TYPE / SERIAL NO"),
        _record(f"{method:<20.20s}{agency:<20.20s}{1:6d}    {date:<10.10s}",
                "METH / BY / # / DATE"),
        _record(f"  {p.dazi_deg:6.1f}", "DAZI"),
        _record(f"  {zen[0]:6.1f}{zen[-1]:6.1f}{dzen:6.1f}", "ZEN1 / ZEN2 / DZEN"),
        _record(f"{len(p.frequencies):6d}", "# OF FREQUENCIES"),
    ]
    for f in p.frequencies:
        lines += [_record(f"   {f}", "START OF FREQUENCY"),
                  _record("".join(f"{v:10.2f}" for v in _mm(p.pco[f], f"{f} PCO")),
                          "NORTH / EAST / UP"),
                  _row("   NOAZI", _mm(p.noazi[f], f"{f} NOAZI"))]
        if p.dazi_deg > 0:
            grid = _mm(p.grid[f], f"{f} PCV grid")
            lines += [_row(f"{az:8.1f}", row) for az, row in zip(p.azimuth_deg, grid)]
        lines.append(_record(f"   {f}", "END OF FREQUENCY"))
    lines.append(_record("", "END OF ANTENNA"))
    return lines


def antex_lines(patterns: Sequence[AntennaPattern], *, comments: Iterable[str] = (),
                method: str = "RESIDUAL", agency: str = "LEOPOD",
                date: str = "") -> list[str]:
    """The lines of an ANTEX 1.4 file holding ``patterns`` (receiver antennas).

    Parameters
    ----------
    patterns : sequence of AntennaPattern
        Receiver antennas; ``zenith_deg`` regular, ``grid[f]`` of shape (n_az + 1, n_zen)
        when ``dazi_deg > 0``; values [m].
    comments : iterable of str
        Header ``COMMENT`` lines (each at most 60 characters).
    method, agency, date : str
        The ``METH / BY / # / DATE`` fields (calibration method, agency, date text).

    Raises
    ------
    ValueError
        On a satellite antenna, a value that is not finite or exceeds the F8.2 field, or a
        comment longer than 60 characters.
    """
    lines = [_record(f"{1.4:8.1f}            M", "ANTEX VERSION / SYST"),
             _record("A", "PCV TYPE / REFANT")]
    lines += [_record(c, "COMMENT") for c in comments]
    lines.append(_record("", "END OF HEADER"))
    for p in patterns:
        lines += _antenna_lines(p, method, agency, date)
    return lines


def write_antex(path: str | Path, patterns: Sequence[AntennaPattern], **kwargs) -> Path:
    """Write :func:`antex_lines` of ``patterns`` (keyword arguments passed on) atomically."""
    return write_text(path, "\n".join(antex_lines(patterns, **kwargs)) + "\n")
