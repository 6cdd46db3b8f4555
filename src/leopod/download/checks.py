"""Checks that a fetched file is usable: non-empty, not an error page, parses, covers the day.

Each product *kind* has one check. It reads the file with leopod's reader of the format
(:mod:`leopod.io`), so a file that passes can be read by the steps downstream, and adds what a
reader cannot know: that a daily product covers the day it was fetched for, and that biases
have no missing values (a NaN observable-specific bias in a WUM Bias-SINEX file crashed
PRIDE PPP-AR, issue PrideLab/PRIDE-PPPAR#56: here it is rejected and the next source tried).

Coverage rules (epochs compared as labels of the file's own time system, GPS for GNSS
products; day = [00:00, 24:00) of the date):

- ``sp3``, ``clock``: first epoch <= 00:00 + Δ and last epoch >= 24:00 − 2Δ, with Δ the
  sampling interval: the nominal first (00:00) and last (24:00 − Δ) epochs are present to
  within one sampling interval (a clock file ending at 23:59:00 at 30 s passes; one ending at
  18:00 does not).
- ``rinex_obs``: every epoch falls in [00:00, 24:00] of the day.
- ``bias_sinex``: at least one bias valid during the day; every value finite.
- ``erp`` (IGS ERP), ``eop`` (IERS finals2000A): the table reaches the day (ERP: its MJD range
  overlaps the day; finals: the day's row has polar motion and UT1−UTC).
- ``space_weather``: the day has a row. ``crd``: at least one normal point in the day.

A failed check raises :class:`CheckError`, whose message names the file and, when the
reader gives them, the line and the field.
"""

from __future__ import annotations

import datetime as _dt
import logging
from collections.abc import Callable
from pathlib import Path

import numpy as np

from leopod.io._text import FormatError, parse_float, read_lines
from leopod.time.calendar import parse_date_id

__all__ = ["KINDS", "CheckError", "check_file"]

logger = logging.getLogger(__name__)

_SECONDS_PER_DAY = 86_400
_MJD_UNIX_EPOCH = 40_587  # MJD of 1970-01-01
_HTML_MARKS = (b"<!doctype html", b"<html", b"<head", b"<body", b"<?xml")


class CheckError(ValueError):
    """A file is not a usable product; the message names the file (and line/field if known)."""


def _day_bounds(day: _dt.date) -> tuple[np.datetime64, np.datetime64]:
    start = np.datetime64(day.isoformat(), "ns")
    return start, start + np.timedelta64(_SECONDS_PER_DAY, "s")


def _iso(t) -> str:
    return str(np.datetime64(t, "s"))


def _interval_s(times: np.ndarray, declared: float | None) -> float:
    """Sampling interval [s]: the declared one if positive, else the median epoch spacing."""
    if declared is not None and np.isfinite(declared) and declared > 0:
        return float(declared)
    if times.size < 2:
        return 0.0
    return float(np.median(np.diff(times).astype("timedelta64[ns]").astype(np.int64)) * 1e-9)


def _require_day_span(path: Path, times: np.ndarray, interval_s: float, day: _dt.date,
                      what: str) -> None:
    """First epoch <= 00:00 + Δ and last epoch >= 24:00 − 2Δ (see the module docstring)."""
    start, end = _day_bounds(day)
    if times.size == 0:
        raise CheckError(f"{path}: {what} has no epoch")
    step = np.timedelta64(round(interval_s * 1e9), "ns")
    first, last = times.min(), times.max()
    if first > start + step or last < end - 2 * step:
        raise CheckError(f"{path}: {what} spans {_iso(first)} to {_iso(last)} and does not cover "
                         f"the day {day.isoformat()} (sampling {interval_s:g} s)")


def _check_sp3(path: Path, day: _dt.date | None) -> str:
    from leopod.io.sp3 import read_sp3

    ds = read_sp3(path)
    times = ds["time"].values
    if not np.isfinite(ds["pos_m"].values).any():
        raise CheckError(f"{path}: no satellite has a valid position")
    interval = _interval_s(times, ds.attrs.get("interval_s"))
    if day is not None:
        _require_day_span(path, times, interval, day, "the orbit")
    return (f"SP3 {times.size} epochs {_iso(times[0])} to {_iso(times[-1])}, "
            f"{ds.sizes['sv']} satellites")


