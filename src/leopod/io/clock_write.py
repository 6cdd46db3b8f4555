"""Writer of RINEX clock files (versions 2.00 and 3.00): satellite clocks as AS records.

Specification: J. Ray, W. Gurtner, M. Coleman, "RINEX Extensions to Handle Clock Information",
version 3.04 (8 July 2017, files.igs.org/pub/data/format/rinex_clock304.txt), which also
documents 2.00 and 3.00-3.02. The Dataset written is that of
:func:`leopod.io.clock.read_rinex_clock` (schema in :mod:`leopod.io.clock`).
"""

from __future__ import annotations

from datetime import datetime
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import creation_time, write_text

__all__ = ["write_rinex_clock"]

_UNIX0 = datetime(1970, 1, 1)


def _fortran_e(values: np.ndarray) -> np.ndarray:
    """``values`` as Fortran E19.12 ("-0.123456789012E-03"), 12 significant digits.

    The digits are those of Python's ``f"{v:.11E}"`` (correctly rounded), moved behind a
    leading "0." with the exponent raised by one (0 stays "0.000000000000E+00").

    Parameters
    ----------
    values : ndarray of float, shape (n,)
        Finite values.

    Returns
    -------
    ndarray of str, shape (n,)
    """
    values = np.asarray(values, dtype=float)
    if not values.size:                  # numpy's string functions refuse empty arrays
        return np.array([], dtype=str)
    text = np.array([f"{v:.11E}" for v in np.abs(values).tolist()], dtype=str)  # d.d..dE±XX
    digits = np.strings.add(np.strings.slice(text, 0, 1), np.strings.slice(text, 2, 13))
    exponent = np.strings.slice(text, 14, None).astype(int) + (values != 0.0)
    sign = np.where(np.signbit(values), "-", " ")
    magnitude = np.strings.zfill(np.abs(exponent).astype(str), 2)
    return sign + np.strings.add(np.strings.add("0.", digits), "E") + np.strings.add(
        np.where(exponent < 0, "-", "+"), magnitude)


def value_records(kind: str, sats: list[str], epochs: list[str], value: np.ndarray,
                  sigma: np.ndarray) -> list[str]:
    """Data records ``<kind> <sat> <epoch>  n   <value> [<sigma>]`` of the finite values, in
    time, then satellite order (RINEX clock AS records, CNES/CLS WL records): E19.12 values,
    n = 2 with a finite sigma, else 1.

    Parameters
    ----------
    kind : str
        Record type, two characters ("AS", "WL").
    sats : list of str
        Satellite ids (at most 4 characters).
    epochs : list of str
        Epoch fields of the records, one per time.
    value, sigma : ndarray, shape (n_time, n_sat)
        Values and their sigmas (NaN: no record / no sigma).
    """
    i, k = np.nonzero(np.isfinite(value))
    if not i.size:
        return []
    with_sigma = np.isfinite(sigma[i, k])
    heads = np.strings.add(np.array([f"{kind} {sv:<4s} " for sv in sats])[k],
                           np.array(epochs)[i])
    values = np.strings.add(np.where(with_sigma, "  2   ", "  1   "), _fortran_e(value[i, k]))
    sigmas = np.full(i.size, "", dtype=values.dtype)
    sigmas[with_sigma] = np.strings.add(" ", _fortran_e(sigma[i, k][with_sigma]))
    return np.strings.add(heads, np.strings.add(values, sigmas)).tolist()


def _label(content: str, label: str) -> str:
    """A header line: content in columns 1-60, label in 61-80."""
    if len(content) > 60:
        raise ValueError(f"header content longer than 60 characters: '{content}'")
    return f"{content:<60s}{label}"


