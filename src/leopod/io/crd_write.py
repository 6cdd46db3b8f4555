"""Writer of ILRS Consolidated laser Ranging Data (CRD) normal-point files, versions 1 and 2.

Specification: "Consolidated Laser Ranging Data Format (CRD) Version 1.01" (Ricklefs & Moore,
ILRS 2009) and "ILRS CRD 2.01" (Ricklefs et al., ILRS 2019/2021). :func:`write_crd` writes
normal points (H1-H4, C0, 11, 20, H8 per session, H9 at the end) of a Dataset of the schema of
:func:`leopod.io.crd.read_crd`.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text
from leopod.io.crd import _DAY_NS, _NS

__all__ = ["write_crd"]

_MAX_WRITE_SESSION_NS = 12 * 3600 * _NS


#: Formats of the statistics that differ between versions: CRD 1 is fixed format (F9.1 ps,
#: F5.1 %, F4.0 %), CRD 2 is free format and keeps more decimals.
_NUMBER_FORMATS = {1: {"ps": "9.1f", "rate": "5.1f", "humidity": "4.0f"},
                   2: {"ps": "9.3f", "rate": "6.2f", "humidity": "5.1f"}}
_V1_WIDTHS = {"station_name": 10, "satellite": 10, "system_config": 4}
_WRITE_REQUIRED = ("time", "tof_s", "pass_id", "station", "satellite", "ilrs_id",
                   "wavelength_nm")
_WRITE_DEFAULTS = {
    "station_name": None, "system_number": 1, "occupancy_number": 1, "time_scale": 4,
    "norad_id": -1, "data_release": 0, "range_type": 2, "data_quality_alert": 0,
    "refraction_applied": 0, "com_applied": 0, "amplitude_corr_applied": 0,
    "station_delay_applied": 1, "spacecraft_delay_applied": 0, "system_config": "std",
    "epoch_event": 2, "np_window_s": np.nan, "n_raw": -1, "bin_rms_s": np.nan,
    "bin_skew": np.nan, "bin_kurtosis": np.nan, "bin_peak_minus_mean_s": np.nan,
    "return_rate_pct": np.nan, "detector_channel": 0, "snr": np.nan,
    "pressure_hpa": np.nan, "temperature_k": np.nan, "humidity_pct": np.nan,
}


def write_crd(ds: xr.Dataset, path: str | Path, version: int = 2, *,
              production_time: _dt.datetime | None = None) -> None:
    """Write normal points as a CRD file that :func:`read_crd` reads back.

    One block H1, H2, H3, H4, C0 (one per system configuration), then per point a record 11
    and, where pressure, temperature and humidity are all finite, a record 20 at the same
    epoch (origin 1, "interpolated"), H8; H9 at the end. Epochs are written to 1 ns (12
    decimals of the seconds of day), times of flight to 1 ps (12 decimals), pressure and
    temperature to 0.01; bin RMS and peak-mean to 0.001 ps, return rate and SNR to 0.01,
    humidity to 0.1 % in CRD 2; the CRD 1 fixed widths (0.1 ps, 0.1 %, 1 % humidity) in CRD 1.
    ``pass_id`` is not written: reading the file back numbers the sessions 0, 1, ... in
    the order of the input's ``pass_id`` values.

    Parameters
    ----------
    ds : xarray.Dataset
        Dimension ``point`` with at least ``time``, ``tof_s`` [s], ``pass_id``, ``station``
        (4-digit CDP pad id), ``satellite``, ``ilrs_id`` and ``wavelength_nm`` [nm]. Any other
        variable of the :func:`read_crd` schema is used when present, otherwise defaults:
        station_name = station, system/occupancy number 1, time_scale 4 (UTC(GPS)),
        range_type 2, station_delay_applied 1, other H4 flags 0, system_config "std",
        epoch_event 2, detector_channel 0, statistics "na" (CRD 2) or -1 (CRD 1).
        H3 is written with SIC "na" (CRD 1: 0), spacecraft time scale 0, target type 1
        (passive retro-reflector) and (CRD 2) location 1 (Earth orbit).
    path : str or Path
        Output file.
    version : {1, 2}
        CRD version of the output (both use blank-separated fields in the CRD 1 order).
    production_time : datetime, optional
        H1 production date and hour; default the current UTC time.

    Raises
    ------
    ValueError
        Missing required variable, NaT time, non-finite time of flight or wavelength, a
        station id that is not 4 digits, a name containing blanks, a session longer than
        12 h (it could not be read back unambiguously), unsupported version.
    """
    if version not in (1, 2):
        raise ValueError(f"CRD version must be 1 or 2, not {version}")
    missing = [name for name in _WRITE_REQUIRED if name not in ds.variables]
    if missing:
        raise ValueError(f"write_crd needs the variables {missing}")
    cols = _write_columns(ds)
    if version == 1:
        for name, width in _V1_WIDTHS.items():
            bad = [v for v in cols[name] if len(v) > width]
            if bad:
                raise ValueError(f"write_crd: CRD 1 allows {width} characters for {name}, "
                                 f"'{bad[0]}' is longer")
    prod = production_time or _dt.datetime.now(_dt.UTC)
    out = []
    for pid in np.unique(cols["pass_id"]):
        idx = np.flatnonzero(cols["pass_id"] == pid)
        idx = idx[np.argsort(cols["time"][idx], kind="stable")]
        out += _session_lines(cols, idx, version, prod)
    out.append("H9")
    write_text(path, "\n".join(out) + "\n")


def _write_columns(ds: xr.Dataset) -> dict:
    """Per-point numpy arrays of every field written, with defaults, checked."""
    n = ds.sizes.get("point", 0)
    cols = {name: np.asarray(ds[name].values) for name in _WRITE_REQUIRED}
    for name, default in _WRITE_DEFAULTS.items():
        if name in ds.variables:
            cols[name] = np.asarray(ds[name].values)
        elif default is None:
            cols[name] = cols["station"]
        else:
            cols[name] = np.full(n, default)
    time = cols["time"].astype("datetime64[ns]")
    if np.isnat(time).any():
        raise ValueError("write_crd: time contains NaT")
    cols["time"] = time.astype(np.int64)
    for name in ("tof_s", "wavelength_nm"):
        if not np.isfinite(cols[name].astype(float)).all():
            raise ValueError(f"write_crd: {name} must be finite")
    for name in ("station", "station_name", "satellite", "ilrs_id", "system_config"):
        cols[name] = cols[name].astype(str)
        bad = [s for s in cols[name] if not s or any(c.isspace() for c in s)]
        if bad:
            raise ValueError(f"write_crd: {name} '{bad[0]}' is empty or contains blanks")
    bad = [s for s in cols["station"] if not (s.isdigit() and len(s) == 4)]
    if bad:
        raise ValueError(f"write_crd: station '{bad[0]}' is not a 4-digit CDP pad id")
    return cols


def _fmt(value: float, spec: str, version: int) -> str:
    """A number, or the "not available" token of the version (na / -1) for NaN or -1 ints."""
    if isinstance(value, (int, np.integer)):
        if value == -1:
            return "na" if version == 2 else "-1"
        return format(int(value), spec)
    if not np.isfinite(value):
        return "na" if version == 2 else "-1"
    return format(float(value), spec)


def _sod_text(sod_ns: int) -> str:
    """Seconds of day with 12 decimals from an integer number of nanoseconds."""
    sec, ns = divmod(int(sod_ns), _NS)
    return f"{sec:5d}.{ns:09d}000"


def _session_lines(c: dict, idx: np.ndarray, version: int, prod: _dt.datetime) -> list[str]:
    """The records of one session (points ``idx`` sorted by time)."""
    t = c["time"][idx]
    start = int(t[0]) - int(t[0]) % _NS
    stop = int(t[-1]) + (-int(t[-1])) % _NS
    if stop - start >= _MAX_WRITE_SESSION_NS:
        hours = (stop - start) / 3.6e12
        raise ValueError(f"write_crd: pass {c['pass_id'][idx[0]]} spans {hours:.1f} h; "
                         "sessions must be shorter than 12 h")
    day = start - start % _DAY_NS
    k = idx[0]
    d0 = _ns_to_datetime(start)
    d1 = _ns_to_datetime(stop)
    fl = [int(c[n][k]) for n in ("data_release", "refraction_applied", "com_applied",
                                 "amplitude_corr_applied", "station_delay_applied",
                                 "spacecraft_delay_applied", "range_type",
                                 "data_quality_alert")]
    norad = _fmt(int(c["norad_id"][k]), "8d", version)
    sic = "na" if version == 2 else "0"
    out = [
        f"H1 CRD {version:2d} {prod.year:4d} {prod.month:2d} {prod.day:2d} {prod.hour:2d}",
        f"H2 {c['station_name'][k]:<10s} {c['station'][k]} {int(c['system_number'][k]):2d} "
        f"{int(c['occupancy_number'][k]):2d} {int(c['time_scale'][k]):2d}"
        + (" na" if version == 2 else ""),
        f"H3 {c['satellite'][k]:<10s} {c['ilrs_id'][k]:>8s} {sic:>4s} {norad:>8s} 0 1"
        + (" 1" if version == 2 else ""),
        "H4  1 " + _h4_epoch(d0) + " " + _h4_epoch(d1) + f" {fl[0]:2d} "
        + " ".join(str(f) for f in fl[1:]),
    ]
    configs = dict.fromkeys(c["system_config"][idx])
    for cfg in configs:
        wl = c["wavelength_nm"][idx][c["system_config"][idx] == cfg][0]
        out.append(f"C0 0 {float(wl):.3f} {cfg}")
    f = _NUMBER_FORMATS[version]
    for j, tj in zip(idx, t):
        sod = _sod_text((int(tj) - day) % _DAY_NS)
        rec = (f"11 {sod:>18s} {float(c['tof_s'][j]):18.12f} {c['system_config'][j]} "
               f"{int(c['epoch_event'][j])} {_fmt(c['np_window_s'][j], '6.1f', version)} "
               f"{_fmt(int(c['n_raw'][j]), '6d', version)} "
               f"{_fmt(c['bin_rms_s'][j] * 1e12, f['ps'], version)} "
               f"{_fmt(c['bin_skew'][j], '7.3f', version)} "
               f"{_fmt(c['bin_kurtosis'][j], '7.3f', version)} "
               f"{_fmt(c['bin_peak_minus_mean_s'][j] * 1e12, f['ps'], version)} "
               f"{_fmt(c['return_rate_pct'][j], f['rate'], version)} "
               f"{_fmt(int(c['detector_channel'][j]), 'd', version)}")
        if version == 2:
            rec += f" {_fmt(c['snr'][j], f['rate'], version)}"
        out.append(rec)
        met = [float(c[n][j]) for n in ("pressure_hpa", "temperature_k", "humidity_pct")]
        if all(np.isfinite(met)):
            out.append(f"20 {sod:>18s} {met[0]:7.2f} {met[1]:6.2f} "
                       f"{format(met[2], f['humidity'])} 1")
    out.append("H8")
    return out


def _ns_to_datetime(t_ns: int) -> _dt.datetime:
    return _dt.datetime(1970, 1, 1) + _dt.timedelta(microseconds=t_ns // 1000)


def _h4_epoch(d: _dt.datetime) -> str:
    return f"{d.year:4d} {d.month:2d} {d.day:2d} {d.hour:2d} {d.minute:2d} {d.second:2d}"