def _check_clock(path: Path, day: _dt.date | None) -> str:
    from leopod.io.clock import read_rinex_clock

    ds = read_rinex_clock(path, kinds=("AS",))
    times = ds["time"].values
    if "clk_s" not in ds or not np.isfinite(ds["clk_s"].values).any():
        raise CheckError(f"{path}: no satellite clock (AS) record")
    interval = _interval_s(times, ds.attrs.get("interval_s"))
    if day is not None:
        _require_day_span(path, times, interval, day, "the clock file")
    return (f"clock {times.size} epochs {_iso(times[0])} to {_iso(times[-1])}, "
            f"{ds.sizes['sv']} satellites, {interval:g} s")


def _check_bias_sinex(path: Path, day: _dt.date | None) -> str:
    from leopod.io.bias_sinex import read_bias_sinex

    ds = read_bias_sinex(path)
    n = ds.sizes["bias"]
    if n == 0:
        raise CheckError(f"{path}: +BIAS/SOLUTION holds no bias")
    bad = np.flatnonzero(~np.isfinite(ds["value_s"].values))
    if bad.size:
        k = bad[0]
        raise CheckError(f"{path}: field 'ESTIMATED_VALUE': bias {k + 1} ({ds['prn'].values[k]} "
                         f"{ds['obs1'].values[k]}) is missing or not finite")
    if day is not None:
        start, end = _day_bounds(day)
        s, e = ds["start"].values, ds["end"].values
        valid = (np.isnat(s) | (s < end)) & (np.isnat(e) | (e > start))
        if not valid.any():
            raise CheckError(f"{path}: no bias is valid on {day.isoformat()} (data "
                             f"{ds.attrs.get('data_start')} to {ds.attrs.get('data_end')})")
    return f"Bias-SINEX {n} biases of {np.unique(ds['prn'].values).size} satellites/systems"


def _check_wl_bias(path: Path, day: _dt.date | None) -> str:
    from leopod.io.wlbias import read_wl_bias

    ds = read_wl_bias(path)
    n = int(np.isfinite(ds["wl_bias_cyc"].values).sum())
    if n == 0:
        raise CheckError(f"{path}: field 'WL': no finite wide-lane bias")
    return f"{n} wide-lane biases of {ds.sizes['sv']} satellites"


def _check_dcb(path: Path, day: _dt.date | None) -> str:
    from leopod.io.dcb import read_code_dcb

    ds = read_code_dcb(path)
    values = ds["dcb_s"].values
    if values.size == 0 or not np.isfinite(values).all():
        raise CheckError(f"{path}: field 'DCB': missing or non-finite satellite DCB")
    return f"DCB {ds.attrs.get('dcb_type', '')} of {values.size} satellites"


def _check_rinex_obs(path: Path, day: _dt.date | None) -> str:
    from leopod.io.rinex_obs import read_rinex_obs

    ds = read_rinex_obs(path)
    times = ds["time"].values
    if times.size == 0:
        raise CheckError(f"{path}: the observation file has no epoch")
    if day is not None:
        start, end = _day_bounds(day)
        outside = (times < start) | (times > end)
        if outside.any():
            raise CheckError(f"{path}: epoch {_iso(times[np.argmax(outside)])} is outside the "
                             f"day {day.isoformat()}")
    return (f"RINEX {ds.attrs.get('rinex_version')} {times.size} epochs {_iso(times[0])} to "
            f"{_iso(times[-1])}, {ds.sizes['sv']} satellites")


def _check_antex(path: Path, day: _dt.date | None) -> str:
    from leopod.io.antex import read_antex

    atx = read_antex(path)
    return f"ANTEX {len(atx)} antennas, {len(atx.prns)} satellites"


def _mjd(day: _dt.date) -> int:
    return (day - _dt.date(1970, 1, 1)).days + _MJD_UNIX_EPOCH


