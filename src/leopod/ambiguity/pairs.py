"""Single-difference pairs of undifferenced ambiguities (between-satellite differences).

Single differencing two passes of different satellites observed by the same receiver removes
the receiver phase and code biases (Peng et al. 2021, sec. III-B, eqs. (6)-(8); Jiang et al. 2023,
"IAR-based POD with OSB products"). A pair is formed when the two passes share enough observation
time: "Single-differenced ambiguities with a common observation time of fewer than 8 minutes were
ignored" (Peng et al. 2021, sec. IV-B), hence the default ``min_common_s`` of 480 s. Only satellites
of the same system are paired: across systems the receiver biases of different signals would not
cancel.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["MIN_COMMON_S", "SdPairs", "sd_pairs"]

#: Shortest common observation time of a single-difference pair [s] (Peng et al. 2021, sec. IV-B:
#: pairs with fewer than 8 minutes were ignored).
MIN_COMMON_S = 480.0


class SdPairs(NamedTuple):
    """Single-difference pairs ``i − j`` of undifferenced ambiguities.

    Attributes
    ----------
    i, j : ndarray of int64, shape (m,)
        Indices of the two undifferenced ambiguities, ``i < j``, sorted by ``(i, j)``.
    common_start, common_end : ndarray of datetime64[ns], shape (m,)
        Common observation window ``[max(start), min(end)]`` of the pair.
    """

    i: np.ndarray
    j: np.ndarray
    common_start: np.ndarray
    common_end: np.ndarray


def sd_pairs(sv, start, end, *, min_common_s: float = MIN_COMMON_S) -> SdPairs:
    """All pairs of passes of different satellites with enough common observation time.

    Parameters
    ----------
    sv : array_like of str, shape (n,)
        Satellite of each undifferenced ambiguity (``"G05"``); the first letter is the system.
    start, end : array_like of datetime64, shape (n,)
        First and last observation of each ambiguity (e.g. ``start``/``end`` of the float
        ambiguity dataset of :func:`leopod.estimation.outputs.ambiguity_dataset`).
    min_common_s : float
        Shortest common observation time ``min(end) − max(start)`` [s] of a pair (default
        480 s, Peng et al. 2021).

    Returns
    -------
    SdPairs
        Pairs with ``i < j``, same system, different satellites and
        ``common_end − common_start >= min_common_s``.

    Raises
    ------
    ValueError
        If the arrays differ in length or an ambiguity ends before it starts.
    """
    sv = np.asarray(sv).astype(str)
    start = np.asarray(start, dtype="datetime64[ns]")
    end = np.asarray(end, dtype="datetime64[ns]")
    if not sv.shape == start.shape == end.shape or sv.ndim != 1:
        raise ValueError(f"sv, start and end must be 1-d of equal length, got shapes "
                         f"{sv.shape}, {start.shape}, {end.shape}")
    if np.any(end < start):
        bad = np.nonzero(end < start)[0]
        raise ValueError(f"ambiguities {bad.tolist()} end before they start")
    i, j = np.triu_indices(sv.size, k=1)
    common_start = np.maximum(start[i], start[j])
    common_end = np.minimum(end[i], end[j])
    common_s = (common_end - common_start) / np.timedelta64(1, "s")
    system = np.array([s[:1] for s in sv])
    keep = (sv[i] != sv[j]) & (system[i] == system[j]) & (common_s >= min_common_s)
    return SdPairs(i=i[keep].astype(np.int64), j=j[keep].astype(np.int64),
                   common_start=common_start[keep], common_end=common_end[keep])
