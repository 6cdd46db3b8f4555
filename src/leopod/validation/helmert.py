"""Helmert transformation between two position sets: its displacement and a least-squares fit.

IERS Conventions 2010 eq. (4.4), linearised small-angle form, with 3, 6 or 7 parameters;
:func:`leopod.validation.compare.compare_orbits` removes a fitted transformation from the
reference to the orbit before the RTN statistics.
"""

from __future__ import annotations

import numpy as np

__all__ = ["HELMERT_PARAMETERS", "fit_helmert", "helmert_displacement"]

#: Helmert parameters, IERS Conventions 2010 eq. (4.4): translations [m], scale D [1],
#: rotations [rad].
HELMERT_PARAMETERS = ("tx_m", "ty_m", "tz_m", "scale", "rx_rad", "ry_rad", "rz_rad")
_HELMERT_UNITS = ("m", "m", "m", "1", "rad", "rad", "rad")
#: Parameters estimated for each allowed ``helmert`` value (indices into HELMERT_PARAMETERS).
_HELMERT_SETS = {3: (0, 1, 2), 6: (0, 1, 2, 4, 5, 6), 7: (0, 1, 2, 3, 4, 5, 6)}


def helmert_displacement(params, pos_m) -> np.ndarray:
    """``T + D r + R × r`` of the 7-parameter Helmert transformation, IERS 2010 eq. (4.4).

    ``x_s = x + T1 + D x − R3 y + R2 z``, ``y_s = y + T2 + R3 x + D y − R1 z``,
    ``z_s = z + T3 − R2 x + R1 y + D z``.

    Parameters
    ----------
    params : array_like, shape (7,)
        Values in the order of :data:`HELMERT_PARAMETERS` [m, m, m, 1, rad, rad, rad].
    pos_m : array_like, shape (n, 3)
        Positions ``x`` [m].

    Returns
    -------
    ndarray, shape (n, 3)
        ``x_s − x`` [m].
    """
    p = np.asarray(params, dtype=float)
    r = np.asarray(pos_m, dtype=float)
    return p[:3] + p[3] * r + np.cross(p[4:7], r)


def _helmert_design(pos_m: np.ndarray) -> np.ndarray:
    """Partials of eq. (4.4) with respect to all 7 parameters, shape (3n, 7)."""
    x, y, z = pos_m.T
    n = x.size
    a = np.zeros((n, 3, 7))
    a[:, 0, 0] = a[:, 1, 1] = a[:, 2, 2] = 1.0
    a[:, :, 3] = pos_m
    a[:, 0, 5], a[:, 0, 6] = z, -y
    a[:, 1, 4], a[:, 1, 6] = -z, x
    a[:, 2, 4], a[:, 2, 5] = y, -x
    return a.reshape(3 * n, 7)


def fit_helmert(pos_m, ref_pos_m, n_parameters: int = 7) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares Helmert transformation from reference positions to positions.

    Solves ``pos − ref = T + D ref + R × ref`` (IERS Conventions 2010 eq. 4.4, linearised
    small-angle form) with equal weights, by ``numpy.linalg.lstsq`` on column-scaled partials.

    Parameters
    ----------
    pos_m, ref_pos_m : array_like, shape (n, 3)
        Positions and reference positions at the same epochs, finite [m].
    n_parameters : {3, 6, 7}
        Translations only; translations and rotations; or all seven (with scale).

    Returns
    -------
    estimate : ndarray, shape (7,)
        In the order of :data:`HELMERT_PARAMETERS` (0 for parameters not estimated).
    sigma : ndarray, shape (7,)
        Formal standard deviations from the a-posteriori unit weight (NaN for parameters not
        estimated). Epoch-to-epoch correlation of orbit errors is ignored, so they are
        optimistic.
    """
    if n_parameters not in _HELMERT_SETS:
        raise ValueError(f"n_parameters must be one of {sorted(_HELMERT_SETS)}")
    pos = np.asarray(pos_m, dtype=float)
    ref = np.asarray(ref_pos_m, dtype=float)
    cols = list(_HELMERT_SETS[n_parameters])
    a = _helmert_design(ref)[:, cols]
    b = (pos - ref).reshape(-1)
    if b.size <= len(cols):
        raise ValueError(f"{pos.shape[0]} epochs cannot determine {len(cols)} Helmert parameters")
    scale = np.linalg.norm(a, axis=0)
    x, *_ = np.linalg.lstsq(a / scale, b, rcond=None)
    res = b - (a / scale) @ x
    s0_sq = float(res @ res) / (b.size - len(cols))
    cov = np.linalg.inv((a / scale).T @ (a / scale)) * s0_sq
    estimate = np.zeros(7)
    sigma = np.full(7, np.nan)
    estimate[cols] = x / scale
    sigma[cols] = np.sqrt(np.diag(cov)) / scale
    return estimate, sigma