def _check_erp(path: Path, day: _dt.date | None) -> str:
    """IGS ERP (version 2, files.igs.org/pub/data/format/erp.txt): MJD, Xpole, Ypole, UT1-UTC."""
    lines = read_lines(path)
    first = next((ln for ln in lines if ln.strip()), "")
    if not first.strip().lower().startswith("version"):
        raise CheckError(f"{path}:1: field 'VERSION': not an IGS ERP file (first line "
                         f"'{first[:30]}')")
    head = next((k for k, ln in enumerate(lines) if ln.split()[:1] == ["MJD"]), None)
    if head is None:
        raise CheckError(f"{path}: field 'MJD': the column header line is missing")
    mjds = []
    data = False  # lines between the column header and the first record are units
    for k in range(head + 1, len(lines)):
        tokens = lines[k].split()
        if not tokens:
            continue
        if not data:
            try:
                float(tokens[0])
            except ValueError:
                continue
            data = True
        if len(tokens) < 4:
            raise CheckError(f"{path}:{k + 1}: field 'UT1-UTC': the record has {len(tokens)} "
                             "fields, expected at least MJD, X, Y, UT1-UTC")
        for text, field in zip(tokens[:4], ("MJD", "X-P", "Y-P", "UT1-UTC"), strict=True):
            parse_float(text, path, k + 1, field)
        mjds.append(float(tokens[0]))
    if not mjds:
        raise CheckError(f"{path}: field 'MJD': the file holds no ERP record")
    lo, hi = min(mjds), max(mjds)
    if day is not None and (lo > _mjd(day) + 1 or hi < _mjd(day)):
        raise CheckError(f"{path}: ERP records span MJD {lo:.2f} to {hi:.2f} and do not reach "
                         f"{day.isoformat()} (MJD {_mjd(day)})")
    return f"ERP {len(mjds)} records, MJD {lo:.2f} to {hi:.2f}"


# finals2000A columns (0-based, end exclusive): IERS Rapid Service readme.finals2000A.
_FINALS_FIELDS = (("MJD", 7, 15), ("PM-x", 18, 27), ("PM-y", 37, 46), ("UT1-UTC", 58, 68))


def _check_eop(path: Path, day: _dt.date | None) -> str:
    """IERS finals2000A: every row has an MJD; the day's row has polar motion and UT1-UTC."""
    lines = read_lines(path)
    filled = {}
    for k, line in enumerate(lines):
        if not line.strip():
            continue
        values = [parse_float(line[a:b], path, k + 1, name, allow_blank=name != "MJD")
                  for name, a, b in _FINALS_FIELDS]
        if all(np.isfinite(values[1:])):
            filled[round(values[0])] = k + 1
    if not filled:
        raise CheckError(f"{path}: field 'PM-x': no row with polar motion and UT1-UTC")
    if day is not None and _mjd(day) not in filled:
        raise CheckError(f"{path}: no finals2000A row with polar motion and UT1-UTC for "
                         f"{day.isoformat()} (MJD {_mjd(day)}); the file covers MJD "
                         f"{min(filled)} to {max(filled)}")
    return f"finals2000A MJD {min(filled)} to {max(filled)}"


def _check_space_weather(path: Path, day: _dt.date | None) -> str:
    from leopod.io.space_weather import read_space_weather

    ds = read_space_weather(path)
    dates = ds["date"].values
    if day is not None and np.datetime64(day.isoformat(), "ns") not in dates:
        raise CheckError(f"{path}: no space-weather row for {day.isoformat()} (file covers "
                         f"{_iso(dates[0])[:10]} to {_iso(dates[-1])[:10]})")
    return f"space weather {dates.size} rows to {_iso(dates[-1])[:10]}"


def _check_icgem(path: Path, day: _dt.date | None) -> str:
    from leopod.io.icgem import read_icgem

    ds = read_icgem(path)
    return f"gravity field {ds.attrs.get('modelname', path.name)} degree {ds.attrs['max_degree']}"


def _check_crd(path: Path, day: _dt.date | None) -> str:
    from leopod.io.crd import read_crd

    ds = read_crd(path)
    times = ds["time"].values
    if times.size == 0:
        raise CheckError(f"{path}: field '11': the file holds no normal point")
    if day is not None:
        start, end = _day_bounds(day)
        if not ((times >= start) & (times < end)).any():
            raise CheckError(f"{path}: no normal point on {day.isoformat()} (points "
                             f"{_iso(times.min())} to {_iso(times.max())})")
    return f"CRD {times.size} normal points, {ds.attrs.get('n_sessions', '?')} passes"


