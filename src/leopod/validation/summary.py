"""Campaign summary table: one row per day and solution with the figures the source papers publish.

Columns (NaN where a product does not exist, e.g. no overlap for the last day, no AR for the
float row): post-fit phase and code residual RMS and their counts (Wang et al. 2024, sec. 3.3.1),
the WL/NL fixing rates of the day's ambiguity resolution (Jiang et al. 2023: fixed independent / all
independent), the number of constraints, the verdict of the product guard
(:mod:`leopod.ambiguity.consistency`: 1 accepted, 0 refused - nothing fixed - and the mean
cosine of the WL and NL fractional parts it tested), the 3D RMS of the overlap of the day's arc with
the next one (Jiang et al. 2023, Fig. 13), the RMS of the orbit minus reference orbit in R, T, N and
3D (Wang et al. 2024, Table 4), and the number, mean and STD of the used SLR residuals
(Peng et al. 2021, Table IV), and the verdict of the quality gate
(:mod:`leopod.validation.quality_gate`: 0 ok, 1 suspect, 2 failed; the worst day in the
``all_days`` row).

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

Per-system ambiguity resolution of a combined arc (:func:`leopod.ambiguity.resolve.
resolve_systems`, whose table has ``<system>_*`` attributes): the graph-rank fixing rates
``wl_fixing_rate_<S>_pct``, ``nl_fixing_rate_<S>_pct`` beside the SD shares, and the product
guard's verdict and mean cosines ``ar_product_accepted_<S>``, ``wl_guard_mean_cos_<S>``,
``nl_guard_mean_cos_<S>`` (the guard runs per system; a single-system table fills its one
system's columns with its own figures). With the simulator's truth (a simulated campaign),
the wrongly fixed single differences counted against the true integers of each system's own
phase pair (:func:`leopod.simulate.ambiguity_truth.wrong_fix_counts`, ``wrong_fixes``):
``wl_wrong``, ``nl_wrong`` (WL or NL integer wrong), ``constrained_wrong`` and per system.

Combined POD (``pod.system`` a list; :mod:`leopod.estimation.float_pod`): the inter-system
bias of every system but the first (the datum), ``isb_<S>_m`` with its formal sigma
``isb_<S>_sigma_m`` - with piecewise ISBs (``pod.isb_interval_s``) the mean of the
``n_isb_<S>`` pieces, the sigma of that mean from their covariance and the STD of the pieces
``isb_<S>_std_m`` (:func:`isb_series` gives the pieces over time) - and per system and
observation type the variance factor of the variance component estimation (``pod.vce``;
1 without) with its sigma, ``vf_<S>_code``, ``vf_<S>_code_sigma``, ``vf_<S>_phase``,
``vf_<S>_phase_sigma``, and the resulting observation sigmas ``sigma_<S>_code_m``,
``sigma_<S>_phase_mm`` (square root of the factor times the a-priori sigma above the
weighting elevation; Zhang et al. 2024, Table 1), after the a-posteriori sigma of unit weight
``sigma0``.

Besides the daily rows, :func:`campaign_table` adds per solution a ``mean`` row (means of the
daily figures, counts included: a count per day) and a ``std`` row (sample STD of the daily
figures over the days) - the "average and STD" of Jiang et al. (2023), Fig. 8 - and an
``all_days`` row with the counts summed over the days and the quality gate of the worst day.

For the report, :func:`column_label` gives each column a short header, :func:`column_kind`
how its values read (count, per cent, yes/no flag, gate level, number) and
:func:`missing_reason` why a value is missing (a footnote instead of ``nan``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping

import numpy as np
import pandas as pd
import xarray as xr

from leopod.numerics.statistics import finite_rms
from leopod.signals import system_of
from leopod.validation.quality_gate import GateSettings, check, stamped_figures

__all__ = ["AGGREGATE_ROWS", "COLUMNS", "COUNTS", "LABELS", "SECTIONS", "SYSTEM_COLUMNS",
           "campaign_table", "column_kind", "column_label", "column_meta", "csv_text", "day_row",
           "excluded_row", "isb_series", "missing_reason", "sections", "system_of_column"]

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
    "wl_wrong": ("1", "fixed WL single differences whose integer differs from the simulated "
                      "truth"),
    "nl_wrong": ("1", "fixed NL single differences whose WL or NL integer differs from the "
                      "simulated truth"),
    "constrained_wrong": ("1", "constrained single differences with a wrong integer "
                               "(simulated truth)"),
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
    "sigma0": ("1", "a-posteriori standard deviation of unit weight of the POD"),
    "quality_gate": ("1", "quality gate of the day (leopod.validation.quality_gate): 0 ok, "
                          "1 suspect, 2 failed"),
}

#: Per-system column templates (``{system}``: one letter, e.g. ``G``) -> (unit, description).
SYSTEM_COLUMNS = {
    "phase_rms_{system}_mm": ("mm", "post-fit ionosphere-free phase residual RMS, system {system}"),
    "code_rms_{system}_m": ("m", "post-fit ionosphere-free code residual RMS, system {system}"),
    "n_phase_{system}": ("1", "phase observations used, system {system}"),
    "n_sd_{system}": ("1", "single-difference ambiguities, system {system}"),
    "wl_fixing_rate_{system}_pct": ("%", "wide-lane fixing rate (fixed/all independent), "
                                         "system {system}"),
    "nl_fixing_rate_{system}_pct": ("%", "narrow-lane fixing rate (fixed/all independent), "
                                         "system {system}"),
    "wl_sd_fixed_{system}_pct": ("%", "share of single differences with the wide lane fixed, "
                                      "system {system}"),
    "nl_sd_fixed_{system}_pct": ("%", "share of single differences with the narrow lane fixed, "
                                      "system {system}"),
    "ar_product_accepted_{system}": ("1", "AR product of system {system} accepted by its "
                                          "consistency guard (0: refused)"),
    "wl_guard_mean_cos_{system}": ("1", "mean cosine of the WL fractional parts (guard), "
                                        "system {system}"),
    "nl_guard_mean_cos_{system}": ("1", "mean cosine of the NL fractional parts (guard), "
                                        "system {system}"),
    "wl_wrong_{system}": ("1", "wrongly fixed WL single differences, system {system}"),
    "nl_wrong_{system}": ("1", "wrongly fixed NL single differences, system {system}"),
    "constrained_wrong_{system}": ("1", "constrained single differences with a wrong "
                                        "integer, system {system}"),
    "isb_{system}_m": ("m", "inter-system code bias of system {system} relative to the first "
                            "system of the POD (mean of its pieces)"),
    "isb_{system}_sigma_m": ("m", "formal standard deviation of isb_{system}_m"),
    "n_isb_{system}": ("1", "pieces of the inter-system bias of system {system}"),
    "isb_{system}_std_m": ("m", "STD of the inter-system-bias pieces of system {system} "
                                "(NaN with one piece)"),
    "vf_{system}_code": ("1", "variance factor of the codes of system {system} (VCE; 1: not "
                              "estimated)"),
    "vf_{system}_code_sigma": ("1", "standard deviation of vf_{system}_code"),
    "sigma_{system}_code_m": ("m", "code sigma of system {system}: sqrt(variance factor) "
                                   "times the a-priori sigma"),
    "vf_{system}_phase": ("1", "variance factor of the phases of system {system} (VCE; 1: "
                               "not estimated)"),
    "vf_{system}_phase_sigma": ("1", "standard deviation of vf_{system}_phase"),
    "sigma_{system}_phase_mm": ("mm", "phase sigma of system {system}: sqrt(variance factor) "
                                      "times the a-priori sigma"),
}

#: Count columns: averaged in the ``mean`` row like every figure, summed in the ``all_days``
#: row.
COUNTS = ("n_phase", "n_sd", "n_constraints", "slr_n", "wl_wrong", "nl_wrong",
          "constrained_wrong")
#: Rows of :func:`campaign_table` that are statistics over the days (index level ``date``).
AGGREGATE_ROWS = ("mean", "std", "all_days")

#: Short header of each column (:data:`COLUMNS` and :data:`SYSTEM_COLUMNS` keys; the unit is
#: added by the table).
LABELS = {
    "phase_rms_mm": "phase RMS", "code_rms_m": "code RMS", "n_phase": "phase obs.",
    "wl_fixing_rate_pct": "WL fixed (graph rank)", "nl_fixing_rate_pct": "NL fixed (graph rank)",
    "n_sd": "SD ambiguities", "wl_sd_fixed_pct": "WL SDs fixed", "nl_sd_fixed_pct": "NL SDs fixed",
    "n_constraints": "constraints", "ar_product_accepted": "AR product accepted",
    "wl_guard_mean_cos": "WL guard mean cos", "nl_guard_mean_cos": "NL guard mean cos",
    "wl_wrong": "wrong WL fixes", "nl_wrong": "wrong NL fixes",
    "constrained_wrong": "wrong constraints", "overlap_3d_rms_cm": "overlap 3D RMS",
    "reference_r_rms_cm": "reference R RMS", "reference_t_rms_cm": "reference T RMS",
    "reference_n_rms_cm": "reference N RMS", "reference_3d_rms_cm": "reference 3D RMS",
    "slr_n": "SLR points", "slr_mean_cm": "SLR mean", "slr_std_cm": "SLR STD",
    "pco_z_cm": "PCO-Z", "pco_z_sigma_cm": "PCO-Z sigma", "sigma0": "sigma0",
    "quality_gate": "quality gate",
    "phase_rms_{system}_mm": "phase RMS {system}", "code_rms_{system}_m": "code RMS {system}",
    "n_phase_{system}": "phase obs. {system}", "n_sd_{system}": "SD ambiguities {system}",
    "wl_fixing_rate_{system}_pct": "WL fixed (graph rank) {system}",
    "nl_fixing_rate_{system}_pct": "NL fixed (graph rank) {system}",
    "wl_sd_fixed_{system}_pct": "WL SDs fixed {system}",
    "nl_sd_fixed_{system}_pct": "NL SDs fixed {system}",
    "ar_product_accepted_{system}": "AR product accepted {system}",
    "wl_guard_mean_cos_{system}": "WL guard mean cos {system}",
    "nl_guard_mean_cos_{system}": "NL guard mean cos {system}",
    "wl_wrong_{system}": "wrong WL fixes {system}", "nl_wrong_{system}": "wrong NL fixes {system}",
    "constrained_wrong_{system}": "wrong constraints {system}",
    "isb_{system}_m": "ISB {system}", "isb_{system}_sigma_m": "ISB {system} sigma",
    "n_isb_{system}": "ISB pieces {system}", "isb_{system}_std_m": "ISB {system} STD of pieces",
    "vf_{system}_code": "variance factor code {system}",
    "vf_{system}_code_sigma": "variance factor code {system} sigma",
    "sigma_{system}_code_m": "code sigma {system}",
    "vf_{system}_phase": "variance factor phase {system}",
    "vf_{system}_phase_sigma": "variance factor phase {system} sigma",
    "sigma_{system}_phase_mm": "phase sigma {system}",
}
_FLAGS = ("ar_product_accepted", "ar_product_accepted_{system}")
_NO_GUARD = "the product guard did not test the AR product"
_NO_TRUTH = "wrong fixes need the simulated truth (a simulated satellite with AR)"
#: Why a daily value can be missing: exact column names first, then name prefixes in order
#: (:func:`missing_reason`).
_MISSING = {
    "n_constraints": "the float solution has no ambiguity constraints (or no AR this day)",
    "overlap_3d_rms_cm": "no overlap: the last day of the campaign has no next arc",
    "slr_std_cm": "fewer than two SLR normal points used",
    "slr_mean_cm": "no SLR normal point used",
}
_MISSING_PREFIXES = (
    (("phase_rms", "code_rms", "n_phase"), "no residuals of this system on this day"),
    (("ar_product", "wl_guard", "nl_guard"), _NO_GUARD),
    (("wl_wrong", "nl_wrong", "constrained_wrong"), _NO_TRUTH),
    (("wl_", "nl_", "n_sd"), "no ambiguity resolution of this day (ambiguity.enabled false, "
                             "or no AR product)"),
    (("reference_",), "no reference orbit of this day (validation.reference_orbit)"),
    (("slr_",), "no SLR normal points of this day (validation.slr)"),
    (("pco_z",), "PCO-Z not estimated (pod.estimate_pco_z false)"),
    (("isb_", "n_isb_"), "no inter-system bias: a single-system POD"),
    (("vf_",), "not estimated (variance components off: pod.vce)"),
    (("sigma_",), "no a-priori sigma of this observation group"),
    (("sigma0",), "no POD parameters of this day"),
    (("quality_gate",), "no quality gate of this day"),
)
_COUNT_PREFIXES = ("n_phase_", "n_sd_", "n_isb_", "wl_wrong_", "nl_wrong_",
                   "constrained_wrong_")

#: All-system column -> the per-system templates that follow it in the table (each group
#: per system in :data:`SYSTEM_COLUMNS` order).
_SYSTEMS_AFTER = {"n_phase": tuple(SYSTEM_COLUMNS)[:3],
                  "nl_sd_fixed_pct": tuple(SYSTEM_COLUMNS)[3:8],
                  "nl_guard_mean_cos": tuple(SYSTEM_COLUMNS)[8:11],
                  "constrained_wrong": tuple(SYSTEM_COLUMNS)[11:14],
                  "sigma0": tuple(SYSTEM_COLUMNS)[14:]}
#: Section title -> its first all-system column (the table's columns in order, split there).
SECTIONS = {"residuals": "phase_rms_mm",
            "ambiguity resolution": "wl_fixing_rate_pct",
            "product guard and wrong fixes (simulated truth)": "ar_product_accepted",
            "validation": "overlap_3d_rms_cm",
            "antenna, inter-system biases and variance components": "pco_z_cm",
            "quality gate": "quality_gate"}
_ISB = re.compile(r"isb_(?P<system>[A-Z])(?:_(?P<piece>\d+))?_m")
_SYSTEM_PATTERNS = {template: re.compile(re.escape(template).replace(r"\{system\}",
                                                                     "(?P<system>[A-Z])"))
                    for template in SYSTEM_COLUMNS}


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


def _template(name: str) -> str:
    """The :data:`COLUMNS` key or :data:`SYSTEM_COLUMNS` template of a column (with its system
    filled into the returned label by the callers), ``name`` itself if it is neither."""
    if name in COLUMNS:
        return name
    return next((t for t, p in _SYSTEM_PATTERNS.items() if p.fullmatch(name)), name)


def column_label(name: str) -> str:
    """Short readable header of a summary column, without its unit (``phase RMS G``)."""
    return LABELS.get(_template(name), name).format(system=system_of_column(name))


def column_kind(name: str) -> str:
    """How a column's values read: ``count``, ``percent``, ``flag`` (1 yes, 0 no), ``level``
    (the quality gate, :data:`leopod.validation.quality_gate.STATUS`) or ``number``."""
    if name == "quality_gate":
        return "level"
    if _is_count(name):
        return "count"
    if _template(name) in _FLAGS:
        return "flag"
    return "percent" if column_meta(name)[0] == "%" else "number"


def missing_reason(name: str, row: str, n_days: int) -> str:
    """Why the value of column ``name`` in ``row`` (a day ``YYYY-DDD`` or one of
    :data:`AGGREGATE_ROWS`) of a campaign of ``n_days`` days is missing, in words."""
    if row == "std" and n_days < 2:
        return "the STD over the days needs two days or more"
    if row == "all_days" and not (_is_count(name) or name == "quality_gate"):
        return ("all days: counts summed and the quality gate of the worst day; the other "
                "figures have their mean and STD rows")
    if row in ("mean", "std") and name == "quality_gate":
        return "the quality gate of the worst day is in the all-days row"
    if name.startswith("isb_") and name.endswith("_std_m"):
        return "one ISB piece only (pod.isb_interval_s)"
    if name in _MISSING:
        return _MISSING[name]
    return next((text for prefixes, text in _MISSING_PREFIXES if name.startswith(prefixes)),
                "not available for this day and solution")


def system_of_column(name: str) -> str | None:
    """The GNSS system of a per-system column (``G`` of ``phase_rms_G_mm``), else None."""
    template = _template(name)
    return (_SYSTEM_PATTERNS[template].fullmatch(name)["system"]
            if template in SYSTEM_COLUMNS else None)


def csv_text(table: pd.DataFrame) -> str:
    """The campaign table as CSV: counts and the quality gate as integers, other figures with
    4 decimals, missing values empty."""
    out = table.copy()
    for name in out.columns:
        if _is_count(name) or name == "quality_gate":
            out[name] = out[name].round().astype("Int64")
    return out.to_csv(float_format="%.4f")


def _is_count(name: str) -> bool:
    return name in COUNTS or name.startswith(_COUNT_PREFIXES)


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


def sections(columns) -> dict[str, list[str]]:
    """The columns of a :func:`campaign_table` (in its order) split into :data:`SECTIONS`
    (for a readable report: one table per section; empty sections left out)."""
    columns = list(columns)
    starts = sorted((columns.index(first), title) for title, first in SECTIONS.items()
                    if first in columns)
    bounds = [k for k, _ in starts[1:]] + [len(columns)]
    return {title: columns[k:end] for (k, title), end in zip(starts, bounds, strict=True)
            if columns[k:end]}


def _sd_share(flags: np.ndarray) -> float:
    """Percentage of single differences whose flag is 1 (NaN without candidates)."""
    return 100 * float(np.mean(flags == 1)) if flags.size else float("nan")


def _verdict(value) -> float:
    """1 accepted, 0 refused, NaN not tested."""
    return {"accepted": 1.0, "refused": 0.0}.get(str(value), np.nan)


def _per_system_attrs(ambiguity: xr.Dataset) -> dict[str, dict]:
    """The attributes of each system's ambiguity resolution: ``<S>_*`` of a combined table
    (``systems`` attribute), all of a single-system table (its system from ``sv_i``)."""
    attrs = ambiguity.attrs
    if "systems" in attrs:
        return {x: {k[len(x) + 1:]: v for k, v in attrs.items() if k.startswith(f"{x}_")}
                for x in str(attrs["systems"]).split()}
    systems = np.unique(system_of(ambiguity.sv_i.values)) if "sv_i" in ambiguity else []
    return {str(systems[0]): dict(attrs)} if len(systems) == 1 else {}


def _ar_system_columns(ambiguity: xr.Dataset) -> dict:
    """Graph-rank fixing rates and guard statistics per system (module docstring)."""
    row = {}
    for x, attrs in _per_system_attrs(ambiguity).items():
        for lane in ("wl", "nl"):
            row[f"{lane}_fixing_rate_{x}_pct"] = 100 * float(attrs.get(f"{lane}_fixing_rate",
                                                                       np.nan))
            row[f"{lane}_guard_mean_cos_{x}"] = float(attrs.get(f"{lane}_guard_mean_cos",
                                                                np.nan))
        row[f"ar_product_accepted_{x}"] = _verdict(attrs.get("product_guard"))
    return row


def _wrong_fix_columns(counts: Mapping) -> dict:
    """Wrongly fixed single differences, all (``counts["all"]``) and per system."""
    keys = ("wl_wrong", "nl_wrong", "constrained_wrong")
    row = {}
    for x, per in counts.items():
        row |= {(k if x == "all" else f"{k}_{x}"): per[k] for k in keys}
    return row


def _isb_pieces(parameters: xr.Dataset) -> dict[str, list[str]]:
    """ISB parameter names per system, in piece order."""
    out: dict[str, list[tuple[int, str]]] = {}
    for name in parameters.parameter.values.astype(str):
        match = _ISB.fullmatch(name)
        if match:
            out.setdefault(match["system"], []).append((int(match["piece"] or 0), name))
    return {x: [n for _, n in sorted(v)] for x, v in out.items()}


def _isb_columns(parameters: xr.Dataset) -> dict:
    """Mean ISB of the pieces with the sigma of that mean (covariance) and their STD."""
    row = {}
    for x, names in _isb_pieces(parameters).items():
        est = parameters.estimate.sel(parameter=names).values.astype(float)
        cov = parameters.covariance.sel(parameter=names, parameter_b=names).values
        n = len(names)
        row[f"isb_{x}_m"] = float(np.mean(est))
        row[f"isb_{x}_sigma_m"] = float(np.sqrt(max(np.sum(cov), 0.0))) / n
        row[f"n_isb_{x}"] = n
        row[f"isb_{x}_std_m"] = float(np.std(est, ddof=1)) if n > 1 else np.nan
    return row


def _vce_columns(parameters: xr.Dataset) -> dict:
    """Variance factors per system and observation type, their sigmas, the resulting
    observation sigmas, and sigma0."""
    row = {"sigma0": float(parameters.attrs.get("sigma0", np.nan))}
    if "variance_factor" not in parameters:
        return row
    scale = {"code": ("m", 1.0), "phase": ("mm", 1e3)}
    for group in parameters.group.values.astype(str):
        x, kind = group.split("_", 1)
        g = parameters.sel(group=group)
        factor = float(g.variance_factor)
        row[f"vf_{x}_{kind}"] = factor
        row[f"vf_{x}_{kind}_sigma"] = float(g.variance_factor_sigma)
        prior = float(g.apriori_sigma_m) if "apriori_sigma_m" in g else np.nan
        unit, to_unit = scale[kind]
        row[f"sigma_{x}_{kind}_{unit}"] = to_unit * np.sqrt(factor) * prior
    return row


def isb_series(parameters: xr.Dataset, residuals: xr.Dataset) -> pd.DataFrame:
    """The inter-system-bias pieces of a POD solution over time.

    Parameters
    ----------
    parameters : xarray.Dataset
        POD parameters (``isb_<S>_m`` or ``isb_<S>_<piece>_m``, ``estimate``, ``sigma``).
    residuals : xarray.Dataset
        POD residuals of the same solution (``time``; ``isb_piece`` on time, the piece of
        each epoch; without it the arc must have one piece per system).

    Returns
    -------
    pandas.DataFrame
        One row per system and piece: ``system``, ``piece``, ``start``, ``end`` (first and
        last epoch of the piece, datetime64), ``estimate_m``, ``sigma_m``; empty without ISB.

    Raises
    ------
    ValueError
        If an arc has several ISB pieces but the residuals no ``isb_piece``.
    """
    times = residuals.time.values
    piece_of = (residuals.isb_piece.values if "isb_piece" in residuals
                else np.zeros(times.size, int))
    rows = []
    for x, names in _isb_pieces(parameters).items():
        if len(names) > 1 and "isb_piece" not in residuals:
            raise ValueError(f"{len(names)} ISB pieces of system {x} but the residuals have "
                             "no isb_piece variable (written by leopod >= this version)")
        for piece, name in enumerate(names):
            at = times[piece_of == piece]
            p = parameters.sel(parameter=name)
            rows.append({"system": x, "piece": piece,
                         "start": at.min() if at.size else np.datetime64("NaT"),
                         "end": at.max() if at.size else np.datetime64("NaT"),
                         "estimate_m": float(p.estimate), "sigma_m": float(p.sigma)})
    return pd.DataFrame(rows, columns=["system", "piece", "start", "end", "estimate_m",
                                       "sigma_m"])


def day_row(date: str, solution: str, *, residuals: xr.Dataset,
            ambiguity: xr.Dataset | None = None, overlap: xr.Dataset | None = None,
            reference: xr.Dataset | None = None, slr: xr.Dataset | None = None,
            parameters: xr.Dataset | None = None,
            wrong_fixes: Mapping | None = None, gate: GateSettings | None = None) -> dict:
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
        PCO-Z was estimated, ``isb_<S>[_<piece>]_m`` [m] of a combined POD, and the
        variance groups (``variance_factor``, ``variance_factor_sigma``, ``apriori_sigma_m``
        on ``group``) and ``sigma0`` of :func:`leopod.estimation.outputs.parameter_dataset`.
    wrong_fixes : mapping, optional
        Wrong fixes of the day's ambiguity resolution against the simulated truth,
        :func:`leopod.simulate.ambiguity_truth.wrong_fix_counts` (``{"all": counts,
        system: counts}``).
    gate : GateSettings, optional
        Thresholds of the quality gate: ``quality_gate`` is the level of
        :func:`leopod.validation.quality_gate.check` of the figures the POD kept in
        ``parameters`` and the overlap (the reasons in ``quality_gate_reasons``, a text).

    Returns
    -------
    dict
        ``date``, ``solution``, the :data:`COLUMNS` and the :data:`SYSTEM_COLUMNS` of the
        systems in ``residuals`` and ``ambiguity``.
    """
    row = {"date": date, "solution": solution} | dict.fromkeys(COLUMNS, np.nan)
    phase = residuals.phase_residual_m.values
    code = residuals.code_residual_m.values
    row["phase_rms_mm"] = 1e3 * finite_rms(phase)
    row["code_rms_m"] = finite_rms(code)
    row["n_phase"] = int(np.isfinite(phase).sum())
    if "sv" in residuals.coords:
        axis = residuals.phase_residual_m.dims.index("sv")
        systems = system_of(residuals.sv.values)
        for system in np.unique(systems):
            cols = systems == system
            p = np.compress(cols, phase, axis=axis)
            row[f"phase_rms_{system}_mm"] = 1e3 * finite_rms(p)
            row[f"code_rms_{system}_m"] = finite_rms(np.compress(cols, code, axis=axis))
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
        row |= _ar_system_columns(ambiguity)
    if wrong_fixes is not None:
        row |= _wrong_fix_columns(wrong_fixes)
    if overlap is not None:
        row["overlap_3d_rms_cm"] = 100 * float(overlap.rms_m.sel(component="3D"))
    if reference is not None:
        total = reference.rms_m.sel(period="total")
        for c in ("R", "T", "N", "3D"):
            row[f"reference_{c.lower()}_rms_cm"] = 100 * float(total.sel(component=c))
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
    if parameters is not None:
        row |= _isb_columns(parameters) | _vce_columns(parameters)
    if gate is not None and parameters is not None:
        verdict = check(stamped_figures(parameters) | {"overlap_3d_cm": row["overlap_3d_rms_cm"]},
                        gate, converged=bool(parameters.attrs.get("converged", 1)))
        row["quality_gate"] = float(verdict.level)
        row["quality_gate_reasons"] = "; ".join(verdict.reasons)
    return row