def write_rinex_clock(ds: xr.Dataset, path: str | Path, *, version: str = "3.00",
                      analysis_center: str = "LEO", analysis_center_name: str = "leopod",
                      program: str = "leopod", comments: tuple[str, ...] = (),
                      created: datetime | None = None) -> None:
    """Write the satellite clocks of ``ds`` as AS records of a RINEX clock 3.00 or 2.00 file.

    Values are written as E19.12 (12 significant digits, far below 1e-12 s for clocks under
    1 s); epochs with F10.6 seconds (1 µs resolution). Each (time, sv) with a finite
    ``clk_s`` gives one record, with 2 values when ``clk_sigma_s`` is present and finite, else 1.
    A name ending in ``.gz`` is gzip-compressed.

    Parameters
    ----------
    ds : xarray.Dataset
        ``clk_s`` (time, sv) [s], optional ``clk_sigma_s`` (time, sv) [s];
        ``attrs["time_system"]`` (default "GPS"); satellite ids of 3 characters.
    path : str or Path
        Output file.
    version : {"3.00", "2.00"}
        Format version to write.
    analysis_center : str
        3-character analysis centre id.
    analysis_center_name : str
        Analysis centre name (at most 55 characters).
    program : str
        Program name for "PGM / RUN BY / DATE" (at most 20 characters).
    comments : tuple of str
        COMMENT lines (at most 60 characters each).
    created : datetime, optional
        Creation time of "PGM / RUN BY / DATE" (UTC); default
        :func:`leopod.io._text.creation_time` (``SOURCE_DATE_EPOCH`` or the wall clock).

    Raises
    ------
    ValueError
        If ``ds`` lacks ``clk_s``, a satellite id is not 3 characters, the version is not
        supported, or a header text is too long.
    """
    if version not in ("3.00", "2.00"):
        raise ValueError(f"version must be '3.00' or '2.00', got '{version}'")
    if "clk_s" not in ds:
        raise ValueError("the Dataset has no 'clk_s' variable")
    clk = ds["clk_s"].transpose("time", "sv").values
    sigma = (ds["clk_sigma_s"].transpose("time", "sv").values if "clk_sigma_s" in ds
             else np.full(clk.shape, np.nan))
    sats = [str(s) for s in ds["sv"].values]
    if any(len(s) != 3 for s in sats):
        raise ValueError(f"satellite ids must have 3 characters, got {sats}")
    for text, width, what in ((analysis_center, 3, "analysis_center"),
                              (analysis_center_name, 55, "analysis_center_name"),
                              (program, 20, "program")):
        if len(text) > width:
            raise ValueError(f"{what} '{text}' is longer than {width} characters")
    time_system = str(ds.attrs.get("time_system", "GPS"))
    systems = {s[0] for s in sats}
    system = systems.pop() if len(systems) == 1 else "M"
    kind_text = "C" if version == "3.00" else "CLOCK DATA"
    now = creation_time(created).strftime("%Y%m%d %H%M%S UTC")
    system_text = system if version == "3.00" else ""
    out = [_label(f"{version:>9s}{'':11s}{kind_text:<20s}{system_text:<20s}",
                  "RINEX VERSION / TYPE"),
           _label(f"{program:<20s}{analysis_center:<20s}{now:<20s}", "PGM / RUN BY / DATE")]
    out += [_label(c, "COMMENT") for c in comments]
    if version == "3.00":
        out.append(_label(f"   {time_system:<3s}", "TIME SYSTEM ID"))
    out.append(_label(f"{1:6d}    AS", "# / TYPES OF DATA"))
    out.append(_label(f"{analysis_center:<3s}  {analysis_center_name}", "ANALYSIS CENTER"))
    out.append(_label(f"{len(sats):6d}", "# OF SOLN SATS"))
    for k in range(0, len(sats), 15):
        out.append(_label(" ".join(sats[k:k + 15]), "PRN LIST"))
    out.append(_label("", "END OF HEADER"))

    times = ds["time"].values.astype("datetime64[ns]").astype(np.int64)
    epochs = []
    for t_ns in times:
        us = (int(t_ns) + 500) // 1000
        whole, frac_us = divmod(us, 1_000_000)
        days, sec_of_day = divmod(whole, 86_400)
        day = datetime.fromordinal(_UNIX0.toordinal() + days)
        hour, rest = divmod(sec_of_day, 3600)
        minute, sec = divmod(rest, 60)
        epochs.append(f"{day.year:4d} {day.month:2d} {day.day:2d} {hour:2d} {minute:2d} "
                      f"{sec:2d}.{frac_us:06d}")
    out += value_records("AS", sats, epochs, clk, sigma)
    text = "\n".join(out) + "\n"
    write_text(path, text)
