"""Product consistency guard: refuse an AR product whose fractional parts do not cluster at 0.

With a bias product that fits the observations and the clocks, every single-difference (SD)
float ambiguity corrected by it is an integer plus noise; with a wrong one (a flipped sign,
biases and clocks of different analysis centres, biases of another signal) each satellite
``s`` keeps an unknown error ``e^s`` and the SD of passes of satellites ``s`` and ``k`` sits at
``frac(e^s − e^k)``: the fixing decisions then still fix a share of them, to wrong integers
(issue 19: 1 344 wrong WL fixes with a flipped OSB sign). The guard tests, before anything is
fixed, whether the fractional parts cluster near zero.

Test (per lane, WL then NL), on the SD float values ``x_r`` [cycles] as angles ``2π x_r``:

* statistic: the mean cosine ``C̄ = mean_r cos(2π x_r)`` (the V statistic of a test of
  uniformity against the specified mean direction 0; Mardia & Jupp 2000, sec. 6.3): near 1 when the
  SDs cluster at integers, near 0 without clustering, negative for a cluster at half a cycle;
* null hypothesis "the product says nothing about the satellites' fractional biases": the
  errors ``e^s`` are independent and uniform on the circle, independent of integers and
  noise. The joint distribution of the SDs is then unchanged by any rotation
  ``x_r → x_r + u_s − u_k`` of the satellites of each SD, so the null distribution of ``C̄``
  given the data is that of ``C̄`` over uniformly drawn rotations ``u`` (a randomization
  test under a group of transformations, Hoeffding 1952). Unlike a test that counts SDs as
  independent, it holds whatever the number of passes per satellite and the sharing of
  satellites between SDs (tests/ambiguity/test_ambiguity_consistency.py measures its size);
* p-value ``(1 + #{C̄_m ≥ C̄}) / (M + 1)`` over ``M`` draws of a fixed-seed generator
  (Phipson & Smyth 2010: never zero, exact size), deterministic for given inputs;
* also reported: ``u = C̄ / σ0`` with the exact null standard deviation
  ``σ0² = Σ_p |Z_p|² / (2 N²)`` (``Z_p`` the sum of ``exp(2πi x_r)`` over the SDs of satellite
  pair ``p``, ``N`` SDs; pairs are uncorrelated under the rotations), the mean resultant length
  ``R̄`` and the mean direction (Fisher 1993, ch. 2). For a wrapped normal of standard
  deviation ``σ`` [cycles], ``C̄ = exp(−2 π² σ²)``.

The product is accepted when the WL test, and then the NL test on the SDs whose WL was
fixed, reject the null hypothesis at ``alpha`` (``p <= alpha``) with at least ``min_pairs``
independent satellite pairs (satellites − connected components of the satellite graph);
otherwise it is refused and nothing is fixed. The direction 0 is part of the hypothesis of a
consistent product, so a cluster away from 0 (e.g. at half a cycle) fails too.

Second screen, per fix (:func:`float_consistent`): a fixed NL whose constraint would move the
float SD by more than ``max_shift_sigma`` of its formal sigma (``|x − round(x)| / σ``) is
not fixed: an integer that far from the float value is at odds with the float solution
(the Dong & Bock (1989) probability alone accepts any ``|x − round(x)| < 0.5`` when ``σ`` is
small).
"""

from __future__ import annotations

import logging
from typing import NamedTuple

import numpy as np

from leopod.ambiguity.independent import graph_rank

__all__ = ["GUARD_DRAWS", "ClusteringTest", "PairSums", "ProductVerdict", "float_consistent",
           "product_verdict", "rotation_test", "satellite_pair_sums"]

log = logging.getLogger(__name__)

#: Random rotations of the guard's randomization test (Monte-Carlo standard error of a p-value
#: of 0.001: 1e-4).
GUARD_DRAWS = 99_999
#: Seed of the rotations (fixed: the same inputs give the same p-value).
GUARD_SEED = 19
_CHUNK = 2000


def _check_alpha(alpha: float) -> None:
    if not 0.0 < alpha < 0.5:
        raise ValueError(f"guard significance alpha must lie in (0, 0.5), got {alpha}")


