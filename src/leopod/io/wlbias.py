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

Errors: :class:`leopod.io.FormatError` naming file, line and field; epochs follow the reader
contract (years 1900-2199), values lie within +-1e6 cycles with a non-negative sigma, and a
value that is not an E19.12 number with its two-digit exponent (a line cut inside it) is
refused.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import epoch_ns, is_number
from leopod.io._text import FormatError, fixed_float, parse_float, parse_int, read_lines

__all__ = ["read_wl_bias"]

_SV = re.compile(r"^[A-Z]\d\d$")
_E_FORMAT = re.compile(r"[+-]?\d*\.\d+[EeDd][+-]\d\d\d?")
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
        parse_int(line[a:b], path, lineno, f"WL {name}", lo=0)
        for name, a, b in (("year", 8, 12), ("month", 12, 15), ("day", 15, 18),
                           ("hour", 18, 21), ("minute", 21, 24)))
    sec = fixed_float(line, 24, 34, path, lineno, "WL second")
    t = np.datetime64(epoch_ns(year, month, day, hour, minute, sec, path, lineno, "WL epoch",
                               leap_second=True), "ns")
    n = parse_int(line[34:37], path, lineno, "WL number of values", lo=0, hi=99)
    text = line[37:].rstrip()
    if text.endswith("COMMENT"):  # header comment label (column 61, or 66 in RINEX clock 3.04)
        text = text[:-len("COMMENT")]
    tokens = text.split()
    if n < 1 or not tokens:
        raise FormatError(path, lineno, "WL value", f"record announces {n} values and gives "
                          f"{len(tokens)}")
    # the values are E19.12 (RINEX clock data record): mantissa and a two-digit exponent, so a
    # line cut inside its last number lacks the exponent's digits
    for k, name in ((0, "WL value"), (1, "WL sigma")):
        if k < len(tokens) and (k == 0 or n >= 2) and is_number(tokens[k]) and \
                not _E_FORMAT.fullmatch(tokens[k]):
            raise FormatError(path, lineno, name, f"'{tokens[k]}' is not an E19.12 number "
                              "(mantissa and exponent): line cut short?")
    value = parse_float(tokens[0], path, lineno, "WL value", kind="bias_cycles")
    sigma = parse_float(tokens[1], path, lineno, "WL sigma", lo=0.0, hi=1e6) \
        if n >= 2 and len(tokens) > 1 else np.nan
    return t, sv, value, sigma
