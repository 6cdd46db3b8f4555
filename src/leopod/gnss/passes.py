"""Cycle-slip detection and the splitting of tracking into continuous passes.

A *pass* is a stretch of dual-frequency phase tracking of one GNSS satellite without a gap
longer than ``max_gap_s`` and without a cycle slip; every pass gets its own float ambiguity
in the POD. Slips are detected with three independent tests (Wang et al. 2024, sec. 3.1.3 and the
TurboEdit idea of Blewitt 1990, GRL 17:3):

* the receiver's loss-of-lock indicator (LLI bit 0) on either phase;
* the Melbourne–Wübbena (HMW) combination, in wide-lane cycles, jumping away from the running
  mean of the pass by more than ``mw_k`` running standard deviations (and at least 0.6 cycle,
  so that noise-free stretches do not flag sub-cycle wiggles while a one-cycle slip of
  precise P-code tracking is still seen),
  confirmed by the next epoch (a single deviating epoch is an outlier, not a slip);
* the geometry-free phase ``Φ1 − Φ2`` deviating from a linear prediction from the two previous
  epochs by more than ``gf_threshold_m`` (sensitive to the small slips MW misses, e.g. equal
  slips on both frequencies), again confirmed by the next epoch: a step is a slip, a spike
  that returns to the prediction is an outlier (on GRACE-A 2007-080 most single-epoch GF
  deviations of low-elevation L2 were such spikes).

The flags are bit masks so that the quality report can say why a pass ended.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from leopod.gnss.combinations import melbourne_wuebbena, wide_lane_wavelength_m

__all__ = ["PassResult", "detect_passes", "FLAG_NEW", "FLAG_GAP", "FLAG_LLI", "FLAG_MW",
           "FLAG_GF", "FLAG_OUTLIER"]

FLAG_NEW = 1       #: first epoch of tracking of the satellite in the file
FLAG_GAP = 2       #: first epoch after a gap longer than max_gap_s
FLAG_LLI = 4       #: loss-of-lock indicator set by the receiver
FLAG_MW = 8        #: Melbourne–Wübbena jump
FLAG_GF = 16       #: geometry-free phase jump
FLAG_OUTLIER = 32  #: single-epoch outlier in MW or GF (epoch excluded, pass continues)

_SLIP_FLAGS = FLAG_LLI | FLAG_MW | FLAG_GF
_MW_SIGMA0_CYC = 0.5    # a-priori MW standard deviation until a pass has 10 epochs [cycles]
_MW_MIN_EPOCHS = 10
_MW_MIN_LIMIT_CYC = 0.6  # smallest MW jump that counts as a slip [cycles]


@dataclass
class PassResult:
    """Passes and slip flags of a (time, sv) block of observations.

    Attributes
    ----------
    pass_id : ndarray of int32, shape (n, s)
        Pass number (unique over the block, counting from 0), -1 where the epoch has no
        usable dual-frequency phase and code or is an outlier.
    flags : ndarray of int8, shape (n, s)
        Bit mask of FLAG_* at the first epoch of each pass (and FLAG_OUTLIER at outliers).
    mw_cyc : ndarray, shape (n, s)
        Melbourne–Wübbena combination [wide-lane cycles].
    """

    pass_id: np.ndarray
    flags: np.ndarray
    mw_cyc: np.ndarray

    @property
    def n_passes(self) -> int:
        """Number of passes."""
        return int(self.pass_id.max()) + 1 if (self.pass_id >= 0).any() else 0

    @property
    def n_slips(self) -> int:
        """Number of pass breaks caused by slips (LLI, MW or GF) inside continuous tracking."""
        brk = (self.flags & _SLIP_FLAGS) != 0
        brk &= (self.flags & (FLAG_NEW | FLAG_GAP)) == 0
        return int(brk.sum())


def detect_passes(t_s, phase_1_m, phase_2_m, code_1_m, code_2_m, lli_1, lli_2, f1_hz, f2_hz,
                  *, max_gap_s=60.0, mw_k=4.0, gf_threshold_m=0.05) -> PassResult:
    """Split dual-frequency tracking into passes at gaps and cycle slips.

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Epochs [s], increasing.
    phase_1_m, phase_2_m : ndarray, shape (n, s)
        Carrier phases on frequency 1 and 2 [m] (NaN where absent).
    code_1_m, code_2_m : ndarray, shape (n, s)
        Codes on frequency 1 and 2 [m] used in the MW combination.
    lli_1, lli_2 : ndarray of int, shape (n, s)
        RINEX loss-of-lock indicators of the phases (bit 0 = slip possible).
    f1_hz, f2_hz : float
        Frequencies [Hz].
    max_gap_s : float
        A gap longer than this starts a new pass [s].
    mw_k : float
        MW threshold in running standard deviations (minimum 0.6 wide-lane cycle).
    gf_threshold_m : float
        Threshold of the geometry-free prediction error [m].

    Returns
    -------
    PassResult
    """
    t_s = np.asarray(t_s, dtype=float)
    mw = melbourne_wuebbena(phase_1_m, phase_2_m, code_1_m, code_2_m, f1_hz, f2_hz)
    mw = mw / wide_lane_wavelength_m(f1_hz, f2_hz)
    gf = np.asarray(phase_1_m) - np.asarray(phase_2_m)
    valid = np.isfinite(mw) & np.isfinite(gf)
    lli = ((np.nan_to_num(lli_1, nan=0).astype(int) | np.nan_to_num(lli_2, nan=0).astype(int))
           & 1) != 0
    n, s = mw.shape
    pass_id = np.full((n, s), -1, dtype=np.int32)
    flags = np.zeros((n, s), dtype=np.int8)
    next_id = 0
    for j in range(s):
        rows = np.nonzero(valid[:, j])[0]
        if rows.size == 0:
            continue
        next_id = _passes_of_column(rows, t_s, mw[:, j], gf[:, j], lli[:, j], pass_id[:, j],
                                    flags[:, j], next_id, max_gap_s, mw_k, gf_threshold_m)
    return PassResult(pass_id=pass_id, flags=flags, mw_cyc=mw)


_SLIP, _OUTLIER = 1, 2


def _jump(value, value_next, pred, pred_next, limit) -> int:
    """Classify a deviation from a prediction: 0 none, _SLIP (a step), _OUTLIER (a spike).

    A deviation larger than ``limit`` is a slip when the next epoch also deviates from its
    prediction by more than ``limit`` and stays within ``limit`` of the new level (or when
    there is no next epoch); otherwise the epoch is a single outlier.
    """
    if abs(value - pred) <= limit:
        return 0
    if value_next is None:
        return _SLIP
    if abs(value_next - pred_next) > limit and abs((value_next - pred_next) - (value - pred)) <= limit:
        return _SLIP
    return _OUTLIER


def _passes_of_column(rows, t_s, mw, gf, lli, pass_col, flag_col, next_id, max_gap_s, mw_k,
                      gf_thr):
    """Walk the valid epochs of one satellite, writing pass ids and flags in place."""
    current = -1
    mean = var = 0.0
    count = 0
    gf_hist: list[tuple[float, float]] = []   # (t, gf) of the last two epochs of the pass
    prev_t = -np.inf
    for pos, r in enumerate(rows):
        flag = 0
        if current < 0:
            flag |= FLAG_NEW
        elif t_s[r] - prev_t > max_gap_s:
            flag |= FLAG_GAP
        if lli[r] and current >= 0:
            flag |= FLAG_LLI
        if not flag and count > 0:
            nxt = rows[pos + 1] if pos + 1 < rows.size else None
            sigma = np.sqrt(var / count) if count >= _MW_MIN_EPOCHS else _MW_SIGMA0_CYC
            limit = max(mw_k * sigma, _MW_MIN_LIMIT_CYC)
            verdict = _jump(mw[r], None if nxt is None else mw[nxt], mean, mean, limit)
            if len(gf_hist) == 2:
                (t0, g0), (t1, g1) = gf_hist
                slope = (g1 - g0) / (t1 - t0)
                pred_next = None if nxt is None else g1 + slope * (t_s[nxt] - t1)
                gf_verdict = _jump(gf[r], None if nxt is None else gf[nxt],
                                   g1 + slope * (t_s[r] - t1), pred_next, gf_thr)
            else:
                gf_verdict = 0
            if verdict == _SLIP:
                flag |= FLAG_MW
            if gf_verdict == _SLIP:
                flag |= FLAG_GF
            if not flag and _OUTLIER in (verdict, gf_verdict):
                flag_col[r] = FLAG_OUTLIER
                continue
        if flag:
            current = next_id
            next_id += 1
            mean = var = 0.0
            count = 0
            gf_hist = []
            flag_col[r] = flag
        # running mean and sum of squared deviations (Welford)
        count += 1
        delta = mw[r] - mean
        mean += delta / count
        var += delta * (mw[r] - mean)
        gf_hist = (gf_hist + [(t_s[r], gf[r])])[-2:]
        pass_col[r] = current
        prev_t = t_s[r]
    return next_id