class ClusteringTest(NamedTuple):
    """Randomization test of one lane's fractional parts (module docstring).

    Attributes
    ----------
    lane : str
        ``"WL"`` or ``"NL"``.
    n_sd : int
        SDs tested.
    n : int
        Independent satellite pairs (satellites − components of the satellite graph).
    mean_cos : float
        ``C̄`` [1] (1: all at integers; 0: no clustering at 0); NaN without SDs.
    mean_resultant_length : float
        ``R̄`` [1] (clustering around any direction).
    mean_direction_cyc : float
        Circular mean of the fractions [cycles] in [−0.5, 0.5).
    statistic : float
        ``u = C̄ / σ0`` [1] (null standard deviations).
    p_value : float
        Randomization p-value; NaN without SDs.
    fraction_cyc : ndarray, shape (n_sd,)
        The tested fractions [cycles] in [−0.5, 0.5) (for the histogram).
    """

    lane: str
    n_sd: int
    n: int
    mean_cos: float
    mean_resultant_length: float
    mean_direction_cyc: float
    statistic: float
    p_value: float
    fraction_cyc: np.ndarray

    def passed(self, alpha: float, min_pairs: int) -> bool:
        """Whether the null is rejected at ``alpha`` with at least ``min_pairs`` pairs."""
        return bool(self.n >= min_pairs and self.p_value <= alpha)

    def describe(self) -> str:
        """One line with the figures of the test, for logs and the table."""
        return (f"{self.lane}: {self.n_sd} SDs over {self.n} independent satellite pairs, "
                f"mean cos = {self.mean_cos:.3f} (u = {self.statistic:.2f}), p = "
                f"{self.p_value:.2g}, R = {self.mean_resultant_length:.3f}, mean direction "
                f"{self.mean_direction_cyc:+.3f} cyc")


class PairSums(NamedTuple):
    """SD unit vectors summed per satellite pair (:func:`satellite_pair_sums`)."""

    node_a: np.ndarray     # (p,) index of the first satellite in ``satellites``
    node_b: np.ndarray     # (p,) index of the second satellite (a < b)
    z: np.ndarray          # (p,) complex sum of exp(2πi x) of the pair's SDs, oriented a − b
    count: np.ndarray      # (p,) SDs of the pair
    satellites: np.ndarray  # (s,) sorted satellite names
    fraction_cyc: np.ndarray  # (n_sd,) fractions of the SDs used, in [−0.5, 0.5)


