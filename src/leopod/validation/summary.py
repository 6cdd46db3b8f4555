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
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

__all__ = ["COLUMNS", "campaign_table", "day_row"]

#: Column name -> (unit, description).
COLUMNS = {
    "phase_rms_mm": ("mm", "post-fit ionosphere-free phase residual RMS"),
    "code_rms_m": ("m", "post-fit ionosphere-free code residual RMS"),
    "n_phase": ("1", "phase observations used"),
    "wl_fixing_rate_pct": ("%", "wide-lane fixing rate (fixed/all independent)"),
    "nl_fixing_rate_pct": ("%", "narrow-lane fixing rate (fixed/all independent)"),
    "n_constraints": ("1", "fixed single differences constraining the solution"),
    "ar_product_accepted": ("1", "AR product accepted by the consistency guard (0: refused)"),
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
}


def _rms(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(values**2))) if values.size else float("nan")


def day_row(date: str, solution: str, *, residuals: xr.Dataset,
            ambiguity: xr.Dataset | None = None, overlap: xr.Dataset | None = None,
            reference: xr.Dataset | None = None, slr: xr.Dataset | None = None) -> dict:
    """Figures of one day and solution from its product files (module docstring).

    Parameters
    ----------
    date, solution : str
        Row labels (``YYYY-DDD``; ``float_pod`` / ``fixed_pod``).
    residuals : xarray.Dataset
        POD residuals (``phase_residual_m``, ``code_residual_m``).
    ambiguity : xarray.Dataset, optional
        Ambiguity table (attrs ``wl_fixing_rate``, ``nl_fixing_rate``; ``constrained``).
    overlap : xarray.Dataset, optional
        :func:`leopod.validation.overlap.overlap` of the day's arc with the next one.
    reference : xarray.Dataset, optional
        :func:`leopod.validation.reference.compare_day` output.
    slr : xarray.Dataset, optional
        :func:`leopod.validation.slr.slr_residuals` output (``flag`` 0 = used).

    Returns
    -------
    dict
        ``date``, ``solution`` and the :data:`COLUMNS`.
    """
    row = {"date": date, "solution": solution} | dict.fromkeys(COLUMNS, np.nan)
    phase = residuals.phase_residual_m.values
    row["phase_rms_mm"] = 1e3 * _rms(phase)
    row["code_rms_m"] = _rms(residuals.code_residual_m.values)
    row["n_phase"] = int(np.isfinite(phase).sum())
    if ambiguity is not None:
        row["wl_fixing_rate_pct"] = 100 * float(ambiguity.attrs.get("wl_fixing_rate", np.nan))
        row["nl_fixing_rate_pct"] = 100 * float(ambiguity.attrs.get("nl_fixing_rate", np.nan))
        verdict = ambiguity.attrs.get("product_guard")
        if verdict in ("accepted", "refused"):
            row["ar_product_accepted"] = float(verdict == "accepted")
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
    return row


def campaign_table(rows: list[dict]) -> pd.DataFrame:
    """Rows of :func:`day_row` as a table indexed by (date, solution), plus one ``mean`` row
    per solution (means of the daily figures; counts summed)."""
    table = pd.DataFrame(rows).set_index(["date", "solution"])
    means = []
    for solution, group in table.groupby(level="solution", sort=False):
        mean = group.mean(numeric_only=True)
        for count in ("n_phase", "n_constraints", "slr_n"):
            mean[count] = group[count].sum(min_count=1)
        means.append(mean.rename(("mean", solution)))
    out = pd.concat([table, pd.DataFrame(means)])
    out.index = pd.MultiIndex.from_tuples(out.index, names=["date", "solution"])
    return out
