"""Writer of SP3-d precise orbit files.

Specification: S. Hilla, "The Extended Standard Product 3 Orbit Format (SP3-d)", NGS/NOAA,
21 February 2016 (files.igs.org/pub/data/format/sp3d.pdf). The Dataset written is the one
returned by :func:`leopod.io.sp3.read_sp3` (schema in :mod:`leopod.io.sp3`).
"""

from __future__ import annotations

import logging
import math
from datetime import datetime
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text
from leopod.io.provenance import current_job
from leopod.io.sp3 import _BAD_CLOCK, _NS, _XYZ

__all__ = ["write_sp3"]

logger = logging.getLogger(__name__)

_UNIX0 = datetime(1970, 1, 1)
_GPS0_NS = 315_964_800 * _NS  # 1980-01-06T00:00:00 as ns since 1970-01-01
_MJD0_NS = -40_587 * 86_400 * _NS  # 1858-11-17T00:00:00 as ns since 1970-01-01
_IDS_PER_LINE = 17
#: Bases of the record accuracy exponents written with ``pos_sigma_m``/``clk_sigma_s``: σ =
#: base**n mm (positions) and ps (clocks), the values of the SP3-d example files (Hilla 2016).
_BASE_POS = 1.25
_BASE_CLK = 1.025
_MAX_EXP_POS, _MAX_EXP_CLK = 99, 999


def _calendar(t_ns: int) -> tuple[int, int, int, int, int, str]:
    """Split ns since 1970 into year, month, day, hour, minute and an F11.8 seconds text."""
    ticks = (t_ns + 5) // 10  # 10 ns: the resolution of F11.8 seconds
    whole, frac = divmod(ticks, 100_000_000)
    days, sec_of_day = divmod(whole, 86_400)
    dt = datetime.fromordinal(_UNIX0.toordinal() + days)
    hour, rest = divmod(sec_of_day, 3600)
    minute, sec = divmod(rest, 60)
    return dt.year, dt.month, dt.day, hour, minute, f"{sec:2d}.{frac:08d}"


def _fixed_texts(values: np.ndarray, width: int, decimals: int, what: str,
                 sats: list[str]) -> list[str]:
    """Fixed-point fields of exactly ``width`` characters of ``values`` (time, sv[, xyz]),
    flattened in that order; ValueError naming the first field that overflows."""
    texts = [f"{v:{width}.{decimals}f}" for v in values.ravel().tolist()]
    long = [j for j, t in enumerate(texts) if len(t) > width]
    if long:
        j = long[0]
        i, k = np.unravel_index(j, values.shape)[:2]
        raise ValueError(f"{what} of {sats[k]} at epoch {i} = {values.ravel()[j]} does not "
                         f"fit the SP3 field F{width}.{decimals}")
    return texts


def _clock_texts(values: np.ndarray, what: str, sats: list[str]) -> list[str]:
    """F14.6 clock or clock-rate fields of ``values`` (time, sv), flattened; NaN becomes the
    "bad or absent" 999999.999999, and a value reaching it is a ValueError."""
    ok = np.isfinite(values)
    reserved = ok & (np.abs(np.where(ok, values, 0.0)) >= _BAD_CLOCK)
    if reserved.any():
        i, k = np.argwhere(reserved)[0]
        raise ValueError(f"{what} of {sats[k]} at epoch {i} = {values[i, k]} reaches the "
                         "reserved SP3 bad-clock value 999999")
    texts = _fixed_texts(np.where(ok, values, 0.0), 14, 6, what, sats)
    return [t if good else " 999999.999999" for t, good in zip(texts, ok.ravel().tolist())]


def _exponents(sigma: np.ndarray, base: float, largest: int) -> np.ndarray:
    """SP3-d accuracy exponents ``n = round(log_base σ)`` of ``σ`` [mm or ps], in
    ``[0, largest]``; −1 where ``σ`` is not finite (a blank field)."""
    ok = np.isfinite(sigma) & (sigma > 0)
    n = np.round(np.log(np.where(ok, sigma, 1.0)) / np.log(base))
    return np.where(ok, np.clip(n, 0, largest), -1).astype(int)


def _exponent_text(n: int, width: int) -> str:
    return " " * width if n < 0 else f"{n:{width}d}"