def satellite_pair_sums(sv_i, sv_j, value_cyc) -> PairSums:
    """Sum the unit vectors ``exp(2πi x)`` of the SDs of each satellite pair.

    Parameters
    ----------
    sv_i, sv_j : array_like of str, shape (m,)
        Satellites of the two passes of each SD ``i − j``.
    value_cyc : array_like, shape (m,)
        SD float values [cycles]; non-finite ones and SDs of one satellite are skipped.

    Returns
    -------
    PairSums
        An SD ``i − j`` with ``sv_i > sv_j`` enters as ``−x``.

    Raises
    ------
    ValueError
        If the shapes differ.
    """
    a = np.asarray(sv_i).astype(str)
    b = np.asarray(sv_j).astype(str)
    v = np.asarray(value_cyc, dtype=float)
    if not a.shape == b.shape == v.shape or v.ndim != 1:
        raise ValueError(f"sv_i, sv_j and value_cyc must be 1-d of one length, got "
                         f"{a.shape}, {b.shape}, {v.shape}")
    keep = np.isfinite(v) & (a != b)
    a, b, v = a[keep], b[keep], v[keep]
    sats, node = np.unique(np.concatenate([a, b]), return_inverse=True)
    na, nb = node[:a.size], node[a.size:]
    flip = na > nb
    lo, hi = np.where(flip, nb, na), np.where(flip, na, nb)
    unit = np.exp(2j * np.pi * np.where(flip, -v, v))
    keys, inverse = np.unique(lo * max(sats.size, 1) + hi, return_inverse=True)
    z = (np.bincount(inverse, weights=unit.real, minlength=keys.size)
         + 1j * np.bincount(inverse, weights=unit.imag, minlength=keys.size))
    count = np.bincount(inverse, minlength=keys.size)
    n_sat = max(sats.size, 1)
    return PairSums(keys // n_sat, keys % n_sat, z, count, sats, v - np.floor(v + 0.5))


def rotation_test(sv_i, sv_j, value_cyc, lane: str = "", *, draws: int = GUARD_DRAWS,
                  seed: int = GUARD_SEED) -> ClusteringTest:
    """Randomization test of clustering at 0 under satellite rotations (module docstring).

    Parameters
    ----------
    sv_i, sv_j : array_like of str, shape (m,)
        Satellites of the two passes of each SD.
    value_cyc : array_like, shape (m,)
        SD float values corrected by the product [cycles] (NaN: not used).
    lane : str
        Label.
    draws : int
        Random rotations ``M`` (>= 1).
    seed : int
        Seed of the rotations.

    Returns
    -------
    ClusteringTest
    """
    if draws < 1:
        raise ValueError(f"draws must be >= 1, got {draws}")
    ps = satellite_pair_sums(sv_i, sv_j, value_cyc)
    n_sd = int(ps.count.sum())
    n_indep = graph_rank(ps.node_a, ps.node_b) if ps.z.size else 0
    if n_sd == 0:
        return ClusteringTest(lane, 0, 0, np.nan, np.nan, np.nan, np.nan, np.nan,
                              ps.fraction_cyc)
    total = ps.z.sum() / n_sd
    observed = total.real
    sigma0 = np.sqrt(np.sum(np.abs(ps.z) ** 2) / 2.0) / n_sd
    # Σ_p z_p exp(2πi(u_a − u_b)) = Σ_a e_a Σ_b Z_ab ē_b with e_s = exp(2πi u_s) and the
    # pair sums in the matrix Z (s, s): one matrix product per chunk of draws
    n_sat = ps.satellites.size
    zmat = np.zeros((n_sat, n_sat), dtype=complex)
    np.add.at(zmat, (ps.node_a, ps.node_b), ps.z)
    rng = np.random.default_rng(seed)
    exceed = 0
    for start in range(0, draws, _CHUNK):
        e = np.exp(2j * np.pi * rng.uniform(0.0, 1.0, (min(_CHUNK, draws - start), n_sat)))
        stat = np.einsum("da,da->d", e, np.conj(e) @ zmat.T).real / n_sd
        exceed += int(np.sum(stat >= observed))
    direction = np.angle(total) / (2.0 * np.pi)
    return ClusteringTest(lane, n_sd, n_indep, float(observed), float(abs(total)),
                          float(direction - np.floor(direction + 0.5)),
                          float(observed / sigma0) if sigma0 > 0 else np.nan,
                          (1 + exceed) / (draws + 1), ps.fraction_cyc)


class ProductVerdict(NamedTuple):
    """Outcome of the product guard.

    Attributes
    ----------
    accepted : bool
        False: nothing may be fixed.
    reason : str
        Why the product is refused ("" if accepted).
    wl, nl : ClusteringTest or None
        The tests (``nl`` None when the WL test failed or nothing was tested).
    """

    accepted: bool
    reason: str
    wl: ClusteringTest | None
    nl: ClusteringTest | None

    def attrs(self, alpha: float, min_pairs: int) -> dict:
        """netCDF attributes of the verdict (``product_guard*``, ``wl_guard_*``, ``nl_guard_*``)."""
        out = {"product_guard": "accepted" if self.accepted else "refused",
               "product_guard_reason": self.reason,
               "product_guard_test": "mean cosine of the SD fractional parts, randomization "
                                     "test under satellite rotations (leopod.ambiguity."
                                     "consistency)",
               "product_guard_alpha": float(alpha),
               "product_guard_min_pairs": int(min_pairs)}
        for test, lane in ((self.wl, "wl"), (self.nl, "nl")):
            if test is None:
                out[f"{lane}_guard_n"] = 0
                continue
            out.update({f"{lane}_guard_n": int(test.n),
                        f"{lane}_guard_n_sd": int(test.n_sd),
                        f"{lane}_guard_statistic": test.statistic,
                        f"{lane}_guard_p_value": test.p_value,
                        f"{lane}_guard_mean_cos": test.mean_cos,
                        f"{lane}_guard_mean_resultant_length": test.mean_resultant_length,
                        f"{lane}_guard_mean_direction_cyc": test.mean_direction_cyc})
        return out


def _refusal(test: ClusteringTest, alpha: float, min_pairs: int) -> str:
    if test.n < min_pairs:
        return (f"product refused: only {test.n} satellite pairs to test the {test.lane} "
                f"fractional parts (< {min_pairs})")
    return (f"product refused: {test.lane} fractional parts do not cluster at 0 (p = "
            f"{test.p_value:.2g} > alpha {alpha:.2g}, mean cos = {test.mean_cos:.3f}, u = "
            f"{test.statistic:.2f}, {test.n_sd} SDs, {test.n} satellite pairs)")


def product_verdict(sv_i, sv_j, wl_value_cyc, wl_usable, nl_value_cyc, nl_usable, *,
                    alpha: float, min_pairs: int, draws: int = GUARD_DRAWS) -> ProductVerdict:
    """Test the WL and then the NL fractional parts of an arc (module docstring).

    Parameters
    ----------
    sv_i, sv_j : array_like of str, shape (m,)
        Satellites of the passes of each SD.
    wl_value_cyc : array_like, shape (m,)
        SD WL float values corrected by the product's WL biases [WL cycles].
    wl_usable : array_like of bool, shape (m,)
        SDs that enter the WL test (e.g. WL sigma within its bound).
    nl_value_cyc : array_like, shape (m,)
        SD NL float values [NL cycles] (with the WL integers).
    nl_usable : array_like of bool, shape (m,)
        SDs that enter the NL test (WL fixed, NL sigma within its bound).
    alpha : float
        Significance in (0, 0.5): uniformity must be rejected at this level.
    min_pairs : int
        Fewest independent satellite pairs of a test (fewer: refused).
    draws : int
        Random rotations of each test.

    Returns
    -------
    ProductVerdict
    """
    _check_alpha(alpha)
    wl_v = np.where(np.asarray(wl_usable, bool), np.asarray(wl_value_cyc, float), np.nan)
    wl = rotation_test(sv_i, sv_j, wl_v, "WL", draws=draws)
    log.info("product guard %s", wl.describe())
    if not wl.passed(alpha, min_pairs):
        return ProductVerdict(False, _refusal(wl, alpha, min_pairs), wl, None)
    nl_v = np.where(np.asarray(nl_usable, bool), np.asarray(nl_value_cyc, float), np.nan)
    nl = rotation_test(sv_i, sv_j, nl_v, "NL", draws=draws)
    log.info("product guard %s", nl.describe())
    if not nl.passed(alpha, min_pairs):
        return ProductVerdict(False, _refusal(nl, alpha, min_pairs), wl, nl)
    return ProductVerdict(True, "", wl, nl)


def float_consistent(fraction_cyc, sigma_cyc, max_shift_sigma: float):
    """Fixes whose integer lies within ``max_shift_sigma`` formal sigmas of the float value.

    Parameters
    ----------
    fraction_cyc : array_like, shape (m,)
        Float minus nearest integer [cycles].
    sigma_cyc : array_like, shape (m,)
        Formal sigma of the float value [cycles].
    max_shift_sigma : float
        Largest ``|fraction| / sigma`` [1] (> 0; inf: no screen).

    Returns
    -------
    ok : ndarray of bool, shape (m,)
        False where the shift exceeds the bound (NaN inputs count as consistent: the
        decision rejects them already).
    reason : ndarray of str, shape (m,)
        ``"shift 5.3 sigma > 4"`` where not ok, "" elsewhere.
    """
    if not max_shift_sigma > 0:
        raise ValueError(f"max_shift_sigma must be > 0, got {max_shift_sigma}")
    frac = np.abs(np.asarray(fraction_cyc, dtype=float))
    sigma = np.asarray(sigma_cyc, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = frac / sigma
    bad = np.isfinite(frac) & (sigma >= 0) & (ratio > max_shift_sigma)
    reason = np.full(frac.shape, "", dtype=object)
    for k in np.flatnonzero(bad):
        reason[k] = (f"fixing moves the float value by {ratio[k]:.1f} sigma > "
                     f"{max_shift_sigma:g}")
    return ~bad, reason
