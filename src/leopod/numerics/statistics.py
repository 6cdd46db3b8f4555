"""Statistics over the finite entries of an array (NaN marks an unused or missing value)."""

from __future__ import annotations

import numpy as np

__all__ = ["finite_rms"]


def finite_rms(values, axis=None):
    """Root mean square of the finite entries of ``values``; NaN where there are none.

    Parameters
    ----------
    values : array_like
        Values (NaN or inf: not used).
    axis : int, optional
        Axis to reduce; None: all entries.

    Returns
    -------
    float or ndarray
        A float for ``axis=None``, else the array without ``axis``.
    """
    x = np.asarray(values, dtype=float)
    ok = np.isfinite(x)
    n = ok.sum(axis=axis)
    total = np.square(np.where(ok, x, 0.0)).sum(axis=axis)
    out = np.sqrt(np.divide(total, n, out=np.full(np.shape(n), np.nan), where=n > 0))
    return float(out) if axis is None else out
