"""Writer of RINEX observation files (versions 2.11 and 3.04).

Specifications: "RINEX: The Receiver Independent Exchange Format Version 2.11" (Gurtner and
Estey, 2007/2012) and "RINEX Version 3.04" (IGS/RTCM-SC104, 2018). The Dataset written is the
one returned by :func:`leopod.io.rinex_obs.read_rinex_obs` (schema in :mod:`leopod.io.rinex_obs`).
"""

from __future__ import annotations

import datetime as _dt
import gzip
import logging
import math
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import creation_time
from leopod.io.rinex_obs import _TYPES_V2, _TYPES_V3, _V2_OBS_PER_LINE, _W

__all__ = ["write_rinex_obs"]

log = logging.getLogger(__name__)


_HEADER_KEYS = ("marker_name", "marker_number", "marker_type", "observer", "agency",
                "receiver_number", "receiver_type", "receiver_version", "antenna_number",
                "antenna_type", "approx_position_xyz_m", "antenna_delta_hen_m", "program",
                "run_by", "comments", "created")
_CODE_NAME = re.compile(r"^[A-Z][0-9A-Z][0-9A-Z]?$")


def _hl(text: str, label: str) -> str:
    """One header line: 60 columns of content, then the label."""
    return f"{text:<60.60}{label}"


def _header_values(ds: xr.Dataset, header: Mapping | None) -> dict:
    """Header values: Dataset attributes overridden by ``header``."""
    header = dict(header or {})
    unknown = set(header) - set(_HEADER_KEYS)
    if unknown:
        raise ValueError(f"unknown header keys {sorted(unknown)} (known: {_HEADER_KEYS})")
    values = {k: str(ds.attrs.get(k, "")) for k in _HEADER_KEYS}
    values["program"] = "leopod"
    values["comments"] = []
    values["created"] = None
    values.update(header)
    if isinstance(values["comments"], str):
        values["comments"] = [values["comments"]]
    return values


def _xyz_text(text, name: str) -> str:
    """Three F14.4 numbers from an "x y z" string or a sequence (blank -> zeros)."""
    parts = text.split() if isinstance(text, str) else list(text)
    if not parts:
        parts = [0.0, 0.0, 0.0]
    try:
        xyz = [float(p) for p in parts]
    except ValueError:
        raise ValueError(f"{name} must hold three numbers, not {text!r}") from None
    if len(xyz) != 3 or not all(math.isfinite(v) and abs(v) < 1e9 for v in xyz):
        raise ValueError(f"{name} must hold three finite numbers below 1e9 m, not {text!r}")
    return "".join(f"{v:14.4f}" for v in xyz)


def _observation_codes(ds: xr.Dataset) -> list[str]:
    """Names of the observation variables of a Dataset of this module's schema."""
    return [str(name) for name, var in ds.data_vars.items()
            if var.dims == ("time", "sv") and _CODE_NAME.match(str(name))
            and np.issubdtype(var.dtype, np.floating)]


def _write_plan(ds: xr.Dataset, v2: bool, systems: list[str]) -> dict[str, list[tuple]]:
    """Per system, the (file code, Dataset variable) pairs to write, in header order."""
    from leopod.signals import RINEX2_TO_RINEX3

    to_v2 = {v: k for k, v in RINEX2_TO_RINEX3["G"].items()}
    codes = _observation_codes(ds)
    sv = ds["sv"].values.astype(str)
    plan = {}
    for system in systems:
        cols = np.char.startswith(sv, system)
        listed = str(ds.attrs.get(f"obs_types_{system}", "")).split()
        names = [c for c in listed if c in codes] or \
            [c for c in codes if np.isfinite(ds[c].values[:, cols]).any()]
        pairs = []
        for name in names:
            if v2:
                file_code = name if len(name) == 2 else to_v2.get(name)
            else:
                file_code = name if len(name) == 3 else \
                    RINEX2_TO_RINEX3.get(system, {}).get(name)
            if file_code is None:
                raise ValueError(f"observation '{name}' of system {system} has no RINEX "
                                 f"{'2' if v2 else '3'} name; drop it or rename it")
            pairs.append((file_code, name))
        plan[system] = pairs
    return plan


