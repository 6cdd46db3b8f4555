"""Reader of CNES/CLS (GRG) wide-lane satellite biases given as ``WL`` records.

The CNES/CLS IGS analysis centre publishes GPS clocks with the integer property of the
narrow-lane ambiguities ("integer-recovery clocks", Laurichesse et al. 2009, NAVIGATION 56(2)
135-149) together with daily wide-lane satellite biases (WSB). Their product page
(igsac-cnes.cls.fr/html/products.html) lists the daily ``grgwwwwd.CLK`` RINEX clock files
"(see specificities of clk comment lines)" and a weekly ``grgwwww7.WSB`` file. No format
document for either is public; what is documented (and read here) is the ``WL`` record:

- it has the layout of a RINEX clock data record (RINEX CLOCK 3.02, Ray & Gurtner 2010:
  type A2, name A4, epoch I4,4I3,F10.6, number of values I3, values E19.12) with the record
  type ``WL`` and a satellite name, e.g. ::

      WL G01 2016 01 01 00 00  0.000000  1   -0.123000000000E+00

  columns (0-based, end exclusive): type 0:2, satellite 3:7, year 8:12, month 12:15,
  day 15:18, hour 18:21, minute 21:24, second 24:34, number of values 34:37, values from 37;
- in the GRG clock files the ``WL`` lines sit in the header, before ``END OF HEADER``, as the
  public converter ``grg2snx.cpp`` of github.com/YuanxinPan/clkcomb reads them (``"WL "`` at
  column 1, PRN in columns 4-6, value from column 39); when such a line ends with the
  ``COMMENT`` header label, the label is not read as a value.

The value is the satellite wide-lane (Melbourne-Wuebbena) bias in wide-lane cycles, stored with
the sign it has in the file. The sign convention must be checked against the application:
``grg2snx.cpp`` negates it before building its L1/L2 phase OSBs. A second value, when the
record announces two, is read as its standard deviation (RINEX clock convention). Every
``WL`` line of the file is read, wherever it is, so a file holding only ``WL`` lines (e.g. the
records cut out of a clock file) is read too. The ``.WSB`` file layout itself is not
documented publicly and is not supported unless it uses these records.

Dataset schema
--------------
dims
    ``time`` (epochs of the WL records, datetime64[ns] in the file's time system),
    ``sv`` (``G01`` ...).
data variables
    ``wl_bias_cyc`` (time, sv) [1, wide-lane cycles]; ``wl_bias_sigma_cyc`` (time, sv) [1],
    NaN where the record gives none. Missing (time, sv) pairs are NaN.
attrs
    ``time_system`` (from a ``TIME SYSTEM ID`` header record if present, else "GPS", the
    RINEX clock default), ``record_type`` ("WL"), ``n_records``, ``source`` (the documents
    cited here).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import FormatError, fixed_float, parse_float, parse_int, read_lines, write_text
from leopod.io.clock import _fortran_e

__all__ = ["read_wl_bias", "wl_bias_records", "write_wl_bias"]

_SV = re.compile(r"^[A-Z]\d\d$")
_SOURCE = ("CNES/CLS GRG products (igsac-cnes.cls.fr); RINEX CLOCK 3.02 data record layout; "
           "WL record columns as read by YuanxinPan/clkcomb grg2snx.cpp")


def read_wl_bias(path: str | Path) -> xr.Dataset:
    """Read the ``WL`` wide-lane satellite bias records of a CNES/CLS file.

    Parameters
    ----------
    path : str or Path
        A GRG RINEX clock file (plain, .gz or .Z) or any text file of ``WL`` records.

    Returns
    -------
    xarray.Dataset
        Wide-lane biases in cycles on (time, sv) (schema in the module docstring).

    Raises
    ------
    FormatError
        If the file has no ``WL`` record, a record has an invalid satellite, epoch, count or
        value (non-numeric, NaN), or the same satellite and epoch appear twice.
    """
    path = Path(path)
    lines = read_lines(path)
    time_system = "GPS"
    records: dict[tuple[np.datetime64, str], tuple[float, float]] = {}
    for k, line in enumerate(lines):
        if line.startswith("WL "):
            t, sv, value, sigma = _record(line, k + 1, path)
            if (t, sv) in records:
                raise FormatError(path, k + 1, "WL", f"second WL record of {sv} at {t}")
            records[(t, sv)] = (value, sigma)
        elif line[60:80].strip() == "TIME SYSTEM ID" and line[3:6].strip():
            time_system = line[3:6].strip()
    if not records:
        raise FormatError(path, None, "WL", "no WL (wide-lane bias) record in the file")
    times = np.array(sorted({t for t, _ in records}), dtype="datetime64[ns]")
    svs = sorted({sv for _, sv in records})
    cube = np.full((len(times), len(svs), 2), np.nan)
    t_index = {t: i for i, t in enumerate(times)}
    s_index = {s: i for i, s in enumerate(svs)}
    for (t, sv), pair in records.items():
        cube[t_index[t], s_index[sv]] = pair
    ds = xr.Dataset(
        {
            "wl_bias_cyc": (("time", "sv"), cube[..., 0],
                            {"units": "1", "long_name": "wide-lane satellite bias in wide-lane "
                                                        "cycles (sign as in the file)"}),
            "wl_bias_sigma_cyc": (("time", "sv"), cube[..., 1],
                                  {"units": "1", "long_name": "standard deviation of the "
                                                              "wide-lane satellite bias"}),
        },
        coords={"time": times, "sv": svs},
    )
    ds.attrs.update(time_system=time_system, record_type="WL", n_records=len(records),
                    source=_SOURCE)
    return ds


def _record(line: str, lineno: int, path) -> tuple[np.datetime64, str, float, float]:
    """Decode one WL line: (epoch, satellite, value [cycles], sigma [cycles] or NaN)."""
    sv = line[3:7].strip()
    if not _SV.match(sv):
        raise FormatError(path, lineno, "WL satellite", f"'{sv}' is not a satellite sNN")
    year, month, day, hour, minute = (
        parse_int(line[a:b], path, lineno, f"WL {name}")
        for name, a, b in (("year", 8, 12), ("month", 12, 15), ("day", 15, 18),
                           ("hour", 18, 21), ("minute", 21, 24)))
    sec = fixed_float(line, 24, 34, path, lineno, "WL second")
    if not (1 <= month <= 12 and 1 <= day <= 31 and 0 <= hour <= 23 and 0 <= minute <= 59
            and 0 <= sec < 61):
        raise FormatError(path, lineno, "WL epoch", f"invalid epoch '{line[8:34].strip()}'")
    try:
        t = np.datetime64(f"{year:04d}-{month:02d}-{day:02d}", "ns")
    except ValueError:
        raise FormatError(path, lineno, "WL epoch", f"invalid date '{line[8:18]}'") from None
    t = t + np.timedelta64(hour * 3600 + minute * 60, "s") + np.timedelta64(round(sec * 1e9),
                                                                              "ns")
    n = parse_int(line[34:37], path, lineno, "WL number of values")
    text = line[37:].rstrip()
    if text.endswith("COMMENT"):  # header comment label (column 61, or 66 in RINEX clock 3.04)
        text = text[:-len("COMMENT")]
    tokens = text.split()
    if n < 1 or not tokens:
        raise FormatError(path, lineno, "WL value", f"record announces {n} values and gives "
                          f"{len(tokens)}")
    value = parse_float(tokens[0], path, lineno, "WL value")
    sigma = parse_float(tokens[1], path, lineno, "WL sigma") if n >= 2 and len(tokens) > 1 \
        else np.nan
    return t, sv, value, sigma


def wl_bias_records(ds: xr.Dataset) -> list[str]:
    """The ``WL`` records of ``ds`` as text lines of at most 59 characters.

    Layout of a RINEX clock data record (A2,1X,A4,1X,I4,4I3,F10.6,I3,3X,E19.12[,1X,E19.12]):
    e.g. ``WL G01 2016  1  1  0  0  0.000000  1   -0.123000000000E+00``; the second value
    (standard deviation) is written only where ``wl_bias_sigma_cyc`` is finite. Lines with
    one value fit the 60 columns of a RINEX header ``COMMENT``, so they can be passed as
    ``comments`` to :func:`leopod.io.clock.write_rinex_clock` to give a clock file in the
    GRG style (WL records in its header), which :func:`read_wl_bias` reads.

    Parameters
    ----------
    ds : xarray.Dataset
        ``wl_bias_cyc`` (time, sv) [WL cycles] and optional ``wl_bias_sigma_cyc`` (time, sv),
        the schema of :func:`read_wl_bias`; NaN entries are skipped. Values are written with
        the sign they have in ``ds`` (CNES convention: see :func:`write_wl_bias`).

    Returns
    -------
    list of str
        One line per finite (time, sv), time-major, satellites in ``ds`` order.

    Raises
    ------
    ValueError
        If ``wl_bias_cyc`` is missing or a satellite id is not of the form ``G01``.
    """
    if "wl_bias_cyc" not in ds:
        raise ValueError("the Dataset has no 'wl_bias_cyc' variable")
    value = ds["wl_bias_cyc"].transpose("time", "sv").values
    sigma = (ds["wl_bias_sigma_cyc"].transpose("time", "sv").values
             if "wl_bias_sigma_cyc" in ds else np.full(value.shape, np.nan))
    svs = [str(s) for s in ds["sv"].values]
    bad = [s for s in svs if not _SV.match(s)]
    if bad:
        raise ValueError(f"satellite ids must look like 'G01', got {bad}")
    lines = []
    for i, t in enumerate(ds["time"].values.astype("datetime64[ns]")):
        epoch = _epoch_text(t)
        for k, sv in enumerate(svs):
            if not np.isfinite(value[i, k]):
                continue
            values = _fortran_e(value[i, k])
            n = 1
            if np.isfinite(sigma[i, k]):
                values += " " + _fortran_e(sigma[i, k])
                n = 2
            lines.append(f"WL {sv:<4s} {epoch}{n:3d}   {values}")
    return lines


def write_wl_bias(ds: xr.Dataset, path: str | Path) -> None:
    """Write wide-lane satellite biases as a file of CNES/CLS ``WL`` records.

    The file holds only ``WL`` lines (:func:`wl_bias_records`), which :func:`read_wl_bias`
    reads back exactly to 12 significant digits (E19.12). It is written atomically; a name
    ending in ``.gz`` is gzip-compressed.

    Sign convention: the value is written as given. The convention of the CNES/CLS files,
    followed by the simulator (:func:`leopod.simulate.biases.ar_products`), is taken to be
    ``HMW/λ_WL = N_WL + μ_r − μ^s`` with ``μ^s`` the file value, i.e. the file holds the
    negative of the satellite term of the HMW combination: the public GRG converter
    (YuanxinPan/clkcomb, ``read_grg_bias`` and ``grg2snx.cpp``) negates the value to get that
    term. A user fixes ``N_WL = HMW/λ_WL + μ^s − μ_r``.

    Parameters
    ----------
    ds : xarray.Dataset
        ``wl_bias_cyc`` (time, sv) [WL cycles], optional ``wl_bias_sigma_cyc`` (time, sv).
    path : str or Path
        Output file.

    Raises
    ------
    ValueError
        As :func:`wl_bias_records`, or if no value is finite.
    """
    lines = wl_bias_records(ds)
    if not lines:
        raise ValueError("no finite wide-lane bias to write")
    text = "\n".join(lines) + "\n"
    write_text(path, text)


def _epoch_text(t: np.datetime64) -> str:
    """``I4,4I3,F10.6`` epoch of a RINEX clock data record (1 µs resolution)."""
    day = t.astype("datetime64[D]")
    us = int((t - day) / np.timedelta64(1, "us"))
    year, month, dom = (int(x) for x in str(day).split("-"))
    hour, rest = divmod(us, 3_600_000_000)
    minute, rest = divmod(rest, 60_000_000)
    return f"{year:4d}{month:3d}{dom:3d}{hour:3d}{minute:3d}{rest / 1e6:10.6f}"
