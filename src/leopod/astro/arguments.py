"""Fundamental (Delaunay) and Doodson arguments of the luni-solar tides and nutation.

IERS Conventions (2010) eq. (5.43) and sec. 6.2.1; shared by the solid-Earth, ocean and pole
tides of the force model and by the station displacements of the SLR model.
"""

from __future__ import annotations

import erfa
import numpy as np

__all__ = ["fundamental_arguments", "doodson_arguments"]

_S_PER_CENTURY = 86400.0 * 36525.0


def fundamental_arguments(t_tt_s_j2000) -> np.ndarray:
    """Delaunay arguments of nutation theory, IERS Conventions (2010) eq. (5.43).

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0 (used for TDB).

    Returns
    -------
    numpy.ndarray, shape (n, 5)
        l, l', F, D, Ω [rad] (from the IERS 2003 = 2010 expressions in ERFA: ``fal03``,
        ``falp03``, ``faf03``, ``fad03``, ``faom03``).
    """
    t = np.atleast_1d(np.asarray(t_tt_s_j2000, dtype=float)) / _S_PER_CENTURY
    return np.column_stack([erfa.fal03(t), erfa.falp03(t), erfa.faf03(t), erfa.fad03(t),
                            erfa.faom03(t)])


def doodson_arguments(t_tt_s_j2000, gmst_rad) -> np.ndarray:
    """Doodson arguments (τ, s, h, p, N', p_s) from the Delaunay arguments.

    IERS Conventions (2010), sec. 6.2.1, with eq. (6.8): ``s = F + Ω``, ``h = s − D``,
    ``p = s − l``, ``N' = −Ω``, ``p_s = s − D − l'``, ``τ = θ_g + π − s``.

    Parameters
    ----------
    t_tt_s_j2000 : array_like, shape (n,)
        TT seconds since J2000.0.
    gmst_rad : array_like, shape (n,)
        Greenwich mean sidereal time θ_g [rad] (e.g. ``erfa.gmst06``; not the Earth rotation
        angle, which differs by the accumulated precession in right ascension).

    Returns
    -------
    numpy.ndarray, shape (n, 6)
        τ, s, h, p, N', p_s [rad] (not reduced to [0, 2π)).
    """
    l, lp, f, d, om = fundamental_arguments(t_tt_s_j2000).T
    s = f + om
    tau = np.atleast_1d(np.asarray(gmst_rad, dtype=float)) + np.pi - s
    return np.column_stack([tau, s, s - d, s - l, -om, s - d - lp])