def _record_texts(ds: xr.Dataset, plan: dict) -> np.ndarray:
    """Fixed-width observation text of every (time, sv) cell, None where nothing to write."""
    sv = ds["sv"].values.astype(str)
    texts = np.full((ds.sizes["time"], sv.size), None, dtype=object)
    for system, pairs in plan.items():
        if not pairs:
            continue
        cols = np.nonzero(np.char.startswith(sv, system))[0]
        names = [name for _, name in pairs]
        vals = np.stack([ds[n].values[:, cols] for n in names], axis=-1)
        present = np.isfinite(vals)
        fits = (vals > -999999999.9995) & (vals < 9999999999.9995)
        if (present & ~fits).any():
            t, s, j = np.argwhere(present & ~fits)[0]
            raise ValueError(f"{names[j]} of {sv[cols[s]]} at {ds.time.values[t]} = "
                             f"{vals[t, s, j]} does not fit the F14.3 field")
        inds = []
        for suffix in ("_lli", "_ssi"):
            ind = np.stack([ds[n + suffix].values[:, cols] if n + suffix in ds
                            else np.zeros(vals.shape[:2], int) for n in names], axis=-1)
            ind = np.where(present, ind, 0)
            if ((ind < -1) | (ind > 9)).any():
                raise ValueError(f"{suffix[1:].upper()} indicators must be -1 or 0-9")
            inds.append(np.maximum(ind, 0))
        record = _cell_bytes(vals, present, inds[0], inds[1])
        for t, s in np.argwhere(present.any(axis=2)):
            texts[t, cols[s]] = record[t, s].decode("latin-1")
    return texts


def _cell_bytes(vals: np.ndarray, present: np.ndarray, lli: np.ndarray,
                ssi: np.ndarray) -> np.ndarray:
    """Fixed-width fields (F14.3, LLI, SSI; blanks where absent) of every observation of a
    (time, sv, code) block, joined per (time, sv): ``bytes`` array of shape (time, sv).

    The values are formatted by one ``%`` operation over all of them (the same text as
    ``f"{v:14.3f}"`` per value, three times faster for a simulated day) and placed into a
    byte grid; the indicators are digits, 0 a blank.
    """
    n_t, n_s, n_c = vals.shape
    grid = np.full((n_t, n_s, n_c, _W), ord(" "), dtype=np.uint8)
    shown = vals[present]
    text = ("%14.3f" * shown.size % tuple(shown.tolist())).encode("latin-1")
    grid[present, :14] = np.frombuffer(text, dtype=np.uint8).reshape(-1, 14)
    for column, ind in ((14, lli), (15, ssi)):
        grid[present, column] = np.where(ind[present] > 0, ord("0") + ind[present], ord(" "))
    return grid.reshape(n_t, n_s, n_c * _W).view(f"S{n_c * _W}")[..., 0]


def _time_fields(times: np.ndarray) -> list[tuple]:
    """(year, month, day, hour, minute, seconds) of each time, rounded to 100 ns."""
    ns = times.astype("datetime64[ns]").astype(np.int64)
    ns = (ns + 50) // 100 * 100
    fields = []
    for t in ns:
        whole, frac = divmod(int(t), 60_000_000_000)
        base = _dt.datetime(1970, 1, 1) + _dt.timedelta(minutes=whole)
        fields.append((base.year, base.month, base.day, base.hour, base.minute, frac * 1e-9))
    return fields


