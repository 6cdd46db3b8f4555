"""False-fix rate of the WL decisions with the old and the new WL sigma (issue 19, part 5).

Simulates many arcs of single-difference HMW series (:mod:`leopod.simulate.hmw_noise`: white
plus first-order Gauss–Markov noise with known integers), runs them through
:func:`leopod.ambiguity.wide_lane.sd_wide_lane` with ``sigma_method="white"`` (STD/sqrt(n),
the old sigma) and ``"autocorrelation"`` (:mod:`leopod.ambiguity.correlation`), and counts
for each decision the share of tested single differences fixed to a wrong integer
("wrong/tested", which the Dong & Bock test bounds by α when its sigma is right: a wrong fix
needs ``|e|`` in one of the intervals ``(i − d*, i + d*)`` whose probability is ``1 − P0(d*)
= α`` at the acceptance bound ``d*``), and wrong/fixed.

Noise model (where the numbers come from):
- 30 s sampling: the default campaign (``simulate.interval_s``; HY-2B onboard data);
- common time 8–40 min (16–80 epochs): Peng et al. (2021) 8-min minimum; the default campaign's
  single differences have a median of 21 common epochs (results of a default run);
- per-epoch SD HMW STD 0.1–0.5 WL cycles: the default campaign's SD STD has a median of
  0.087 cycles; real GRACE-A 2007-080 HMW (BlackJack, P1/P2) has a median per-pass STD of
  0.16 cycles (0.23 for a single difference); the HY-2B P1 code errors of Peng et al. (2021)
  reach metres at low elevation (0.5 cycles is an SD with about 0.6 m of P1 error);
- a share 0.2–0.8 of the variance in a Gauss–Markov process with τ = 1, 2.5, 5 or 10 min (one
  per arc): "several minutes" of multipath correlation (issue 19); real GRACE-A HMW at 10 s
  has a lag-1 correlation of 0.74 and its slow part follows the elevation;
- biased arcs (``--biased SHARE``): that share of the single differences carries a constant
  error of ±(0.3–0.7) cycles or ±1 cycle (an unmodelled code bias, a wrong product): the
  model of the test no longer holds, the figures show how far each sigma limits the damage.

    .venv/bin/python benchmarks/wl_statistics.py [--arcs 40] [--per-arc 300] [--seed 1]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from leopod.ambiguity.correlation import student_t_factor
from leopod.ambiguity.decision import (
    DONG_BOCK_ALPHA,
    WL_MAX_DEV_CYC,
    dong_bock_decision,
    rounding_decision,
)
from leopod.ambiguity.wide_lane import sd_wide_lane
from leopod.simulate.hmw_noise import sd_arc

STEP_S = 30.0
TAUS_S = (60.0, 150.0, 300.0, 600.0)


def simulate_arc(rng, per_arc: int, biased: float):
    """One arc: lengths, levels, one τ; returns the SdArc and its τ [s]."""
    tau = float(rng.choice(TAUS_S))
    share = rng.uniform(0.2, 0.8)
    level = rng.uniform(0.1, 0.5, per_arc)
    lengths = rng.integers(16, 81, per_arc)
    offset = np.zeros(per_arc)
    bad = rng.random(per_arc) < biased
    half = rng.random(per_arc) < 0.5
    sign = rng.choice([-1.0, 1.0], per_arc)
    offset[bad] = sign[bad] * np.where(half[bad], rng.uniform(0.3, 0.7, per_arc)[bad], 1.0)
    arc = sd_arc(rng, lengths, level * np.sqrt(1 - share), level * np.sqrt(share), tau,
                 STEP_S, offset_cyc=offset)
    return arc, tau


def decisions(arc, alpha: float) -> dict:
    """Fix flags and integers of each decision variant for one arc."""
    old = sd_wide_lane(arc.hmw_cyc, arc.pass_id, arc.id_i, arc.id_j, sigma_method="white")
    new = sd_wide_lane(arc.hmw_cyc, arc.pass_id, arc.id_i, arc.id_j,
                       sigma_method="autocorrelation")
    widened = new.sigma_cyc * student_t_factor(new.dof, alpha)
    return {
        "rounding 0.24 (Peng 2021), old sigma <= 0.1": rounding_decision(
            old.value_cyc, old.sigma_cyc, max_dev_cyc=WL_MAX_DEV_CYC, max_sigma_cyc=0.1),
        "Dong-Bock, old sigma STD/sqrt(n)": dong_bock_decision(old.value_cyc, old.sigma_cyc,
                                                               alpha=alpha),
        "Dong-Bock, new sigma (n_eff)": dong_bock_decision(new.value_cyc, new.sigma_cyc,
                                                           alpha=alpha),
        "Dong-Bock, new sigma + Satterthwaite t": dong_bock_decision(new.value_cyc, widened,
                                                                     alpha=alpha),
    }


def measure(arcs: int, per_arc: int, seed: int, biased: float, alpha: float) -> dict:
    """Counts (tested, fixed, wrong) per decision over all arcs."""
    rng = np.random.default_rng(seed)
    counts: dict = {}
    for _ in range(arcs):
        arc, _tau = simulate_arc(rng, per_arc, biased)
        for name, dec in decisions(arc, alpha).items():
            c = counts.setdefault(name, np.zeros(3, dtype=np.int64))
            wrong = dec.fixed & (dec.integer != arc.true_cyc)
            c += [dec.fixed.size, dec.fixed.sum(), wrong.sum()]
    return counts


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--arcs", type=int, default=40)
    p.add_argument("--per-arc", type=int, default=300)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--alpha", type=float, default=DONG_BOCK_ALPHA)
    a = p.parse_args()
    for biased in (0.0, 0.1):
        t0 = time.perf_counter()
        counts = measure(a.arcs, a.per_arc, a.seed, biased, a.alpha)
        print(f"\n{a.arcs} arcs x {a.per_arc} SDs, seed {a.seed}, alpha {a.alpha:g}, "
              f"biased share {biased:.0%} ({time.perf_counter() - t0:.0f} s)")
        print(f"  {'decision':45s} {'fixed':>7s} {'wrong':>6s} {'wrong/tested':>13s} "
              f"{'wrong/fixed':>12s}")
        for name, (n, f, w) in counts.items():
            print(f"  {name:45s} {f / n:7.1%} {w:6d} {w / n:13.2e} {w / max(f, 1):12.2e}")


if __name__ == "__main__":
    main()