def _header_lines(ds: xr.Dataset, times: np.ndarray, sats: list[str], pv: str, *, agency: str,
                  orbit_type: str, coordinate_system: str, data_used: str,
                  comments: tuple[str, ...]) -> list[str]:
    """The SP3-d header lines for ``ds``."""
    t0 = int(times[0])
    y, mo, d, h, mi, sec = _calendar(t0)
    interval = float(np.median(np.diff(times))) / 1e9 if times.size > 1 else 0.0
    week, sow_ns = divmod(t0 - _GPS0_NS, 7 * 86_400 * _NS)
    mjd, frac_ns = divmod(t0 - _MJD0_NS, 86_400 * _NS)
    out = [f"#d{pv}{y:4d} {mo:2d} {d:2d} {h:2d} {mi:2d} {sec} {times.size:7d} "
           f"{data_used:<5s} {coordinate_system:<5s} {orbit_type:<3s} {agency:<4s}",
           f"## {week:4d} {sow_ns / 1e9:15.8f} {interval:14.8f} {mjd:5d} "
           f"{frac_ns / (86_400 * _NS):15.13f}"]
    n_lines = max(5, math.ceil(len(sats) / _IDS_PER_LINE))
    ids = sats + ["  0"] * (n_lines * _IDS_PER_LINE - len(sats))
    if "orbit_accuracy_m" in ds:
        acc_mm = ds["orbit_accuracy_m"].values * 1e3
        with np.errstate(divide="ignore", invalid="ignore"):
            exps = np.where(np.isfinite(acc_mm) & (acc_mm > 0),
                            np.clip(np.round(np.log2(acc_mm)), 1, 99), 0).astype(int)
    else:
        exps = np.zeros(len(sats), dtype=int)
    accs = [f"{e:3d}" for e in exps] + ["  0"] * (n_lines * _IDS_PER_LINE - len(sats))
    for k in range(n_lines):
        chunk = slice(k * _IDS_PER_LINE, (k + 1) * _IDS_PER_LINE)
        lead = f"+  {len(sats):3d}   " if k == 0 else "+        "
        out.append(lead + "".join(ids[chunk]))
    for k in range(n_lines):
        out.append("++       " + "".join(accs[k * _IDS_PER_LINE:(k + 1) * _IDS_PER_LINE]))
    systems = {sv[0] for sv in sats}
    file_type = systems.pop() if len(systems) == 1 else "M"
    time_system = str(ds.attrs.get("time_system", "GPS"))
    if len(time_system) != 3:
        raise ValueError(f"time_system '{time_system}' must have 3 characters (e.g. 'GPS')")
    out += [f"%c {file_type:<2s} cc {time_system} ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc",
            "%c cc cc ccc ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc",
            (f"%f {_BASE_POS:10.7f} {_BASE_CLK:12.9f}  0.00000000000  0.000000000000000"
             if "pos_sigma_m" in ds else
             "%f  0.0000000  0.000000000  0.00000000000  0.000000000000000"),
            "%f  0.0000000  0.000000000  0.00000000000  0.000000000000000",
            "%i    0    0    0    0      0      0      0      0         0",
            "%i    0    0    0    0      0      0      0      0         0"]
    texts = ["Written by leopod", *comments]
    texts += [""] * (4 - len(texts))
    for text in texts:
        if len(text) > 77:
            raise ValueError(f"SP3-d comment longer than 77 characters: '{text}'")
        out.append(f"/* {text}".rstrip() if text else "/*")
    return out


