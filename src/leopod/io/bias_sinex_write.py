"""Writer of Bias-SINEX 1.00 files (GNSS code and phase biases: OSB, DSB, ISB).

Format: "SINEX_BIAS - Solution (Software/technique) INdependent EXchange Format for GNSS
Biases, Version 1.00", S. Schaer, IGS, 7 December 2016. Record columns, units, sign and the
Dataset written are those of the reader, :mod:`leopod.io.bias_sinex`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text
from leopod.io.bias_sinex import (
    _INT_KEYWORDS,
    _NAT,
    _NS_TO_S,
    _PER_SYSTEM_KEYWORDS,
    _TIME_SYSTEMS,
)
from leopod.signals import frequency_hz

__all__ = ["write_bias_sinex"]


_SEPARATOR = "*" + "-" * 79
_SOLUTION_HEADER = ("*BIAS SVN_ PRN STATION__ OBS1 OBS2 BIAS_START____ BIAS_END______ UNIT "
                    "__ESTIMATED_VALUE____ _STD_DEV___ __ESTIMATED_SLOPE____ _STD_DEV___")
_TIME_SYSTEM_CODES = {name: code for code, name in _TIME_SYSTEMS.items()}
_NAT_INT = _NAT.view("int64")
# +BIAS/DESCRIPTION keywords written from the attrs of :func:`read_bias_sinex`, in the order of
# the CODE files (integer keywords right-aligned in columns 42-53, text from column 42).
_DESCRIPTION_ORDER = ("OBSERVATION_SAMPLING", "PARAMETER_SPACING", "DETERMINATION_METHOD",
                      "BIAS_MODE", "APC_MODEL", "TIME_SYSTEM", "RECEIVER_CLOCK_REFERENCE_GNSS",
                      "RECEIVER_CLOCK_REFERENCE_OBSERVABLES",
                      "SATELLITE_CLOCK_REFERENCE_OBSERVABLES")


def write_bias_sinex(ds: xr.Dataset, path: str | Path, *, decimals: int = 6,
                     comments: tuple[str, ...] = ()) -> None:
    """Write a Bias-SINEX 1.00 file that :func:`read_bias_sinex` reads back to ``ds``.

    The layout is that of the real CODE and WHU files (header line, ``+FILE/REFERENCE``,
    optional ``+FILE/COMMENT``, ``+BIAS/DESCRIPTION``, ``+BIAS/SOLUTION``, ``%=ENDBIA``);
    record columns as in the module docstring. Values are written in each record's ``unit``
    (``ns``, or ``cyc`` for phase biases, converted with the carrier frequency of ``OBS1``)
    with ``decimals`` decimals (default 6: 1e-6 ns, 0.3 µm; real files use 3-5). A blank
    ``sigma_s``/slope (NaN) leaves the field blank. Sign as in the reader: the bias is
    subtracted from the observation. A name ending in ``.gz`` is gzip-compressed; the file is
    written atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        The schema of :func:`read_bias_sinex`: on dim ``bias`` the coordinates ``bias_type``,
        ``svn``, ``prn``, ``station``, ``obs1``, ``obs2``, ``start``, ``end`` (NaT: open bound
        ``0000:000:00000``, or a time stamp when ``attrs["bias_timing"] == "epoch"``), optional
        ``unit`` (default ``ns``), data ``value_s`` [s] and optional ``sigma_s`` [s],
        ``slope_s_per_s``, ``slope_sigma_s_per_s``. Header attrs (defaults in brackets):
        ``file_agency`` [LEO], ``data_agency`` [file_agency], ``creation_time``
        [data_end, for reproducible files], ``data_start``/``data_end`` [first start/last end
        of the records], ``bias_mode_flag`` [A], ``time_system_code`` (or ``time_system``)
        [G], the ``+BIAS/DESCRIPTION`` keywords in lower case (``observation_sampling``,
        ``parameter_spacing``, ``determination_method``, ``bias_mode``, ``apc_model``,
        ``receiver_clock_reference_gnss``, ``satellite_clock_reference_observables_<sys>``,
        ``receiver_clock_reference_observables_<sys>``) and ``reference_<info_type>`` entries
        ("; " separates several lines of one type).
    path : str or Path
        Output file.
    decimals : int
        Decimals of the values and standard deviations.
    comments : tuple of str
        Lines of a ``+FILE/COMMENT`` block (at most 79 characters each).

    Raises
    ------
    ValueError
        If a required variable is missing, a value is not finite, a text field or comment is
        too long, a unit is not ns/cyc, or a time cannot be written as ``YYYY:DOY:SSSSS``.
    """
    for name in ("value_s", "bias_type", "prn", "obs1", "start", "end"):
        if name not in ds.variables:
            raise ValueError(f"the Dataset has no '{name}' variable")
    if any(len(c) > 79 for c in comments):
        raise ValueError("a +FILE/COMMENT line is longer than 79 characters")
    records = _solution_records(ds, decimals)
    attrs = ds.attrs
    agency = str(attrs.get("file_agency", "LEO"))
    starts = ds["start"].values
    ends = ds["end"].values
    data_start = attrs["data_start"] if "data_start" in attrs else _bound(starts, np.min)
    data_end = attrs["data_end"] if "data_end" in attrs else _bound(ends, np.max)
    header = (f"%=BIA 1.00 {agency:3.3s} {_format_time(attrs.get('creation_time') or data_end)} "
              f"{attrs.get('data_agency', agency)!s:3.3s} {_format_time(data_start)} "
              f"{_format_time(data_end)} {attrs.get('bias_mode_flag', 'A')!s} "
              f"{len(records):08d}")
    lines = [header, _SEPARATOR,
             "* Bias Solution INdependent EXchange Format (Bias-SINEX)", _SEPARATOR]
    lines += _reference_block(attrs)
    if comments:
        lines += ["+FILE/COMMENT", "*PRODUCT_REFERENCE" + "_" * 62, *(f" {c}" for c in comments),
                  "-FILE/COMMENT", _SEPARATOR]
    lines += _description_block(attrs)
    lines += ["+BIAS/SOLUTION", _SOLUTION_HEADER, *records, "-BIAS/SOLUTION", "%=ENDBIA"]
    write_text(path, "\n".join(lines) + "\n")


def _bound(times: np.ndarray, pick) -> str:
    """First or last finite time of the records ("" if all are open)."""
    finite = times[~np.isnat(times)]
    return str(pick(finite)) if finite.size else ""


def _reference_block(attrs) -> list[str]:
    lines = []
    for key, value in attrs.items():
        if key.startswith("reference_"):
            info_type = key[len("reference_"):].upper()
            lines += [f" {info_type:<18.18s} {part}"[:80] for part in str(value).split("; ")]
    if not lines:
        return []
    return ["+FILE/REFERENCE", "*INFO_TYPE_________ INFO" + "_" * 56, *lines,
            "-FILE/REFERENCE", _SEPARATOR]


def _description_block(attrs) -> list[str]:
    lines = []
    for keyword in _DESCRIPTION_ORDER:
        key = keyword.lower()
        if keyword in _PER_SYSTEM_KEYWORDS:
            for attr in sorted(k for k in attrs if k.startswith(key + "_")):
                system = attr[len(key) + 1:]
                observables = "  ".join(str(attrs[attr]).split())
                lines.append(f" {keyword:<39s} {system}  {observables}".rstrip())
        elif keyword == "TIME_SYSTEM":
            code = attrs.get("time_system_code") or _TIME_SYSTEM_CODES.get(
                str(attrs.get("time_system", "GPS")), "G")
            lines.append(f" {keyword:<39s} {code}")
        elif key in attrs:
            value = attrs[key]
            text = f"{int(value):>12d}" if keyword in _INT_KEYWORDS else str(value)
            lines.append(f" {keyword:<39s} {text}")
    return ["+BIAS/DESCRIPTION", "*KEYWORD" + "_" * 32 + " VALUE(S)" + "_" * 31, *lines,
            "-BIAS/DESCRIPTION", _SEPARATOR]


def _solution_records(ds: xr.Dataset, decimals: int) -> list[str]:
    n = ds.sizes["bias"]

    def column(name, default):
        return ds[name].values if name in ds.variables else np.full(n, default)

    text = {name: [str(v) for v in column(name.lower(), "")]
            for name in ("BIAS_TYPE", "SVN", "PRN", "STATION", "OBS1", "OBS2")}
    units = [str(u) for u in column("unit", "ns")]
    values = np.stack([column(name, np.nan) for name in
                       ("value_s", "sigma_s", "slope_s_per_s", "slope_sigma_s_per_s")], axis=-1)
    stamps = ds.attrs.get("bias_timing") == "epoch"
    starts, ends = ds["start"].values, ds["end"].values
    # format each distinct time once (keyed by its integer value: NaT compares unequal)
    keys = {int(i): t for t, i in zip(np.concatenate([starts, ends]),
                                      np.concatenate([starts, ends]).view("int64"))}
    times = {i: _format_time(t) for i, t in keys.items()}
    starts, ends = starts.view("int64"), ends.view("int64")
    out = []
    for k in range(n):
        fields = {name: text[name][k] for name in text}
        for name, width in (("BIAS_TYPE", 4), ("SVN", 4), ("PRN", 3), ("STATION", 9),
                            ("OBS1", 4), ("OBS2", 4), ):
            if len(fields[name]) > width:
                raise ValueError(f"record {k}: {name} '{fields[name]}' is longer than {width}")
        if not np.isfinite(values[k, 0]):
            raise ValueError(f"record {k} ({fields['PRN']} {fields['OBS1']}): value is not "
                             "finite")
        scale = _from_seconds(units[k], fields["PRN"], fields["OBS1"], k)
        start = times[int(starts[k])]
        end = "" if stamps and ends[k] == _NAT_INT else times[int(ends[k])]
        v = values[k] * scale
        numbers = (f"{v[0]:21.{decimals}f} {_blank_or(v[1], 11, decimals)} "
                   f"{_blank_or(v[2], 21, decimals)} {_blank_or(v[3], 11, decimals)}")
        out.append(f" {fields['BIAS_TYPE']:<4s} {fields['SVN']:<4s} {fields['PRN']:<3s} "
                   f"{fields['STATION']:<9s} {fields['OBS1']:<4s} {fields['OBS2']:<4s} "
                   f"{start:<14s} {end:<14s} {units[k]:<4s} {numbers}".rstrip())
    return out


def _blank_or(value: float, width: int, decimals: int) -> str:
    return f"{value:{width}.{decimals}f}" if np.isfinite(value) else " " * width


def _from_seconds(unit: str, prn: str, obs1: str, k: int) -> float:
    """Factor converting seconds to ``unit`` (inverse of the reader's ``_to_seconds``)."""
    if unit == "ns":
        return 1.0 / _NS_TO_S
    if unit == "cyc" and obs1.startswith("L"):
        return frequency_hz(prn[:1], obs1)
    raise ValueError(f"record {k} ({prn} {obs1}): cannot write unit '{unit}' (ns, or cyc "
                     "for phase)")


def _format_time(value) -> str:
    """datetime64 / ISO text -> ``YYYY:DOY:SSSSS``; NaT or "" -> ``0000:000:00000``."""
    if isinstance(value, str) and not value:
        return "0000:000:00000"
    t = np.datetime64(value, "ns")
    if np.isnat(t):
        return "0000:000:00000"
    day = t.astype("datetime64[D]")
    seconds = (t - day) / np.timedelta64(1, "s")
    if seconds != int(seconds):
        raise ValueError(f"time {t} is not a whole second (Bias-SINEX times are YYYY:DOY:SSSSS)")
    year = day.astype("datetime64[Y]")
    doy = int((day - year) / np.timedelta64(1, "D")) + 1
    return f"{int(str(year)):04d}:{doy:03d}:{int(seconds):05d}"
