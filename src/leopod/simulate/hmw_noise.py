"""Time-correlated HMW noise for testing wide-lane statistics (issue 19, honest AR statistics).

An HMW single-difference series in wide-lane cycles is modelled as white noise plus a
first-order Gauss–Markov (AR(1)) process, the usual stand-in for code multipath that varies
with the slowly changing signal direction (first-order Gauss–Markov process: Gelb 1974)::

    x_k = m_k + w_k,    m_k = ρ m_{k−1} + sqrt(1 − ρ²) σ_m u_k,    ρ = exp(−Δt/τ),

``w_k ~ N(0, σ_w²)``, ``u_k ~ N(0, 1)``, ``m_0 ~ N(0, σ_m²)`` (stationary from the first
epoch). :func:`sd_arc` lays many such single differences out as (time, sv) arrays that
:func:`leopod.ambiguity.wide_lane.sd_wide_lane` reads, so a test goes through the production
code.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import xarray as xr

__all__ = ["SdArc", "gauss_markov_series", "sd_arc"]

_T0 = np.datetime64("2019-01-01T00:00", "ns")


def gauss_markov_series(rng: np.random.Generator, n: int, white_sigma: float,
                        markov_sigma: float, tau_s: float, step_s: float) -> np.ndarray:
    """One stationary series of white plus first-order Gauss–Markov noise (module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
    n : int
        Epochs.
    white_sigma, markov_sigma : float
        ``σ_w``, ``σ_m`` [cycles].
    tau_s : float
        Correlation time [s] (> 0).
    step_s : float
        Sampling interval [s].

    Returns
    -------
    ndarray, shape (n,)
        [cycles].
    """
    rho = np.exp(-step_s / tau_s)
    u = rng.standard_normal(n)
    m = np.empty(n)
    m[0] = markov_sigma * u[0]
    drive = markov_sigma * np.sqrt(1.0 - rho * rho) * u
    for k in range(1, n):
        m[k] = rho * m[k - 1] + drive[k]
    return m + white_sigma * rng.standard_normal(n)


class SdArc(NamedTuple):
    """Single differences laid out for :func:`~leopod.ambiguity.wide_lane.sd_wide_lane`.

    ``hmw_cyc`` (time, sv) holds SD ``k`` in column ``k`` (pass id ``k + 1``) and a reference
    pass of zeros (pass id 0) in the last column, so ``sd_wide_lane(hmw_cyc, pass_id, id_i,
    id_j)`` averages exactly series ``k``.
    """

    hmw_cyc: xr.DataArray
    pass_id: xr.DataArray
    id_i: np.ndarray          # (m,)
    id_j: np.ndarray          # (m,)
    true_cyc: np.ndarray      # (m,) true integers


def sd_arc(rng: np.random.Generator, lengths, white_sigma, markov_sigma, tau_s: float,
           step_s: float, offset_cyc=0.0, max_integer: int = 10) -> SdArc:
    """Many simulated SD HMW series with known integers (module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
    lengths : array_like of int, shape (m,)
        Epochs of each single difference.
    white_sigma, markov_sigma : array_like, shape (m,) or scalar
        Noise levels [cycles].
    tau_s : float
        Correlation time of the Gauss–Markov part [s], common to the arc.
    step_s : float
        Sampling interval [s].
    offset_cyc : array_like, shape (m,) or scalar
        Constant error added to a series [cycles] (0: unbiased; e.g. a half cycle or one cycle
        of an unmodelled code bias or a wrong product).
    max_integer : int
        True integers are uniform in ``[−max_integer, max_integer]``.

    Returns
    -------
    SdArc
    """
    lengths = np.asarray(lengths, dtype=np.int64)
    m = lengths.size
    white = np.broadcast_to(np.asarray(white_sigma, float), (m,))
    markov = np.broadcast_to(np.asarray(markov_sigma, float), (m,))
    offset = np.broadcast_to(np.asarray(offset_cyc, float), (m,))
    truth = rng.integers(-max_integer, max_integer + 1, m)
    n_t = int(lengths.max())
    h = np.full((n_t, m + 1), np.nan)
    pid = np.full((n_t, m + 1), -1, dtype=np.int64)
    for k in range(m):
        n = lengths[k]
        h[:n, k] = truth[k] + offset[k] + gauss_markov_series(rng, n, white[k], markov[k],
                                                               tau_s, step_s)
        pid[:n, k] = k + 1
    h[:, m], pid[:, m] = 0.0, 0
    time = _T0 + (np.arange(n_t) * step_s * 1e9).astype("timedelta64[ns]")
    coords = {"time": time, "sv": [f"S{k:05d}" for k in range(m + 1)]}
    return SdArc(xr.DataArray(h, coords=coords, dims=("time", "sv")),
                 xr.DataArray(pid, coords=coords, dims=("time", "sv")),
                 np.arange(1, m + 1), np.zeros(m, dtype=np.int64), truth)
