"""Baselines of a formation pair against each other, the simulated truth and a measured range.

A baseline solution (reduced-dynamic, :mod:`leopod.estimation.baseline`, or kinematic,
:mod:`leopod.estimation.kinematic_baseline`) is an ITRF vector follower − leader per epoch; two
solutions or a solution and the truth are compared as the difference vector in the leader's
radial, along-track, cross-track frame (Zhang et al. 2024, Table 6: dynamic − kinematic).
Against an inter-satellite range (K-band ranging of GRACE; Kroes et al. 2005), the length
``|Δr|`` of a baseline is compared with the range at the same epochs: a check along the line of
sight only, independent of GNSS. Two consecutive daily solutions over the 6 h their 30-h arcs
share give the baseline overlap (Zhang et al. 2024: 0.5-0.8 mm 3D for the DD-fixed dynamic
baselines; :func:`baseline_overlap`), the internal consistency check of the orbit overlaps
(:mod:`leopod.validation.overlap`) applied to baselines. The campaign summary of a pair (:func:`formation_day_row`,
:func:`formation_table`) puts the DD fixing, the baselines against the truth, kinematic −
dynamic and the range checks of each day in one table, as paper 003's Tables 4-6 do.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np
import pandas as pd
import xarray as xr

from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.signals import system_of

__all__ = ["baseline_overlap", "burn_windows", "difference_rtn", "formation_day_row",
           "formation_table", "mutual_differences", "range_residuals", "rms_rtn",
           "sd_residual_rms",
           "truth_baseline_itrf"]


def truth_baseline_itrf(truth_a, truth_b, times: np.ndarray) -> np.ndarray:
    """True baseline B − A (ITRF) [m], shape (m, 3), of a simulated pair at ``times`` (epochs
    of the files, GPS time), from the simulator's daily truth netCDF files (full precision: the
    truth SP3 rounds each coordinate to 1 mm, 0.7 mm 3D RMS in a baseline)."""
    pos = []
    for path in (truth_a, truth_b):
        with xr.open_dataset(path) as truth:
            pos.append(truth.pos_itrf_m.sel(time=times).values)
    return pos[1] - pos[0]


def difference_rtn(baseline_itrf_m: np.ndarray, reference_itrf_m: np.ndarray,
                   times: np.ndarray, leader_gcrf: np.ndarray) -> np.ndarray:
    """``baseline − reference`` in the leader's R, T, N [m], shape (m, 3).

    Parameters
    ----------
    baseline_itrf_m, reference_itrf_m : ndarray, shape (m, 3)
        Two baselines (ITRF) [m].
    times : ndarray of datetime64, shape (m,)
    leader_gcrf : ndarray, shape (m, 6)
        Leader's GCRF position [m] and velocity [m/s] (defines R, T, N).
    """
    d_gcrf, _ = itrf_to_gcrf(times, baseline_itrf_m - reference_itrf_m)   # a rotation
    return np.einsum("mij,mj->mi", rtn_matrix(leader_gcrf[:, :3], leader_gcrf[:, 3:]), d_gcrf)


def rms_rtn(diff_rtn_m: np.ndarray) -> dict[str, float]:
    """RMS per component and 3D [m] over the finite rows of (m, 3) differences, and their
    count: keys ``R``, ``T``, ``N``, ``3D``, ``n``."""
    ok = np.isfinite(diff_rtn_m).all(axis=1)
    if not ok.any():
        return {"R": np.nan, "T": np.nan, "N": np.nan, "3D": np.nan, "n": 0}
    rms = np.sqrt(np.mean(diff_rtn_m[ok] ** 2, axis=0))
    return {"R": float(rms[0]), "T": float(rms[1]), "N": float(rms[2]),
            "3D": float(np.sqrt(np.sum(rms**2))), "n": int(ok.sum())}


def range_residuals(baseline_itrf_m: np.ndarray, times: np.ndarray,
                    range_m: np.ndarray, range_times: np.ndarray) -> np.ndarray:
    """``|Δr| − range`` [m] at the baseline epochs that the range series has (m,), NaN
    elsewhere or where the baseline is NaN.

    Parameters
    ----------
    baseline_itrf_m : ndarray, shape (m, 3)
        Baseline vectors [m] (any frame: the length is compared).
    times : ndarray of datetime64, shape (m,)
    range_m : ndarray, shape (r,)
        Measured or simulated range [m].
    range_times : ndarray of datetime64, shape (r,)
        Its epochs (same time scale as ``times``).
    """
    rt = np.asarray(range_times, dtype="datetime64[ns]")
    t = np.asarray(times, dtype="datetime64[ns]")
    k = np.clip(np.searchsorted(rt, t), 0, max(rt.size - 1, 0))
    out = np.full(t.size, np.nan)
    if rt.size == 0:
        return out
    hit = rt[k] == t
    out[hit] = np.linalg.norm(baseline_itrf_m[hit], axis=1) - range_m[k[hit]]
    return out


def sd_residual_rms(residuals_a: xr.Dataset, residuals_b: xr.Dataset
                    ) -> dict[str, tuple[float, int]]:
    """RMS of the receiver single differences B − A of the post-fit residuals, per GNSS system
    and observable: ``{"<system>_<phase|code>": (rms [m], count)}``.

    The residuals of the two satellites' solutions (:func:`leopod.estimation.outputs.
    residual_dataset`: ionosphere-free, NaN where not used) are differenced at the epochs and
    GNSS satellites both used: the residuals of the receiver-SD observations that Zhang et al.
    (2024, Table 1 and Fig. 3) give for their baselines (GPS 4.4 mm, BDS-3 2.5 mm phase), here
    for solutions that fit each satellite's undifferenced data (the common GNSS orbit and clock
    errors cancel in the difference as they do in SD observations).

    Parameters
    ----------
    residuals_a, residuals_b : xarray.Dataset
        On (time, sv) with ``phase_residual_m`` and ``code_residual_m`` [m].
    """
    times = np.intersect1d(residuals_a.time.values, residuals_b.time.values)
    sv = np.intersect1d(residuals_a.sv.values, residuals_b.sv.values)
    a = residuals_a.sel(time=times, sv=sv)
    b = residuals_b.sel(time=times, sv=sv)
    systems = system_of(sv)
    out = {}
    for x in sorted(set(systems)):
        cols = systems == x
        for kind in ("phase", "code"):
            var = f"{kind}_residual_m"
            sd = b[var].values[:, cols] - a[var].values[:, cols]
            sd = sd[np.isfinite(sd)]
            out[f"{x}_{kind}"] = (float(np.sqrt(np.mean(sd**2))) if sd.size else np.nan,
                                  int(sd.size))
    return out


def _in_day(ds: xr.Dataset) -> xr.Dataset:
    """The day's epochs of a baseline file (all of them in files without ``in_day``)."""
    return ds.isel(time=ds.in_day.values == 1) if "in_day" in ds else ds


def mutual_differences(lines: Mapping[str, xr.Dataset]) -> dict[str, dict[str, float]]:
    """RMS R/T/N/3D [m] of the differences between the DD-fixed reduced-dynamic baselines of
    the solutions of one pair-day (Zhang et al. 2024, Fig. 5: G/C, G/GC and C/GC), over the
    day's epochs they share: ``{"<a>_minus_<b>": rms_rtn}`` for each two labels in order.

    Parameters
    ----------
    lines : mapping
        ``{label: baseline dataset}`` (output of the baseline rule, ``baseline_rtn_m`` in its
        leader's RTN), e.g. ``{"G+C": ..., "G": ..., "C": ...}``.

    Notes
    -----
    The RTN components are differenced directly: the leader orbits of two solutions differ by
    millimetres, their RTN axes by < 1e-9 rad, i.e. < 5 µm on a 5-km baseline.
    """
    days = {k: _in_day(v) for k, v in lines.items()}
    labels = list(days)
    out = {}
    for i, la in enumerate(labels):
        for lb in labels[i + 1:]:
            a, b = days[la], days[lb]
            _, ia, ib = np.intersect1d(a.time.values, b.time.values, return_indices=True)
            out[f"{la}_minus_{lb}"] = rms_rtn(a.baseline_rtn_m.values[ia]
                                              - b.baseline_rtn_m.values[ib])
    return out


def _pct(value) -> float:
    return 100.0 * float(value) if value is not None else np.nan


def formation_day_row(baseline: xr.Dataset, *, kinematic: xr.Dataset | None = None,
                      ranges: xr.Dataset | None = None, overlap: xr.Dataset | None = None,
                      wrong: Mapping | None = None, lines: Mapping | None = None
                      ) -> dict[str, tuple[float, str, str]]:
    """The figures of one pair-day: ``{column: (value, unit, description)}``.

    Parameters
    ----------
    baseline : xarray.Dataset
        Output of the baseline rule (attributes: DD fixing rates overall and per system,
        ``n_dd_constraints_used``, ``<float|fixed>_rms_<r|t|n|3d>_m`` against the truth,
        ``<float|fixed>_sd_<system>_<phase|code>_rms_m`` of the SD residuals).
    kinematic : xarray.Dataset, optional
        Output of the kinematic_baseline rule (``rms_minus_truth_m``, ``rms_minus_dynamic_m``).
    ranges : xarray.Dataset, optional
        Output of the range_check rule (``std_m``, ``mean_m`` per solution).
    overlap : xarray.Dataset, optional
        Output of the baseline_overlap rule for this day and the next (``rms_m`` per
        solution and component).
    wrong : mapping, optional
        Wrong DD fixes against the simulator's integers per system and ``all``
        (:func:`leopod.simulate.dd_truth.wrong_dd_fixes`).
    lines : mapping, optional
        ``{label: baseline dataset}`` of the pair's solutions (e.g. G+C, G, C) for their
        mutual differences (:func:`mutual_differences`).
    """
    t = baseline.attrs
    row: dict[str, tuple[float, str, str]] = {
        "dd_wl_rate": (_pct(t.get("wl_fixing_rate")), "%",
                       "DD WL fixing rate (graph rank of the fixed over all independent DDs)"),
        "dd_nl_rate": (_pct(t.get("nl_fixing_rate")), "%", "DD NL fixing rate (graph rank)"),
    }
    systems = sorted({k.split("_", 1)[0] for k in t if k.endswith("_nl_fixing_rate")
                      and len(k.split("_", 1)[0]) == 1})
    for x in systems:
        row[f"dd_nl_rate_{x}"] = (_pct(t.get(f"{x}_nl_fixing_rate")), "%",
                                  f"DD NL fixing rate of {x}")
    row["dd_constraints"] = (float(t.get("n_dd_constraints_used", np.nan)), "1",
                             "fixed DDs constraining the baseline")
    if wrong is not None:
        for kind in ("wl", "nl", "constrained"):
            key = f"{kind}_wrong"
            row[f"dd_{kind}_wrong"] = (float(wrong["all"][key]), "1",
                                       f"wrong {kind.upper() if kind != 'constrained' else kind}"
                                       " DD fixes against the simulator's integers")
    for label in ("float", "fixed"):
        name = "DD-fixed" if label == "fixed" else label
        if f"{label}_rms_3d_m" in t:
            for c in ("r", "t", "n", "3d"):
                row[f"dynamic_{label}_vs_truth_{c}"] = (
                    1e3 * float(t[f"{label}_rms_{c}_m"]), "mm",
                    f"reduced-dynamic {name} baseline minus truth, RMS {c.upper()}")
    for label in ("float", "fixed"):
        name = "DD-fixed" if label == "fixed" else label
        for x in systems:
            for kind, unit, scale in (("phase", "mm", 1e3), ("code", "m", 1.0)):
                key = f"{label}_sd_{x}_{kind}_rms_m"
                if key in t:
                    row[f"sd_{kind}_residual_{x}_{label}"] = (
                        scale * float(t[key]), unit,
                        f"RMS of the receiver-SD {kind} residuals of {x}, {name} baseline")
    if kinematic is not None:
        for x in kinematic.system.values:
            for kind in kinematic.ambiguities.values:
                name = "DD-fixed" if kind == "fixed" else str(kind)
                for ref in ("truth", "dynamic"):
                    var = f"rms_minus_{ref}_m"
                    if var in kinematic:
                        v = kinematic[var].sel(system=x, ambiguities=kind, component="3D")
                        row[f"kinematic_{x}_{kind}_minus_{ref}_3d"] = (
                            1e3 * float(v), "mm", f"kinematic {x} {name} baseline minus "
                            f"{'reduced-dynamic DD-fixed' if ref == 'dynamic' else ref} "
                            "baseline, RMS 3D")
    if ranges is not None:
        for label in ranges.solution.values:
            key = str(label).replace(" ", "_").replace("DD-fixed", "fixed")
            row[f"range_std_{key}"] = (1e3 * float(ranges.std_m.sel(solution=label)), "mm",
                                       f"STD of |baseline| minus range, {label}")
    if overlap is not None:
        for label in overlap.solution.values:
            if int(overlap.n_epochs.sel(solution=label)) == 0:
                continue
            key = str(label).replace(" ", "_").replace("DD-fixed", "fixed")
            row[f"overlap_3d_{key}"] = (
                1e3 * float(overlap.rms_m.sel(solution=label, component="3D")), "mm",
                f"overlap with the next day's solution, RMS 3D, {label}")
    if lines is not None:
        for key, r in mutual_differences(lines).items():
            a, b = key.split("_minus_")
            for c in ("R", "T", "N", "3D"):
                row[f"mutual_{key}_{c.lower()}"] = (
                    1e3 * r[c], "mm", f"DD-fixed reduced-dynamic baseline {a} minus {b}, RMS {c}")
    return row


def formation_table(rows: Mapping[str, Mapping[str, tuple[float, str, str]]]
                    ) -> tuple[pd.DataFrame, dict[str, tuple[str, str]]]:
    """Days of :func:`formation_day_row` as a table with ``mean`` and ``std`` rows (counts:
    the sum and NaN), and ``{column: (unit, description)}``.

    Parameters
    ----------
    rows : mapping
        ``{date: row}``.
    """
    meta = {c: (u, d) for row in rows.values() for c, (_, u, d) in row.items()}
    table = pd.DataFrame({date: {c: v for c, (v, _, _) in row.items()}
                          for date, row in rows.items()}).T.reindex(columns=list(meta))
    counts = [c for c, (u, _) in meta.items() if u == "1"]
    mean = table.mean(numeric_only=True)
    std = table.std(ddof=1, numeric_only=True)
    for c in counts:
        mean[c] = table[c].sum(min_count=1)
        std[c] = np.nan
    out = pd.concat([table, pd.DataFrame([mean.rename("mean"), std.rename("std")])])
    out.index.name = "date"
    return out, meta


def baseline_overlap(times_a: np.ndarray, baseline_a: np.ndarray, times_b: np.ndarray,
                     baseline_b: np.ndarray, leader_gcrf: np.ndarray) -> tuple[np.ndarray,
                                                                            np.ndarray]:
    """Differences of two baseline solutions at their common epochs (earlier − later arc) in
    the leader's R, T, N.

    Parameters
    ----------
    times_a, times_b : ndarray of datetime64, shapes (m_a,), (m_b,)
        Epochs of the two solutions.
    baseline_a, baseline_b : ndarray, shapes (m_a, 3), (m_b, 3)
        ITRF baselines [m] (NaN: not solved).
    leader_gcrf : ndarray, shape (m_a, 6)
        Leader's GCRF state at ``times_a`` [m, m/s] (the axes).

    Returns
    -------
    times : ndarray of datetime64, shape (c,)
        The common epochs where both are finite.
    diff_rtn_m : ndarray, shape (c, 3)
    """
    common, ia, ib = np.intersect1d(times_a, times_b, return_indices=True)
    ok = np.isfinite(baseline_a[ia]).all(axis=1) & np.isfinite(baseline_b[ib]).all(axis=1)
    ia, ib = ia[ok], ib[ok]
    if ia.size == 0:
        return common[ok], np.zeros((0, 3))
    return common[ok], difference_rtn(baseline_a[ia], baseline_b[ib], common[ok],
                                      leader_gcrf[ia])


def burn_windows(times: np.ndarray, manoeuvres: Iterable, half_s: float = 1800.0) -> np.ndarray:
    """Epochs within ``half_s`` [s] before the start or after the end of any burn (bool (m,)),
    to show the effect of the manoeuvres on a baseline apart from the rest.

    Parameters
    ----------
    times : ndarray of datetime64, shape (m,)
    manoeuvres : iterable of leopod.io.manoeuvre.Manoeuvre
        Burns (``start``, ``end``; GPS time).
    half_s : float
        Margin [s].
    """
    t = np.asarray(times, dtype="datetime64[ns]")
    near = np.zeros(t.size, bool)
    half = np.timedelta64(int(round(half_s * 1e9)), "ns")
    for m in manoeuvres:
        near |= (t >= m.start - half) & (t <= m.end + half)
    return near