def _header_lines(ds, meta: dict, plan: dict, v2: bool, first: tuple) -> list[str]:
    """The header section of the output file."""
    systems = list(plan)
    file_sys = "G (GPS)" if v2 else (systems[0] if len(systems) == 1 else "M")
    now = creation_time(meta["created"]).strftime("%Y%m%d %H%M%S UTC")
    out = [_hl(f"{2.11 if v2 else 3.04:9.2f}{'':11}{'OBSERVATION DATA':<20}{file_sys:<20}",
               "RINEX VERSION / TYPE"),
           _hl(f"{meta['program']:<20.20}{meta['run_by']:<20.20}{now:<20}",
               "PGM / RUN BY / DATE")]
    out += [_hl(c, "COMMENT") for c in meta["comments"]]
    out.append(_hl(meta["marker_name"], "MARKER NAME"))
    if meta["marker_number"]:
        out.append(_hl(meta["marker_number"], "MARKER NUMBER"))
    if meta["marker_type"] and not v2:
        out.append(_hl(meta["marker_type"], "MARKER TYPE"))
    out += [_hl(f"{meta['observer']:<20.20}{meta['agency']:<40.40}", "OBSERVER / AGENCY"),
            _hl(f"{meta['receiver_number']:<20.20}{meta['receiver_type']:<20.20}"
                f"{meta['receiver_version']:<20.20}", "REC # / TYPE / VERS"),
            _hl(f"{meta['antenna_number']:<20.20}{meta['antenna_type']:<20.20}",
                "ANT # / TYPE"),
            _hl(_xyz_text(meta["approx_position_xyz_m"], "approx_position_xyz_m"),
                "APPROX POSITION XYZ"),
            _hl(_xyz_text(meta["antenna_delta_hen_m"], "antenna_delta_hen_m"),
                "ANTENNA: DELTA H/E/N")]
    if v2:
        codes = [c for c, _ in plan["G"]]
        out.append(_hl(f"{1:6d}{1:6d}", "WAVELENGTH FACT L1/2"))
        for k in range(0, max(len(codes), 1), 9):
            lead = f"{len(codes):6d}" if k == 0 else " " * 6
            out.append(_hl(lead + "".join(f"{c:>6}" for c in codes[k:k + 9]), _TYPES_V2))
    else:
        for system, pairs in plan.items():
            codes = [c for c, _ in pairs]
            for k in range(0, max(len(codes), 1), 13):
                lead = f"{system}  {len(codes):3d}" if k == 0 else " " * 6
                out.append(_hl(lead + "".join(f" {c}" for c in codes[k:k + 13]), _TYPES_V3))
    interval = float(ds.attrs.get("interval_s", math.nan))
    if math.isfinite(interval) and 0 < interval < 1e6:
        out.append(_hl(f"{interval:10.3f}", "INTERVAL"))
    time_system = str(ds.attrs.get("time_system", "GPS"))
    out.append(_hl(f"{first[0]:6d}{first[1]:6d}{first[2]:6d}{first[3]:6d}{first[4]:6d}"
                   f"{first[5]:13.7f}{'':5}{time_system:<3.3}", "TIME OF FIRST OBS"))
    if not v2:
        out += [_hl(system, "SYS / PHASE SHIFT") for system in plan]
    out.append(_hl("", "END OF HEADER"))
    return out


def _clock_text(clock: float, v2: bool) -> str:
    """Receiver clock offset field (F12.9 in RINEX 2, 6X,F15.12 in RINEX 3); '' if NaN."""
    if not math.isfinite(clock):
        return ""
    text = f"{clock:12.9f}" if v2 else f"{'':6}{clock:15.12f}"
    if len(text) > (12 if v2 else 21):
        raise ValueError(f"receiver clock offset {clock} s does not fit the RINEX field")
    return text


def _epoch_lines(fields, flag: int, clock: float, svs: list, texts: list, v2: bool) -> list:
    """Epoch record plus satellite records of one epoch."""
    y, mo, d, h, mi, sec = fields
    if v2:
        head = f" {y % 100:02d} {mo:2d} {d:2d} {h:2d} {mi:2d}{sec:11.7f}  {flag:1d}{len(svs):3d}"
        ids = "".join(svs)
        out = [(head + ids[:36]).ljust(68) + _clock_text(clock, True)]
        out += [" " * 32 + ids[k:k + 36] for k in range(36, len(ids), 36)]
        step = _W * _V2_OBS_PER_LINE
        for text in texts:
            out += [text[k:k + step].rstrip() for k in range(0, len(text), step)]
        return [line.rstrip() for line in out]
    head = f"> {y:4d} {mo:02d} {d:02d} {h:02d} {mi:02d}{sec:11.7f}  {flag:1d}{len(svs):3d}"
    return [head + _clock_text(clock, False)] + \
        [(sv + text).rstrip() for sv, text in zip(svs, texts)]


