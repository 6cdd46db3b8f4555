"""Campaign summary table: one row per day and solution with the figures the source papers publish.

Columns (NaN where a product does not exist, e.g. no overlap for the last day, no AR for the
float row): post-fit phase and code residual RMS and their counts (Wang et al. 2024, sec. 3.3.1),
the WL/NL fixing rates of the day's ambiguity resolution (Jiang et al. 2023: fixed independent / all
independent), the number of constraints, the verdict of the product guard
(:mod:`leopod.ambiguity.consistency`: 1 accepted, 0 refused - nothing fixed - and the mean
cosine of the WL and NL fractional parts it tested), the 3D RMS of the overlap of the day's arc with
the next one (Jiang et al. 2023, Fig. 13), the RMS of the orbit minus reference orbit in R, T, N and
3D (Wang et al. 2024, Table 4), and the number, mean and STD of the used SLR residuals
(Peng et al. 2021, Table IV).

Ambiguity resolution is reported with both definitions in use: the graph-rank fixing rate
(Jiang et al. 2023: fixed independent / all independent single differences, ``*_fixing_rate_pct``)
and the share of single differences fixed (fixed SDs / all SD candidates of the day,
``*_sd_fixed_pct``). The first counts no fix twice where SDs close a cycle; the second is what a
count of fixed (and of wrongly fixed) SDs refers to.

The antenna phase-centre offset along the body Z axis, where the POD estimates it
(``pod.estimate_pco_z``; parameter ``pco_z_m``), is given per day and solution as the estimated
correction to the a-priori PCO with its formal (sigma0-scaled) standard deviation, in cm as in
Jiang et al. (2023), Fig. 8; NaN where it is not estimated.

Per-system columns: residuals are split by GNSS system (first letter of the satellite id,
``G``, ``C``, ``E``, ...), and for each system present in the data of a campaign the table has
``phase_rms_<S>_mm``, ``code_rms_<S>_m`` and ``n_phase_<S>`` after the all-system residual
columns, and ``n_sd_<S>``, ``wl_sd_fixed_<S>_pct``, ``nl_sd_fixed_<S>_pct`` (single differences
are formed within a system; the system of satellite i) after the all-system shares
(:data:`SYSTEM_COLUMNS`); a system absent on a day is NaN there. A wide table keeps one row per
day and solution in the CSV, HTML and netCDF alike (the netCDF carries each column with units
and long name), and a single-system campaign simply has one such group.

Besides the daily rows, :func:`campaign_table` adds per solution a ``mean`` row (means of the
daily figures; counts summed) and a ``std`` row (sample STD of the daily figures over the days;
counts NaN) - the "average and STD" of Jiang et al. (2023), Fig. 8.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import xarray as xr

__all__ = ["COLUMNS", "COUNTS", "SYSTEM_COLUMNS", "campaign_table", "column_meta",
           "day_row", "system_of"]

#: Column name -> (unit, description).
COLUMNS = {
    "phase_rms_mm": ("mm", "post-fit ionosphere-free phase residual RMS"),
    "code_rms_m": ("m", "post-fit ionosphere-free code residual RMS"),
    "n_phase": ("1", "phase observations used"),
    "wl_fixing_rate_pct": ("%", "wide-lane fixing rate (fixed/all independent)"),
    "nl_fixing_rate_pct": ("%", "narrow-lane fixing rate (fixed/all independent)"),
    "n_sd": ("1", "single-difference ambiguities (candidates of the day)"),
    "wl_sd_fixed_pct": ("%", "share of single differences with the wide lane fixed"),
    "nl_sd_fixed_pct": ("%", "share of single differences with the narrow lane fixed"),
    "n_constraints": ("1", "fixed single differences constraining the solution"),
    "ar_product_accepted": ("1", "AR product accepted by the consistency guard (0: refused; "
                                 "combined arcs: by the guard of every system)"),
    "wl_guard_mean_cos": ("1", "mean cosine of the WL fractional parts (guard)"),
    "nl_guard_mean_cos": ("1", "mean cosine of the NL fractional parts (guard)"),
    "overlap_3d_rms_cm": ("cm", "3D RMS of the overlap with the next arc"),
    "reference_r_rms_cm": ("cm", "radial RMS of orbit minus reference"),
    "reference_t_rms_cm": ("cm", "along-track RMS of orbit minus reference"),
    "reference_n_rms_cm": ("cm", "cross-track RMS of orbit minus reference"),
    "reference_3d_rms_cm": ("cm", "3D RMS of orbit minus reference"),
    "slr_n": ("1", "SLR normal points used"),
    "slr_mean_cm": ("cm", "mean SLR residual"),
    "slr_std_cm": ("cm", "STD of the SLR residuals"),
    "pco_z_cm": ("cm", "estimated antenna PCO-Z correction to the a-priori PCO"),
    "pco_z_sigma_cm": ("cm", "formal standard deviation of the PCO-Z estimate"),
}

#: Per-system column templates (``{system}``: one letter, e.g. ``G``) -> (unit, description).
SYSTEM_COLUMNS = {
    "phase_rms_{system}_mm": ("mm", "post-fit ionosphere-free phase residual RMS, system {system}"),
    "code_rms_{system}_m": ("m", "post-fit ionosphere-free code residual RMS, system {system}"),
    "n_phase_{system}": ("1", "phase observations used, system {system}"),
    "n_sd_{system}": ("1", "single-difference ambiguities, system {system}"),
    "wl_sd_fixed_{system}_pct": ("%", "share of single differences with the wide lane fixed, "
                                      "system {system}"),
    "nl_sd_fixed_{system}_pct": ("%", "share of single differences with the narrow lane fixed, "
                                      "system {system}"),
}

#: Count columns: summed in the ``mean`` row, no ``std`` row value.
COUNTS = ("n_phase", "n_sd", "n_constraints", "slr_n")

#: All-system column -> the per-system templates that follow it in the table.
_SYSTEMS_AFTER = {"n_phase": tuple(SYSTEM_COLUMNS)[:3],
                  "nl_sd_fixed_pct": tuple(SYSTEM_COLUMNS)[3:]}
_SYSTEM_PATTERNS = {template: re.compile(re.escape(template).replace(r"\{system\}",
                                                                     "(?P<system>[A-Z])"))
                    for template in SYSTEM_COLUMNS}


def system_of(sv) -> np.ndarray:
    """GNSS system letters (``G``, ``C``, ``E``, ...) of RINEX-3 satellite ids (``G07``)."""
    return np.array([str(s)[:1] for s in np.atleast_1d(sv)], dtype="<U1")


def column_meta(name: str) -> tuple[str, str]:
    """(unit, description) of a summary column, per-system columns included.

    Raises
    ------
    KeyError
        If ``name`` is no column of the summary.
    """
    if name in COLUMNS:
        return COLUMNS[name]
    for template, pattern in _SYSTEM_PATTERNS.items():
        match = pattern.fullmatch(name)
        if match:
            unit, text = SYSTEM_COLUMNS[template]
            return unit, text.format(system=match["system"])
    raise KeyError(f"{name!r} is no column of the campaign summary")


def _is_count(name: str) -> bool:
    return name in COUNTS or name.startswith(("n_phase_", "n_sd_"))


def _ordered(names) -> list[str]:
    """:data:`COLUMNS` order, each group of per-system columns (sorted by system) after its
    all-system column (:data:`_SYSTEMS_AFTER`)."""
    names = set(names)
    systems = sorted({m["system"] for n in names for p in _SYSTEM_PATTERNS.values()
                      if (m := p.fullmatch(n))})
    out = []
    for name in COLUMNS:
        out.append(name)
        group = [t.format(system=s) for s in systems for t in _SYSTEMS_AFTER.get(name, ())]
        out += [n for n in group if n in names]
    return out


def _rms(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(values**2))) if values.size else float("nan")


def _sd_share(flags: np.ndarray) -> float:
    """Percentage of single differences whose flag is 1 (NaN without candidates)."""
    return 100 * float(np.mean(flags == 1)) if flags.size else float("nan")


def day_row(date: str, solution: str, *, residuals: xr.Dataset,
            ambiguity: xr.Dataset | None = None, overlap: xr.Dataset | None = None,
            reference: xr.Dataset | None = None, slr: xr.Dataset | None = None,
            parameters: xr.Dataset | None = None) -> dict:
    """Figures of one day and solution from its product files (module docstring).

    Parameters
    ----------
    date, solution : str
        Row labels (``YYYY-DDD``; ``float_pod`` / ``fixed_pod``).
    residuals : xarray.Dataset
        POD residuals (``phase_residual_m``, ``code_residual_m`` [m] on (time, sv)); with an
        ``sv`` coordinate of satellite ids the per-system columns are filled.
    ambiguity : xarray.Dataset, optional
        Ambiguity table (attrs ``wl_fixing_rate``, ``nl_fixing_rate``; ``wl_fixed``,
        ``nl_fixed``, ``constrained`` (pair) 0/1; with ``sv_i`` (pair) the per-system shares
        are filled).
    overlap : xarray.Dataset, optional
        :func:`leopod.validation.overlap.overlap` of the day's arc with the next one.
    reference : xarray.Dataset, optional
        :func:`leopod.validation.reference.compare_day` output.
    slr : xarray.Dataset, optional
        :func:`leopod.validation.slr.slr_residuals` output (``flag`` 0 = used).
    parameters : xarray.Dataset, optional
        POD parameters (``estimate``, ``sigma`` on ``parameter``); ``pco_z_m`` [m] if the
        PCO-Z was estimated.

    Returns
    -------
    dict
        ``date``, ``solution``, the :data:`COLUMNS` and the :data:`SYSTEM_COLUMNS` of the
        systems in ``residuals`` and ``ambiguity``.
    """
    row = {"date": date, "solution": solution} | dict.fromkeys(COLUMNS, np.nan)
    phase = residuals.phase_residual_m.values
    code = residuals.code_residual_m.values
    row["phase_rms_mm"] = 1e3 * _rms(phase)
    row["code_rms_m"] = _rms(code)
    row["n_phase"] = int(np.isfinite(phase).sum())
    if "sv" in residuals.coords:
        axis = residuals.phase_residual_m.dims.index("sv")
        systems = system_of(residuals.sv.values)
        for system in np.unique(systems):
            cols = systems == system
            p = np.compress(cols, phase, axis=axis)
            row[f"phase_rms_{system}_mm"] = 1e3 * _rms(p)
            row[f"code_rms_{system}_m"] = _rms(np.compress(cols, code, axis=axis))
            row[f"n_phase_{system}"] = int(np.isfinite(p).sum())
    if ambiguity is not None:
        row["wl_fixing_rate_pct"] = 100 * float(ambiguity.attrs.get("wl_fixing_rate", np.nan))
        row["nl_fixing_rate_pct"] = 100 * float(ambiguity.attrs.get("nl_fixing_rate", np.nan))
        if "wl_fixed" in ambiguity and "nl_fixed" in ambiguity:
            row["n_sd"] = int(ambiguity.wl_fixed.size)
            for lane in ("wl", "nl"):
                row[f"{lane}_sd_fixed_pct"] = _sd_share(ambiguity[f"{lane}_fixed"].values)
            if "sv_i" in ambiguity:
                systems = system_of(ambiguity.sv_i.values) if ambiguity.sv_i.size else []
                for system in np.unique(systems):
                    sel = systems == system
                    row[f"n_sd_{system}"] = int(sel.sum())
                    for lane in ("wl", "nl"):
                        row[f"{lane}_sd_fixed_{system}_pct"] = _sd_share(
                            ambiguity[f"{lane}_fixed"].values[sel])
        # one verdict, or one per system of a combined arc (``<system>_product_guard``)
        keys = (["product_guard"] if "product_guard" in ambiguity.attrs else
                [f"{x}_product_guard" for x in ambiguity.attrs.get("systems", "").split()])
        verdicts = [ambiguity.attrs[k] for k in keys if k in ambiguity.attrs]
        if verdicts and set(verdicts) <= {"accepted", "refused"}:
            row["ar_product_accepted"] = float(all(v == "accepted" for v in verdicts))
        for lane in ("wl", "nl"):
            row[f"{lane}_guard_mean_cos"] = float(ambiguity.attrs.get(f"{lane}_guard_mean_cos",
                                                                       np.nan))
        if solution == "fixed_pod" and "constrained" in ambiguity:
            row["n_constraints"] = int((ambiguity.constrained.values == 1).sum())
    if overlap is not None:
        row["overlap_3d_rms_cm"] = 100 * float(overlap.rms_m.sel(component="3D"))
    if reference is not None:
        rms = reference.rms_m.sel(period="total")
        for c in ("R", "T", "N", "3D"):
            row[f"reference_{c.lower()}_rms_cm"] = 100 * float(rms.sel(component=c))
    if slr is not None:
        used = slr.residual_m.values[slr.flag.values == 0]
        row["slr_n"] = int(used.size)
        if used.size:
            row["slr_mean_cm"] = 100 * float(np.mean(used))
            row["slr_std_cm"] = 100 * float(np.std(used, ddof=1)) if used.size > 1 else np.nan
    if parameters is not None and "pco_z_m" in parameters.parameter.values:
        pco = parameters.sel(parameter="pco_z_m")
        row["pco_z_cm"] = 100 * float(pco.estimate)
        row["pco_z_sigma_cm"] = 100 * float(pco.sigma)
    return row


def campaign_table(rows: list[dict]) -> pd.DataFrame:
    """Rows of :func:`day_row` as a table indexed by (date, solution), plus per solution a
    ``mean`` row (means of the daily figures; counts summed) and a ``std`` row (sample STD of
    the daily figures, NaN with one day; counts NaN).

    Columns are :data:`COLUMNS` with the per-system columns of every system in ``rows``
    after ``n_phase``; a system missing from a row is NaN there.
    """
    table = pd.DataFrame(rows).set_index(["date", "solution"])
    table = table.reindex(columns=_ordered(table.columns))
    counts = [c for c in table.columns if _is_count(c)]
    means, stds = [], []
    for solution, group in table.groupby(level="solution", sort=False):
        mean = group.mean(numeric_only=True)
        std = group.std(ddof=1, numeric_only=True)
        for count in counts:
            mean[count] = group[count].sum(min_count=1)
            std[count] = np.nan
        means.append(mean.rename(("mean", solution)))
        stds.append(std.rename(("std", solution)))
    out = pd.concat([table, pd.DataFrame(means + stds)])
    out.index = pd.MultiIndex.from_tuples(out.index, names=["date", "solution"])
    return out
