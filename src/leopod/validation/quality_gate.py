"""Quality gate of a POD day: figures of the solution against thresholds -> ok, suspect, failed.

A day's orbit is not trusted blindly: data faults that the estimator survives without an error
(an unannounced manoeuvre, products of one satellite gone wrong, a day with half its data)
leave their marks in a few figures of the solution, and the gate checks them
(``pod.quality_gate`` of the campaign schema, defaults there):

========================  =====================================================================
figure                    meaning
========================  =====================================================================
``phase_rms_mm``          post-fit ionosphere-free phase residual RMS [mm]
``code_rms_m``            post-fit ionosphere-free code residual RMS [m]
``sigma0``                a-posteriori standard deviation of unit weight
``position_sigma_cm``     largest formal 3D position sigma of the orbit (sigma0-scaled) [cm]
``apriori_diff_m``        3D RMS of the orbit minus its a-priori (code-only) orbit [m]
``coverage_pct``          share of the day with phase observations in the solution [%]
``overlap_3d_cm``         3D RMS of the overlap with the next day's arc [cm] (campaign summary)
========================  =====================================================================

A figure beyond its threshold (below it for the coverage) makes the day *suspect*; beyond
``failed_factor`` times the threshold (below threshold / factor for the coverage), or a POD that
did not converge, makes it *failed*. A figure that is not available (NaN, e.g. no overlap on
the last day) is not checked. The POD steps log the verdict and keep it, with the figures, in
the attributes of their parameters file (:func:`stamp`); the campaign summary repeats the check
with the overlap added (column ``quality_gate``: 0 ok, 1 suspect, 2 failed) and lists the
reasons.

The thresholds are limits of plausibility, not accuracy claims. The default campaign's
simulated day (tests/estimation/test_pod_faults.py, float POD of 1-5 h) has a phase RMS of
7.9 mm, a code RMS of 1.5 m, sigma0 1.8, formal sigmas below 3 cm and an a-priori difference
of 4 m (the code-only orbit's noise); a 2-h data gap raises the largest formal sigma to 16 cm
(the orbit error there is 14 cm: suspect), an unannounced 5-cm/s burn the phase RMS to 33 cm
and sigma0 to 10 (failed).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.numerics.statistics import finite_rms
from leopod.settings import Settings

__all__ = ["FIGURES", "STATUS", "GateSettings", "Verdict", "check", "pod_figures", "stamp",
           "stamped_figures"]

#: Verdicts in increasing severity (the summary's ``quality_gate`` column is the index).
STATUS = ("ok", "suspect", "failed")
#: Figure -> (settings field of its threshold, True if a larger value is worse).
FIGURES = {"phase_rms_mm": ("max_phase_rms_mm", True),
           "code_rms_m": ("max_code_rms_m", True),
           "sigma0": ("max_sigma0", True),
           "position_sigma_cm": ("max_position_sigma_cm", True),
           "apriori_diff_m": ("max_apriori_diff_m", True),
           "coverage_pct": ("min_coverage_pct", False),
           "overlap_3d_cm": ("max_overlap_3d_cm", True)}
_ATTR = "gate_"


@dataclass(frozen=True)
class GateSettings(Settings):
    """Thresholds of the quality gate (config ``pod.quality_gate``; module docstring).

    Attributes
    ----------
    max_phase_rms_mm, max_code_rms_m, max_sigma0, max_position_sigma_cm, max_apriori_diff_m,
    max_overlap_3d_cm : float
        Largest value of each figure of an ok day [mm, m, 1, cm, m, cm].
    min_coverage_pct : float
        Smallest share of the nominal arc with phase observations of an ok day [%].
    failed_factor : float
        A figure this many times beyond its threshold fails the day (> 1).
    """

    SCHEMA_DEF = "quality_gate"

    max_phase_rms_mm: float
    max_code_rms_m: float
    max_sigma0: float
    max_position_sigma_cm: float
    max_apriori_diff_m: float
    min_coverage_pct: float
    max_overlap_3d_cm: float
    failed_factor: float


@dataclass(frozen=True)
class Verdict:
    """Result of :func:`check`: ``status`` (one of :data:`STATUS`) and one reason per figure
    beyond its threshold (e.g. ``"phase_rms_mm 31.2 > 15"``)."""

    status: str
    reasons: tuple[str, ...]

    @property
    def level(self) -> int:
        """Index of the status in :data:`STATUS` (0 ok, 1 suspect, 2 failed)."""
        return STATUS.index(self.status)

    def __str__(self) -> str:
        return self.status + (f" ({'; '.join(self.reasons)})" if self.reasons else "")


def check(figures: Mapping[str, float], settings: GateSettings, *,
          converged: bool = True) -> Verdict:
    """The verdict on a day from its ``figures`` (keys of :data:`FIGURES`; missing or NaN
    ones are not checked) and whether its POD converged."""
    level, reasons = (0, []) if converged else (2, ["POD not converged"])
    for name, (field, larger_is_worse) in FIGURES.items():
        value = float(figures.get(name, np.nan))
        limit = float(getattr(settings, field))
        if not np.isfinite(value):
            continue
        beyond = value > limit if larger_is_worse else value < limit
        if not beyond:
            continue
        far = (value > limit * settings.failed_factor if larger_is_worse
               else value < limit / settings.failed_factor)
        level = max(level, 2 if far else 1)
        reasons.append(f"{name} {value:.4g} {'>' if larger_is_worse else '<'} {limit:g}")
    return Verdict(STATUS[level], tuple(reasons))


def pod_figures(orbit: xr.Dataset, residuals: xr.Dataset, parameters: xr.Dataset,
                span, sampling_s: float) -> dict[str, float]:
    """The POD figures of :data:`FIGURES` (all but the overlap) of one solution.

    Parameters
    ----------
    orbit, residuals, parameters : xarray.Dataset
        Orbit (``sigma_rtn_m``, ``apriori_diff_rtn_m`` (time, rtn) [m]), residuals
        (``phase_residual_m``, ``code_residual_m`` [m], NaN where not used) and parameters
        (attribute ``sigma0``) of :mod:`leopod.estimation.outputs`.
    span : (datetime64, datetime64)
        Start and end of the time the orbit is for (the day; ``coverage_pct`` refers to it).
    sampling_s : float
        Observation sampling [s] (an epoch with phases covers this long).
    """
    phase = residuals.phase_residual_m.values
    code = residuals.code_residual_m.values
    start, end = (np.datetime64(t, "ns") for t in span)
    t = residuals.time.values
    inside = (t >= start) & (t < end)
    epochs = np.isfinite(phase[inside]).reshape(int(inside.sum()), -1).any(axis=1)
    span_s = (end - start) / np.timedelta64(1, "s")
    sigma = np.sqrt(np.sum(orbit.sigma_rtn_m.values**2, axis=1))
    diff = np.sum(orbit.apriori_diff_rtn_m.values**2, axis=1)
    return {"phase_rms_mm": 1e3 * finite_rms(phase), "code_rms_m": finite_rms(code),
            "sigma0": float(parameters.attrs.get("sigma0", np.nan)),
            "position_sigma_cm": 100 * float(np.nanmax(sigma)) if np.isfinite(sigma).any()
            else np.nan,
            "apriori_diff_m": float(np.sqrt(np.nanmean(diff))) if np.isfinite(diff).any()
            else np.nan,
            "coverage_pct": min(100.0, 100.0 * int(epochs.sum()) * sampling_s / span_s)}


def stamp(parameters: xr.Dataset, figures: Mapping[str, float], verdict: Verdict) -> None:
    """Keep the verdict and its figures in the attributes of a POD parameters dataset
    (``quality_gate``, ``quality_gate_reasons``, ``gate_<figure>``)."""
    parameters.attrs["quality_gate"] = verdict.status
    parameters.attrs["quality_gate_reasons"] = "; ".join(verdict.reasons)
    for name, value in figures.items():
        parameters.attrs[_ATTR + name] = float(value)


def stamped_figures(parameters: xr.Dataset) -> dict[str, float]:
    """The figures :func:`stamp` kept in ``parameters`` (empty for a file without them)."""
    return {name: float(parameters.attrs[_ATTR + name]) for name in FIGURES
            if _ATTR + name in parameters.attrs}
