"""Synthetic two-receiver (formation) scenario for the double-difference AR tests.

Generated from the stated model (docstrings of leopod.ambiguity.double_difference,
wide_lane and narrow_lane), nothing estimated:

- GNSS visibility common to the two LEOs (a formation a few km apart): passes of GPS
  satellites on a 10 s grid (the generator of _ambiguity_scenario), each receiver's pass
  starting and ending a few epochs apart from the other's;
- independent slips: each receiver splits its own passes at random epochs (a new pass id,
  new integers), so one pass of A can pair with several passes of B;
- HMW/λ_WL = N_WL + w_r + w^s + white noise, with a receiver-specific WL bias w_r and the
  satellite biases w^s of leopod.simulate.biases (the same for both receivers);
- float IF ambiguity B = λ_NL N1 + λ_NL f2/(f1 − f2) N_WL + b_r,IF + b^s_IF + e per receiver,
  e from a known covariance (common mode, weak factors, independent part), the receivers'
  errors independent of each other.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr
from _ambiguity_scenario import BIASES, EPOCH, GPS, _passes

from leopod.ambiguity.double_difference import ReceiverArc
from leopod.constants import C_LIGHT_M_S
from leopod.signals import frequency_hz
from leopod.simulate.biases import simulate_biases, truth_dataset

#: Phase and code pairs of the systems of the scenario.
SIGNALS = {"G": (("L1C", "L2W"), ("C1W", "C2W")), "E": (("L1C", "L5Q"), ("C1C", "C5Q"))}

#: Receiver WL biases [cycles] and IF phase biases [m] of A and B.
W_RX_CYC = (0.37, -0.21)
B_RX_IF_M = (0.123, -0.071)


def _receiver(rng, visibility, n_epochs, n_sv, slip_prob, shift_epochs):
    """Pass ids (time, sv) of one receiver: the common visibility with its own ends and slips."""
    pass_id = np.full((n_epochs, n_sv), -1, dtype=np.int64)
    n = 0
    for col, passes in enumerate(visibility):
        for first, last in passes:
            first = min(max(first + int(rng.integers(-shift_epochs, shift_epochs + 1)), 0),
                        n_epochs - 1)
            last = min(max(last + int(rng.integers(-shift_epochs, shift_epochs + 1)), first),
                       n_epochs - 1)
            cuts = [first]
            if rng.uniform() < slip_prob and last - first > 20:
                cuts.append(int(rng.integers(first + 10, last - 10)))
            for a, b in zip(cuts, [*cuts[1:], last + 1], strict=True):
                pass_id[a:b, col] = n
                n += 1
    return pass_id


def _floats(rng, n, b_true, sigma_if_m, common_if_m, factor_if_m, scale):
    mix = rng.normal(0.0, factor_if_m, (n, 3))
    cov = (common_if_m**2 + mix @ mix.T + np.diag(rng.uniform(0.5, 1.5, n) * sigma_if_m**2))
    value = b_true + np.linalg.cholesky(cov) @ rng.normal(size=n) * scale
    return value, cov


def dd_scenario(seed: int = 5, hours: float = 8.0, step_s: float = 10.0, n_sv: int = 10,
                sigma_hmw_cyc: float = 0.25, sigma_if_m: float = 0.003,
                common_if_m: float = 0.05, factor_if_m: float = 0.001, slip_prob: float = 0.3,
                shift_epochs: int = 6, noise: bool = True, system: str = "G") -> SimpleNamespace:
    """Two receivers, their truth and their arcs (``arcs``: ReceiverArc of A and B).

    ``noise=False`` gives noise-free HMW and float IF ambiguities (biases kept); ``system``
    "G" (GPS L1/L2) or "E" (the same satellites relabelled, Galileo E1/E5a frequencies)."""
    rng = np.random.default_rng(seed)
    (p1, p2), (c1, c2) = SIGNALS[system]
    f1, f2 = frequency_hz(system, p1), frequency_hz(system, p2)
    lam_nl, wl_factor = C_LIGHT_M_S / (f1 + f2), f2 / (f1 - f2)
    biases = simulate_biases(GPS, None, np.random.default_rng(seed + 100), epoch=EPOCH,
                             settings=BIASES)
    truth = truth_dataset(biases)
    n_epochs = int(hours * 3600 / step_s)
    times = EPOCH + np.arange(n_epochs) * np.timedelta64(int(step_s), "s")
    svs = sorted(rng.choice(GPS, n_sv, replace=False).tolist())
    visibility = [_passes(rng, n_epochs, step_s) for _ in svs]
    scale = 1.0 if noise else 0.0
    receivers = []
    for r in range(2):
        pass_id = _receiver(rng, visibility, n_epochs, n_sv, slip_prob, shift_epochs)
        n = int(pass_id.max()) + 1
        col = np.array([int(np.nonzero((pass_id == p).any(axis=0))[0][0]) for p in range(n)])
        amb_sv = np.array(svs)[col]
        n1 = rng.integers(-10**5, 10**5, n)
        n_wl = rng.integers(-30, 30, n)
        w_sat = truth["wl_bias_sat_cyc"].sel(sv=svs).values      # GPS biases, any system
        b_sat = truth["if_phase_bias_sat_m"].sel(sv=amb_sv).values
        amb_sv = np.array([system + v[1:] for v in amb_sv])
        tracked = pass_id >= 0
        hmw = np.full(pass_id.shape, np.nan)
        n_wl_map = n_wl[np.where(tracked, pass_id, 0)]
        hmw[tracked] = (n_wl_map + W_RX_CYC[r] + w_sat[None, :]
                        + scale * rng.normal(0.0, sigma_hmw_cyc, hmw.shape))[tracked]
        holes = tracked & (rng.uniform(size=hmw.shape) < 0.01)
        pass_id[holes] = -1
        hmw[holes] = np.nan
        b_true = lam_nl * n1 + lam_nl * wl_factor * n_wl + B_RX_IF_M[r] + b_sat
        value, cov = _floats(rng, n, b_true, sigma_if_m, common_if_m, factor_if_m, scale)
        first = np.array([np.nonzero((pass_id == p).any(axis=1))[0][0] for p in range(n)])
        last = np.array([np.nonzero((pass_id == p).any(axis=1))[0][-1] for p in range(n)])
        amb = xr.Dataset({
            "sv": ("ambiguity", amb_sv), "pass_index": ("ambiguity", np.arange(n)),
            "start": ("ambiguity", times[first]), "end": ("ambiguity", times[last]),
            "value_m": ("ambiguity", value), "sigma_m": ("ambiguity", np.sqrt(np.diag(cov))),
            "covariance_m2": (("ambiguity", "ambiguity_b"), cov)})
        coords = {"time": times, "sv": [system + v[1:] for v in svs]}
        # observations whose HMW/λ_WL is the scenario's: L1 = c/f1 · HMW/λ_WL, the rest 0
        l1 = xr.DataArray(hmw * C_LIGHT_M_S / f1, dims=("time", "sv"), coords=coords)
        zero = xr.zeros_like(l1).where(np.isfinite(l1))
        obs = xr.Dataset({p1: l1, p2: zero, c1: zero, c2: zero})
        residuals = xr.Dataset({"pass_index": xr.DataArray(pass_id, dims=("time", "sv"),
                                                           coords=coords)})
        receivers.append(SimpleNamespace(amb=amb, n1=n1, n_wl=n_wl, b_true=b_true,
                                         arc=ReceiverArc(amb, residuals, obs)))
    return SimpleNamespace(times=times, svs=svs, a=receivers[0], b=receivers[1], system=system,
                           arcs=(receivers[0].arc, receivers[1].arc))


def true_dd(s: SimpleNamespace, table: xr.Dataset, key: str) -> np.ndarray:
    """True DD integers (``key`` "n_wl" or "n1") of the rows of a resolve_dd table."""
    a, b = getattr(s.a, key), getattr(s.b, key)
    return ((b[table.amb_b_i.values] - a[table.amb_a_i.values])
            - (b[table.amb_b_j.values] - a[table.amb_a_j.values]))


def combined(g: SimpleNamespace, e: SimpleNamespace) -> SimpleNamespace:
    """Two single-system scenarios as one combined arc per receiver (block-diagonal float
    covariance, pass ids of the second system after those of the first)."""
    out = []
    for rx in ("a", "b"):
        x, y = getattr(g, rx), getattr(e, rx)
        n_x = x.amb.sizes["ambiguity"]
        amb_y = y.amb.assign(pass_index=y.amb.pass_index + n_x)
        cov = np.zeros((n_x + amb_y.sizes["ambiguity"],) * 2)
        cov[:n_x, :n_x] = x.amb.covariance_m2.values
        cov[n_x:, n_x:] = y.amb.covariance_m2.values
        amb = xr.concat([x.amb.drop_vars("covariance_m2"), amb_y.drop_vars("covariance_m2")],
                        dim="ambiguity")
        amb["covariance_m2"] = (("ambiguity", "ambiguity_b"), cov)
        pid_y = y.arc.residuals.pass_index
        pid = xr.concat([x.arc.residuals.pass_index, pid_y.where(pid_y < 0, pid_y + n_x)],
                        dim="sv").astype(np.int64)
        obs = xr.merge([x.arc.obs, y.arc.obs], join="outer", compat="no_conflicts")
        out.append(SimpleNamespace(
            amb=amb, n1=np.concatenate([x.n1, y.n1]), n_wl=np.concatenate([x.n_wl, y.n_wl]),
            b_true=np.concatenate([x.b_true, y.b_true]),
            arc=ReceiverArc(amb, xr.Dataset({"pass_index": pid}), obs)))
    return SimpleNamespace(a=out[0], b=out[1], arcs=(out[0].arc, out[1].arc))
