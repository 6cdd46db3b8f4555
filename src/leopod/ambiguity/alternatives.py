"""Optional fixing strategies beside the per-SD decisions of :mod:`leopod.ambiguity.resolve`.

* :func:`wl_candidate_check` — the WL candidate check that Peng et al. (2021, sec. III-B)
  describe after Leick et al. (2015, pp. 389–391): a WL wrong by one cycle shifts the NL by
  ``f2/(f1 − f2)`` cycles (3.53 for GPS L1/L2), so its fractional part by 0.53 cycles, and
  "since the NL is an integer, ... we can use that fact to decide between two candidate WL
  ambiguities". Peng et al. (2021) also found that it fixes wrong ambiguities ("some
  unfixable NL ambiguities ... can meet the conditions of fixing decisions") that "seriously
  damage" the orbit: hence off by default and strict here — only single differences whose WL
  or NL was rejected are tried, the candidates are the two integers nearest to the float WL,
  and a candidate is taken only when its NL passes the NL decision and the other's does not.
* :func:`ils_nl_decision` — integer least squares of the NL set (LAMBDA with ratio test and
  partial fixing, :mod:`leopod.ambiguity.ils`) instead of one decision per single difference.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from leopod.ambiguity.decision import FixDecision
from leopod.ambiguity.ils import partial_ils
from leopod.ambiguity.independent import independent_edges

__all__ = ["ils_nl_decision", "wl_candidate_check"]

log = logging.getLogger(__name__)


def wl_candidate_check(wl_value_cyc, wl: FixDecision, nl_value_cyc, nl: FixDecision,
                       nl_sigma_cyc, wl_factor: float,
                       decide_nl: Callable[[np.ndarray, np.ndarray], FixDecision]
                       ) -> tuple[FixDecision, np.ndarray, FixDecision]:
    """Choose between the two nearest WL integers by the integer nature of the NL.

    Parameters
    ----------
    wl_value_cyc : array_like, shape (m,)
        Float SD WL [WL cycles].
    wl : FixDecision
        WL decision.
    nl_value_cyc : array_like, shape (m,)
        Float SD NL computed with ``where(wl.fixed, wl.integer, 0)`` [NL cycles].
    nl : FixDecision
        NL decision on them.
    nl_sigma_cyc : array_like, shape (m,)
        NL sigmas [NL cycles].
    wl_factor : float
        ``f2/(f1 − f2)``: NL cycles per WL cycle (Peng et al. 2021, eq. (8)).
    decide_nl : callable
        ``decide_nl(value, sigma) -> FixDecision``: the campaign's NL decision.

    Returns
    -------
    wl, nl_value_cyc, nl
        Updated WL decision (fixed to the chosen candidate, reason "WL by NL candidate
        check"), NL floats with the chosen WL, and NL decision.
    """
    x = np.asarray(wl_value_cyc, dtype=float)
    nl_value = np.asarray(nl_value_cyc, dtype=float).copy()
    sigma = np.asarray(nl_sigma_cyc, dtype=float)
    used = np.where(wl.fixed, wl.integer, 0)
    base = nl_value + wl_factor * used                 # NL float for a WL of zero
    near = np.floor(np.where(np.isfinite(x), x, 0.0) + 0.5)
    second = near + np.where(x >= near, 1.0, -1.0)
    tried = np.isfinite(x) & np.isfinite(base) & ~(wl.fixed & nl.fixed)
    d_near = decide_nl(base - wl_factor * near, sigma)
    d_second = decide_nl(base - wl_factor * second, sigma)
    take_near = tried & d_near.fixed & ~d_second.fixed
    take_second = tried & d_second.fixed & ~d_near.fixed
    take = take_near | take_second
    chosen = np.where(take_second, second, near).astype(np.int64)
    wl_int = np.where(take, chosen, wl.integer)
    wl_new = FixDecision(wl_int, np.where(take, x - chosen, wl.fraction_cyc), wl.fixed | take,
                         np.where(take, "WL by NL candidate check", wl.reason))
    nl_value[take] = (base - wl_factor * chosen)[take]

    def pick(near_value, second_value, old_value):
        return np.where(take_second, second_value, np.where(take_near, near_value, old_value))

    nl_new = FixDecision(pick(d_near.integer, d_second.integer, nl.integer),
                         pick(d_near.fraction_cyc, d_second.fraction_cyc, nl.fraction_cyc),
                         nl.fixed | take, pick(d_near.reason, d_second.reason, nl.reason))
    log.info("WL candidate check: %d of %d tried single differences fixed (%d to the second "
             "nearest WL)", int(take.sum()), int(tried.sum()), int(take_second.sum()))
    return wl_new, nl_value, nl_new


def ils_nl_decision(value_cyc, covariance_cyc2, i, j, eligible, *, min_ratio: float,
                    min_success_rate: float) -> FixDecision:
    """NL fixing by integer least squares of a maximal independent set (module docstring).

    Parameters
    ----------
    value_cyc : array_like, shape (m,)
        Float SD NL [cycles].
    covariance_cyc2 : array_like, shape (m, m)
        Their covariance [cycles²] (may be singular over dependent single differences).
    i, j : array_like of int, shape (m,)
        Ambiguity indices of each single difference.
    eligible : array_like of bool, shape (m,)
        Single differences that may be fixed (WL fixed, finite value).
    min_ratio, min_success_rate : float
        Ratio-test critical value and smallest bootstrapped success rate.

    Returns
    -------
    FixDecision
        ILS integers where fixed; the nearest integer elsewhere, with the reason.
    """
    x = np.asarray(value_cyc, dtype=float)
    q = np.asarray(covariance_cyc2, dtype=float)
    i, j = np.asarray(i), np.asarray(j)
    ok = np.asarray(eligible, bool) & np.isfinite(x) & np.isfinite(np.diag(q))
    near = np.floor(np.where(np.isfinite(x), x, 0.0) + 0.5)
    integer = near.astype(np.int64)
    fixed = np.zeros(x.size, dtype=bool)
    reason = np.full(x.size, "not eligible (WL not fixed or value not finite)", dtype=object)
    cand = np.flatnonzero(ok)
    reason[cand] = "dependent on the ILS set"
    if cand.size:
        sigma = np.sqrt(np.clip(np.diag(q)[cand], 0.0, None))
        subset = cand[independent_edges(i[cand], j[cand], key=sigma)]
        done, res = partial_ils(x[subset], q[np.ix_(subset, subset)], min_ratio=min_ratio,
                                min_success_rate=min_success_rate)
        reason[subset] = "left float by partial ILS (ratio or success-rate test)"
        if res is not None:
            fixed[subset[done]] = True
            integer[subset[done]] = res.integer
            reason[subset[done]] = ""
            log.info("ILS NL: %d of %d independent fixed, ratio %.2f, success rate %.6f",
                     int(done.sum()), subset.size, res.ratio, res.success_rate)
        else:
            log.info("ILS NL: no subset of %d passes the tests", subset.size)
    frac = np.where(np.isfinite(x), x - integer, np.nan)
    return FixDecision(integer, frac, fixed, reason)