def excluded_row(date: str, solution: str, reason: str) -> dict:
    """Row of a day left out of the campaign (config ``exclude_days``): no figures, the
    quality gate failed (2) with ``reason``.

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    solution : str
        POD step (``float_pod`` or ``fixed_pod``).
    reason : str
        Why the day was left out (e.g. the error of its failed step).
    """
    return {"date": date, "solution": solution, "quality_gate": 2.0,
            "quality_gate_reasons": f"excluded from the campaign: {reason}"}


def campaign_table(rows: list[dict]) -> pd.DataFrame:
    """Rows of :func:`day_row` as a table indexed by (date, solution), plus per solution three
    rows of statistics over the days (:data:`AGGREGATE_ROWS`): ``mean`` (the mean of every
    figure, counts included: a mean per day), ``std`` (their sample STD, NaN with one day) and
    ``all_days`` (the counts summed and the quality gate of the worst day; NaN for the other
    figures); the text column ``quality_gate_reasons`` of the rows is left out.

    Columns are :data:`COLUMNS` with the per-system columns of every system in ``rows``
    after ``n_phase``; a system missing from a row is NaN there.
    """
    table = pd.DataFrame(rows).set_index(["date", "solution"])
    table = table.reindex(columns=_ordered(table.columns))
    counts = [c for c in table.columns if _is_count(c)]
    stats = {name: [] for name in AGGREGATE_ROWS}
    for solution, group in table.groupby(level="solution", sort=False):
        mean = group.mean(numeric_only=True)
        std = group.std(ddof=1, numeric_only=True)
        total = pd.Series(np.nan, index=mean.index)
        total[counts] = group[counts].sum(min_count=1)
        if "quality_gate" in group:         # a level: the worst day, no mean of levels
            total["quality_gate"] = group["quality_gate"].max()
            mean["quality_gate"] = std["quality_gate"] = np.nan
        for name, row in zip(AGGREGATE_ROWS, (mean, std, total), strict=True):
            stats[name].append(row.rename((name, solution)))
    out = pd.concat([table, pd.DataFrame([r for name in AGGREGATE_ROWS for r in stats[name]])])
    out.index = pd.MultiIndex.from_tuples(out.index, names=["date", "solution"])
    return out