def write_sp3(ds: xr.Dataset, path: str | Path, *, agency: str = "LEO",
              orbit_type: str = "FIT", coordinate_system: str = "ITRF",
              data_used: str = "u+U", comments: tuple[str, ...] = ()) -> None:
    """Write an SP3-d orbit file from a Dataset with the :func:`read_sp3` schema.

    Positions are written in km with 6 decimals (1 mm), velocities in dm/s with 6 decimals
    (1e-7 m/s), clocks in microseconds with 6 decimals (1 ps) and clock rates in 1e-4 µs/s
    with 6 decimals. NaN positions/velocities are written as the "bad or absent" value
    0.000000 and NaN clocks/rates as 999999.999999. With ``pos_sigma_m`` the P records carry
    the SP3-d accuracy exponents of each epoch, ``σ = 1.25**n`` mm for the positions and
    ``1.025**n`` ps for the clock (``clk_sigma_s``; blank without it), the nearest ``n`` in
    0–99 (0–999), and the first ``%f`` line gives these bases; without it the bases are 0 and
    no exponent is written. The ``++`` accuracy exponents come from ``orbit_accuracy_m`` when
    present, else 0 (unknown). A name ending in ``.gz`` is gzip-compressed.

    Parameters
    ----------
    ds : xarray.Dataset
        Needs ``pos_m`` (time, sv, xyz) [m]; optional ``clk_s`` (time, sv) [s], ``vel_m_s``
        (time, sv, xyz) [m s-1] (then V records are written), ``clk_rate_s_s`` (time, sv),
        ``pos_sigma_m`` (time, sv, xyz) [m] and ``clk_sigma_s`` (time, sv) [s] (record
        standard deviations, NaN: blank).
        ``attrs["time_system"]`` (3 characters, default "GPS") names the time system of ``time``.
    path : str or Path
        Output file.
    agency : str
        Generating agency, at most 4 characters.
    orbit_type : str
        Orbit type ("FIT", "EXT", "BCT", "HLM"), at most 3 characters.
    coordinate_system : str
        Reference frame label ("ITRF", "IGS20"), at most 5 characters.
    data_used : str
        Data-used descriptor ("u+U": undifferenced phase and code), at most 5 characters.
    comments : tuple of str
        Extra ``/*`` comment lines (at most 77 characters each). Inside a workflow job
        (:mod:`leopod.io.provenance`) a last one gives the SHA-256 of the campaign
        (``config hash <hex>``, as ``leopod_config_sha256`` of the job's netCDF files).

    Raises
    ------
    ValueError
        If ``ds`` lacks ``pos_m``, its times are not strictly increasing, a label is too long,
        a satellite id is not 3 characters, or a value overflows its SP3 field.
    """
    for label, value, width in (("agency", agency, 4), ("orbit_type", orbit_type, 3),
                                ("coordinate_system", coordinate_system, 5),
                                ("data_used", data_used, 5)):
        if len(value) > width:
            raise ValueError(f"{label} '{value}' is longer than {width} characters")
    if "pos_m" not in ds:
        raise ValueError("the Dataset has no 'pos_m' variable")
    pos = ds["pos_m"].transpose("time", "sv", "xyz").sel(xyz=list(_XYZ)).values / 1e3
    n_time, n_sat = pos.shape[:2]
    times = ds["time"].values.astype("datetime64[ns]").astype(np.int64)
    if n_time == 0 or (np.diff(times) <= 0).any():
        raise ValueError("'time' must be non-empty and strictly increasing")
    sats = [str(s) for s in ds["sv"].values]
    if any(len(s) != 3 for s in sats):
        raise ValueError(f"satellite ids must have 3 characters, got {sats}")
    clk = (ds["clk_s"].transpose("time", "sv").values * 1e6 if "clk_s" in ds
           else np.full((n_time, n_sat), np.nan))
    has_vel = "vel_m_s" in ds
    if has_vel:
        vel = ds["vel_m_s"].transpose("time", "sv", "xyz").sel(xyz=list(_XYZ)).values * 10.0
        rate = (ds["clk_rate_s_s"].transpose("time", "sv").values * 1e10
                if "clk_rate_s_s" in ds else np.full((n_time, n_sat), np.nan))

    exps = np.full((n_time, n_sat, 4), -1)
    if "pos_sigma_m" in ds:
        sig = ds["pos_sigma_m"].transpose("time", "sv", "xyz").sel(xyz=list(_XYZ)).values
        exps[:, :, :3] = _exponents(sig * 1e3, _BASE_POS, _MAX_EXP_POS)
        if "clk_sigma_s" in ds:
            exps[:, :, 3] = _exponents(ds["clk_sigma_s"].transpose("time", "sv").values * 1e12,
                                       _BASE_CLK, _MAX_EXP_CLK)

    job = current_job()
    if job is not None:
        comments = (*comments, f"config hash {job.config_sha256}")
    out = _header_lines(ds, times, sats, "V" if has_vel else "P", agency=agency,
                        orbit_type=orbit_type, coordinate_system=coordinate_system,
                        data_used=data_used, comments=comments)
    # every field formatted once, column by column; records assembled per epoch below
    pos_text = _fixed_texts(np.where(np.isfinite(pos).all(axis=2)[:, :, None], pos, 0.0),
                            14, 6, "position", sats)
    clk_text = _clock_texts(clk, "clock", sats)
    exp_text = [f" {_exponent_text(n[0], 2)} {_exponent_text(n[1], 2)} "
                f"{_exponent_text(n[2], 2)} {_exponent_text(n[3], 3)}"
                if max(n) >= 0 else "" for n in exps.reshape(-1, 4).tolist()]
    if has_vel:
        vel_text = _fixed_texts(np.where(np.isfinite(vel).all(axis=2)[:, :, None], vel, 0.0),
                                14, 6, "velocity", sats)
        rate_text = _clock_texts(rate, "clock rate", sats)
    for i in range(n_time):
        y, mo, d, h, mi, sec = _calendar(int(times[i]))
        out.append(f"*  {y:4d} {mo:2d} {d:2d} {h:2d} {mi:2d} {sec}")
        for k, sv in enumerate(sats):
            j = i * n_sat + k
            out.append(f"P{sv}{''.join(pos_text[3 * j:3 * j + 3])}{clk_text[j]}"
                       f"{exp_text[j]}".rstrip())
            if has_vel:
                out.append(f"V{sv}{''.join(vel_text[3 * j:3 * j + 3])}{rate_text[j]}")
    out.append("EOF")
    text = "\n".join(out) + "\n"
    write_text(path, text)
