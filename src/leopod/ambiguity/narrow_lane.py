"""Narrow-lane (NL) ambiguities from the float ionosphere-free ambiguities and fixed WL.

The float ionosphere-free (IF) ambiguity of a pass in metres (float POD,
:func:`leopod.estimation.outputs.ambiguity_dataset`) is, with ``λ_NL = c/(f1 + f2)``::

    B_IF = λ_NL N1 + λ_NL f2/(f1 − f2) N_WL + b_r,IF + b^s_IF,     N_WL = N1 − N2,

(Peng et al. 2021, eq. (5); Jiang et al. 2023, eq. (3):
``N_IF = f1 f2/(f1² − f2²) N_WL + f1/(f1 + f2) N_NL`` in units of ``λ_IF = λ1``, the same thing
since ``λ1 f1/(f1 + f2) = λ_NL`` and ``λ1 f1 f2/(f1² − f2²) = λ_NL f2/(f1 − f2)``; the PDF text of
Jiang et al. (2023) eq. (3) is garbled and was re-derived). ``b_r,IF`` is the receiver IF phase
bias; ``b^s_IF`` the satellite one: zero with integer-recovery clocks that hold it (CNES/CLS GRG
clocks, used with WL biases only; :func:`leopod.simulate.biases.integer_clock_s`), and the IF
combination of the phase OSBs, ``(f1² p1 − f2² p2)/(f1² − f2²)``, with clocks that are to be used
together with phase OSBs (:func:`sat_if_phase_bias_osb`; "corrected = observed − OSB", so
the uncorrected phase carries ``+p_i``). If the OSBs were already subtracted from the observations
before the float POD, ``b^s_IF`` is zero here too.

Single difference ``i − j`` with a fixed ``ΔN_WL`` (Peng et al. 2021, eq. (8), where ``ΔB^s_1`` is
dropped because the integer clocks hold the NL bias)::

    ΔN1 = (ΔB_IF − Δb^s_IF)/λ_NL − f2/(f1 − f2) ΔN_WL.

Eq. (10) of the BDS SCB-AR paper prints ``f2/(f1 + f2)`` for the WL factor (text as extracted): a
typo; ``f2/(f1 − f2)`` follows from eq. (5) above and agrees with Peng et al. (2021) eq. (8).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import xarray as xr

from leopod.ambiguity.wide_lane import _pair_frequencies, sat_osb_m
from leopod.gnss.combinations import ionosphere_free, narrow_lane_wavelength_m

__all__ = ["SdNarrowLane", "fixed_sd_if_m", "sat_if_phase_bias_osb", "sd_covariance_m2",
           "sd_narrow_lane"]


def _wl_factor(f1_hz: float, f2_hz: float) -> float:
    """``f2/(f1 − f2)``: NL cycles per WL cycle in the IF ambiguity (Peng et al. 2021, eq. (8))."""
    return f2_hz / (f1_hz - f2_hz)


class SdNarrowLane(NamedTuple):
    """Single-difference float NL ambiguities ``i − j``.

    Attributes
    ----------
    value_cyc : ndarray, shape (m,)
        Float ``ΔN1`` [NL cycles].
    sigma_cyc : ndarray, shape (m,)
        Formal sigma ``sqrt(var_i + var_j − 2 cov_ij)/λ_NL`` [NL cycles] (the fixed WL has
        no variance).
    """

    value_cyc: np.ndarray
    sigma_cyc: np.ndarray


def _pair_indices(i, j, n: int) -> tuple[np.ndarray, np.ndarray]:
    i = np.asarray(i, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    if i.shape != j.shape or i.ndim != 1:
        raise ValueError(f"i and j must be 1-d of equal length, got {i.shape} and {j.shape}")
    if np.any((i < 0) | (i >= n) | (j < 0) | (j >= n)):
        raise ValueError(f"pair indices must lie in [0, {n})")
    return i, j


def sd_covariance_m2(covariance_m2, i, j) -> np.ndarray:
    """Covariance of the single differences ``B_i − B_j`` [m²].

    ``C_sd = D C D^T`` with ``D`` the (m, n) matrix of +1 at ``i`` and −1 at ``j``, i.e.
    ``C[i, i'] − C[i, j'] − C[j, i'] + C[j, j']`` for rows ``(i, j)`` and columns
    ``(i', j')``.

    Parameters
    ----------
    covariance_m2 : array_like, shape (n, n)
        Covariance of the undifferenced float IF ambiguities [m²].
    i, j : array_like of int, shape (m,)
        Pair indices.

    Returns
    -------
    ndarray, shape (m, m)
    """
    c = np.asarray(covariance_m2, dtype=float)
    i, j = _pair_indices(i, j, c.shape[0])
    return (c[np.ix_(i, i)] - c[np.ix_(i, j)] - c[np.ix_(j, i)] + c[np.ix_(j, j)])


def sd_narrow_lane(value_m, covariance_m2, i, j, n_wl_sd, f1_hz: float, f2_hz: float, *,
                   sat_bias_m=None) -> SdNarrowLane:
    """Single-difference float NL ambiguities from float IF ambiguities and fixed WL.

    ``ΔN1 = (ΔB_IF − Δb^s_IF)/λ_NL − f2/(f1 − f2) ΔN_WL`` (Peng et al. 2021, eq. (8); module
    docstring).

    Parameters
    ----------
    value_m : array_like, shape (n,)
        Float IF ambiguities ``B_IF`` [m] (``value_m`` of the float ambiguity dataset).
    covariance_m2 : array_like, shape (n, n)
        Their covariance [m²] (``covariance_m2``).
    i, j : array_like of int, shape (m,)
        Pair indices (into the n ambiguities).
    n_wl_sd : array_like of int, shape (m,)
        Fixed ``ΔN_WL = N_WL,i − N_WL,j``.
    f1_hz, f2_hz : float
        Frequencies of the IF combination [Hz].
    sat_bias_m : array_like, shape (n,), optional
        Satellite IF phase bias ``b^s_IF`` of each undifferenced ambiguity [m]
        (:func:`sat_if_phase_bias_osb` at the ambiguity's satellite and epoch) when OSBs are
        used with ordinary clocks; None (zero) with integer-recovery clocks.

    Returns
    -------
    SdNarrowLane
    """
    b = np.asarray(value_m, dtype=float)
    if sat_bias_m is not None:
        b = b - np.asarray(sat_bias_m, dtype=float)
    c = np.asarray(covariance_m2, dtype=float)
    i, j = _pair_indices(i, j, b.size)
    lam_nl = narrow_lane_wavelength_m(f1_hz, f2_hz)
    value = (b[i] - b[j]) / lam_nl - _wl_factor(f1_hz, f2_hz) * np.asarray(n_wl_sd)
    var = c[i, i] + c[j, j] - 2.0 * c[i, j]
    return SdNarrowLane(value_cyc=value, sigma_cyc=np.sqrt(np.clip(var, 0.0, None)) / lam_nl)


def fixed_sd_if_m(n_wl_sd, n_nl_sd, f1_hz: float, f2_hz: float, *, sat_bias_sd_m=0.0):
    """Fixed single-difference IF ambiguity ``B_i − B_j`` [m] from integer WL and NL.

    ``ΔB_IF = λ_NL (ΔN1 + f2/(f1 − f2) ΔN_WL) + Δb^s_IF`` (Peng et al. 2021, eq. (7); module
    docstring): the value the float parameters ``B_i − B_j`` are constrained to.

    Parameters
    ----------
    n_wl_sd, n_nl_sd : array_like of int
        Fixed ``ΔN_WL`` and ``ΔN1``.
    f1_hz, f2_hz : float
        Frequencies [Hz].
    sat_bias_sd_m : array_like, optional
        ``b^s_IF,i − b^s_IF,j`` [m] removed before fixing (:func:`sd_narrow_lane`'s
        ``sat_bias_m``), added back so that the value refers to the float parameters.
    """
    lam_nl = narrow_lane_wavelength_m(f1_hz, f2_hz)
    return (lam_nl * (np.asarray(n_nl_sd) + _wl_factor(f1_hz, f2_hz) * np.asarray(n_wl_sd))
            + np.asarray(sat_bias_sd_m, dtype=float))


def sat_if_phase_bias_osb(ds: xr.Dataset, svs, epoch, *, phase=("L1C", "L2W")) -> xr.DataArray:
    """Satellite IF phase bias ``b^s_IF`` [m]: IF combination of the phase OSBs.

    ``b^s_IF = (f1² p1 − f2² p2)/(f1² − f2²)`` with phase OSBs ``p_i = λ_i β^s_i`` [m].
    Subtract it from the float IF ambiguity when the clocks are meant to be used with the
    phase OSBs (e.g. the simulator's OSB product with its ordinary clocks; for a real product
    check the clock/bias consistency stated by its provider) and the observations were not
    corrected; with integer-recovery clocks (CNES/CLS) it is already in the clock.

    Parameters
    ----------
    ds : xarray.Dataset
        Output of :func:`leopod.io.bias_sinex.read_bias_sinex`.
    svs : sequence of str
        Satellites.
    epoch : datetime64 or str
        Epoch (file time system).
    phase : tuple of str
        Phase signals of the IF combination.

    Returns
    -------
    xarray.DataArray, (sv)
        ``b^s_IF`` [m]; NaN where a phase OSB is missing.
    """
    table = sat_osb_m(ds, svs, list(phase), epoch)
    out = np.full(table.sizes["sv"], np.nan)
    for system in sorted({str(s)[0] for s in table["sv"].values}):
        rows = np.array([str(s)[0] == system for s in table["sv"].values])
        f1, f2 = _pair_frequencies(system, phase, phase)
        out[rows] = ionosphere_free(table.values[rows, 0], table.values[rows, 1], f1, f2)
    return xr.DataArray(out, dims="sv", coords={"sv": table["sv"].values},
                        attrs={"units": "m", "long_name": "satellite ionosphere-free phase "
                                                          "bias (IF of the phase OSBs)"})