def write_rinex_obs(ds: xr.Dataset, path: str | Path, version: float = 3.04,
                    header: Mapping | None = None) -> Path:
    """Write a Dataset of the :func:`read_rinex_obs` schema as a RINEX observation file.

    Parameters
    ----------
    ds : xarray.Dataset
        Observations (time, sv) as described in the module docstring; ``<code>_lli``,
        ``<code>_ssi``, ``epoch_flag`` and ``rx_clock_offset_s`` are optional. RINEX 2 names
        are mapped to RINEX 3 codes for version 3.04 (and back for 2.11) with
        :data:`leopod.signals.RINEX2_TO_RINEX3`.
    path : str or Path
        Output file, written atomically; gzip-compressed if it ends in ``.gz``.
    version : float
        3.04 (systems G, E, C, J, I, S) or 2.11 (GPS only).
    header : mapping, optional
        Header values overriding ``ds.attrs``: marker_name, marker_number, marker_type,
        observer, agency, receiver_number, receiver_type, receiver_version, antenna_number,
        antenna_type, approx_position_xyz_m, antenna_delta_hen_m (``"x y z"`` [m] or three
        numbers), program, run_by, comments (str or list of str), created (datetime of
        "PGM / RUN BY / DATE", UTC; default :func:`leopod.io._text.creation_time`).

    Returns
    -------
    Path
        The file written. Values are written as F14.3 (1 mm, 1e-3 cycle); epochs without any
        observation are left out; the observation list of a system is the codes of
        ``attrs["obs_types_<sys>"]`` present in ``ds`` (header order), else the codes with
        data for that system (variable order).

    Raises
    ------
    ValueError
        Unsupported version or system, a code without a name in the requested version, a
        value that does not fit its field, unknown ``header`` keys.
    """
    from leopod.io.netcdf import atomic_path

    if round(float(version), 2) not in (2.11, 3.04):
        raise ValueError(f"can write RINEX 2.11 or 3.04, not {version}")
    v2 = round(float(version), 2) == 2.11
    meta = _header_values(ds, header)
    sv = [str(s) for s in ds["sv"].values]
    systems = sorted({s[0] for s in sv})
    allowed = "G" if v2 else "GECJIS"
    if set(systems) - set(allowed):
        raise ValueError(f"RINEX {version} output supports systems {allowed!r}, the data "
                         f"have {systems} (GLONASS would need frequency-slot records)")
    plan = _write_plan(ds, v2, systems or ["G"])
    texts = _record_texts(ds, plan)
    flags = ds["epoch_flag"].values if "epoch_flag" in ds else np.zeros(ds.sizes["time"])
    clocks = ds["rx_clock_offset_s"].values if "rx_clock_offset_s" in ds else \
        np.full(ds.sizes["time"], np.nan)
    rows = [t for t in range(texts.shape[0]) if any(x is not None for x in texts[t])]
    if not rows:
        raise ValueError("the Dataset holds no observation to write")
    times = _time_fields(ds["time"].values[rows])
    body = []
    for t, fields in zip(rows, times):
        cols = [k for k in range(len(sv)) if texts[t, k] is not None]
        flag = int(flags[t]) if int(flags[t]) in (0, 1) else 0
        body += _epoch_lines(fields, flag, float(clocks[t]), [sv[k] for k in cols],
                             [texts[t, k] for k in cols], v2)
    lines = _header_lines(ds, meta, plan, v2, times[0]) + body
    data = ("\n".join(lines) + "\n").encode("latin-1")
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_bytes(gzip.compress(data, compresslevel=6) if path.suffix == ".gz" else data)
    log.info("wrote %s: RINEX %s, %d epochs", path, version, len(rows))
    return path