def _check_sinex(path: Path, day: _dt.date | None) -> str:
    from leopod.io.sinex import read_sinex_stations

    ds = read_sinex_stations(path)
    if ds.sizes["solution"] == 0:
        raise CheckError(f"{path}: field 'SOLUTION/ESTIMATE': no station solution")
    return f"SINEX {ds.sizes['solution']} station solutions"


def _check_sinex_ecc(path: Path, day: _dt.date | None) -> str:
    from leopod.io.sinex import read_sinex_eccentricities

    ds = read_sinex_eccentricities(path)
    if ds.sizes["record"] == 0:
        raise CheckError(f"{path}: field 'SITE/ECCENTRICITY': no eccentricity")
    return f"SINEX {ds.sizes['record']} eccentricities"


def _check_generic(path: Path, day: _dt.date | None) -> str:
    return f"{path.stat().st_size} bytes"


_CHECKS: dict[str, Callable[[Path, _dt.date | None], str]] = {
    "sp3": _check_sp3, "clock": _check_clock, "bias_sinex": _check_bias_sinex,
    "wl_bias": _check_wl_bias, "dcb": _check_dcb, "rinex_obs": _check_rinex_obs,
    "antex": _check_antex, "erp": _check_erp, "eop": _check_eop,
    "space_weather": _check_space_weather, "icgem": _check_icgem, "crd": _check_crd,
    "sinex": _check_sinex, "sinex_ecc": _check_sinex_ecc, "generic": _check_generic,
}

#: Product kinds with a check.
KINDS = tuple(_CHECKS)


def _reject_empty_or_html(path: Path) -> None:
    """An empty file or an HTML/XML page (a login or error page served with status 200)."""
    try:
        size = path.stat().st_size
    except OSError as err:
        raise CheckError(f"{path}: cannot be read ({err.strerror})") from None
    if size == 0:
        raise CheckError(f"{path}: the file is empty")
    with open(path, "rb") as f:
        head = f.read(1024).lstrip(b"\xef\xbb\xbf \t\r\n").lower()
    if head.startswith(_HTML_MARKS) or b"<html" in head:
        first = head.splitlines()[0][:60].decode("latin-1", "replace")
        raise CheckError(f"{path}: an HTML/XML page ('{first}'), not a product file")


def check_file(path: str | Path, kind: str, date: str | _dt.date | None = None, *,
               display: str | None = None) -> str:
    """Check that ``path`` is a usable product of ``kind`` (covering ``date`` if given).

    Parameters
    ----------
    path : str or Path
        The (decompressed) file.
    kind : str
        One of :data:`KINDS`.
    date : str, datetime.date or None
        Day ``YYYY-DDD`` (or ``YYYY-MM-DD``) the file must cover; None skips coverage.
    display : str, optional
        Name to show for the file in error messages instead of ``path`` (e.g. the URL it
        came from, when ``path`` is a temporary file).

    Returns
    -------
    str
        A one-line summary of the content (epochs, satellites, ...), for the log.

    Raises
    ------
    CheckError
        Naming the file, and line and field where the reader gives them.
    ValueError
        For an unknown kind.
    """
    if kind not in _CHECKS:
        raise ValueError(f"unknown product kind '{kind}' (known: {', '.join(KINDS)})")
    path = Path(path)
    day = parse_date_id(date) if isinstance(date, str) else date
    try:
        _reject_empty_or_html(path)
        return _CHECKS[kind](path, day)
    except (CheckError, FormatError) as err:
        message = str(err)
    except Exception as err:  # a corrupt download must not crash the run
        logger.debug("check of %s failed", path, exc_info=True)
        message = f"{path}: unreadable as {kind} ({type(err).__name__}: {err})"
    if display:
        message = message.replace(str(path), display)
        if display not in message:
            message = f"{display}: {message}"
    elif str(path) not in message:
        message = f"{path}: {message}"
    raise CheckError(message)
