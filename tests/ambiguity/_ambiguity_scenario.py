"""Synthetic single-receiver scenario for the ambiguity-resolution tests.

Generated from the stated model (docstrings of leopod.ambiguity.wide_lane/narrow_lane and
leopod.simulate.biases), nothing estimated:

- passes of GPS satellites on a 10 s grid, each with integers N1, N2 (N_WL = N1 − N2), a few
  single-epoch holes (pass_id −1, HMW NaN) inside passes;
- HMW/λ_WL = N_WL + w_r + w^s + white noise (sigma_hmw_cyc per epoch);
- float IF ambiguity B = λ_NL N1 + λ_NL f2/(f1 − f2) N_WL + b_r,IF + b^s_IF + e, with e drawn
  from a known correlated covariance: a common mode (cancels in single differences, like
  the receiver-clock-like correlation of real float ambiguities), a weak 3-factor part and an
  independent part;
- satellite biases from leopod.simulate.biases (truth and the OSB / CNES WL products), the
  products optionally with a fault of leopod.simulate.product_faults;
- ``clocks="ordinary"``: the float IF ambiguities carry the true ``b^s_IF`` (clocks to be used
  with the OSBs); ``clocks="integer"``: they carry ``b^s_IF`` minus the ``b^s_IF`` held by the
  product's integer-recovery clocks (zero for a consistent product).

:func:`arc_inputs` turns a scenario into the inputs of leopod.ambiguity.resolve.resolve_arc
(observations whose HMW combination is the scenario's HMW).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.signals import frequency_hz
from leopod.simulate.biases import BiasSettings, simulate_biases, truth_dataset
from leopod.simulate.product_faults import faulty_products
from leopod.workflow.config import section_defaults

EPOCH = np.datetime64("2020-06-01T00:00", "ns")
#: Bias magnitudes of the simulator (the schema's defaults).
BIASES = BiasSettings.from_config(section_defaults("simulate_biases"))
GPS = [f"G{i:02d}" for i in range(1, 33)]
F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")
LAMBDA_NL_M = C_LIGHT_M_S / (F1 + F2)
WL_FACTOR = F2 / (F1 - F2)
W_RX_CYC = 0.37        # receiver WL bias [cycles]
B_RX_IF_M = 0.123      # receiver IF phase bias [m]


def _passes(rng, n_epochs: int, step_s: float):
    """List of (first, last) epoch indices of consecutive passes of one satellite."""
    out = []
    k = int(rng.integers(0, 200))
    while True:
        length = int(rng.uniform(15, 50) * 60 / step_s)
        last = min(k + length, n_epochs - 1)
        if last - k >= 30:
            out.append((k, last))
        k = last + 1 + int(rng.uniform(2, 40) * 60 / step_s)
        if k >= n_epochs - 30:
            return out


def scenario(seed: int = 3, hours: float = 6.0, step_s: float = 10.0, n_sv: int = 10,
             sigma_hmw_cyc: float = 0.3, sigma_if_m: float = 0.003,
             common_if_m: float = 0.05, factor_if_m: float = 0.001, fault: str = "none",
             clocks: str = "ordinary") -> SimpleNamespace:
    if clocks not in ("ordinary", "integer"):
        raise ValueError(f"clocks must be 'ordinary' or 'integer', got {clocks!r}")
    rng = np.random.default_rng(seed)
    biases = simulate_biases(GPS, None, np.random.default_rng(seed + 100), epoch=EPOCH,
                             settings=BIASES)
    faulty = faulty_products(biases, fault, np.random.default_rng(seed + 200))
    products = faulty.products
    truth = products.truth
    n_epochs = int(hours * 3600 / step_s)
    times = EPOCH + np.arange(n_epochs) * np.timedelta64(int(step_s), "s")
    svs = sorted(rng.choice(GPS, n_sv, replace=False).tolist())
    pass_id = np.full((n_epochs, n_sv), -1, dtype=np.int64)
    amb_sv, amb_first, amb_last = [], [], []
    for col, sv in enumerate(svs):
        for first, last in _passes(rng, n_epochs, step_s):
            pass_id[first:last + 1, col] = len(amb_sv)
            amb_sv.append(sv)
            amb_first.append(first)
            amb_last.append(last)
    n = len(amb_sv)
    amb_sv = np.array(amb_sv)
    n1 = rng.integers(-10**5, 10**5, n)
    n_wl = rng.integers(-30, 30, n)
    w_sat = truth["wl_bias_sat_cyc"].sel(sv=svs).values
    b_sat = truth["if_phase_bias_sat_m"].sel(sv=amb_sv).values
    if clocks == "integer":
        held = truth_dataset(faulty.clock_biases)["if_phase_bias_sat_m"]
        b_sat = b_sat - held.sel(sv=amb_sv).values
    # HMW per epoch, with single-epoch holes inside the passes
    col_of = {sv: k for k, sv in enumerate(svs)}
    hmw = np.full((n_epochs, n_sv), np.nan)
    tracked = pass_id >= 0
    n_wl_map = np.where(tracked, n_wl[np.where(tracked, pass_id, 0)], 0)
    hmw[tracked] = ((n_wl_map + W_RX_CYC + w_sat[None, :]
                     + rng.normal(0.0, sigma_hmw_cyc, hmw.shape))[tracked])
    holes = tracked & (rng.uniform(size=hmw.shape) < 0.01)
    pass_id[holes] = -1
    hmw[holes] = np.nan
    # float IF ambiguities with a correlated covariance
    mix = rng.normal(0.0, factor_if_m, (n, 3))
    cov = (common_if_m**2 + mix @ mix.T
           + np.diag(rng.uniform(0.5, 1.5, n) * sigma_if_m**2))
    b_true = (LAMBDA_NL_M * n1 + LAMBDA_NL_M * WL_FACTOR * n_wl + B_RX_IF_M + b_sat)
    value = b_true + np.linalg.cholesky(cov) @ rng.normal(size=n)
    amb = xr.Dataset({
        "sv": ("ambiguity", amb_sv),
        "pass_index": ("ambiguity", np.arange(n)),
        "start": ("ambiguity", times[amb_first]),
        "end": ("ambiguity", times[amb_last]),
        "value_m": ("ambiguity", value),
        "sigma_m": ("ambiguity", np.sqrt(np.diag(cov))),
        "covariance_m2": (("ambiguity", "ambiguity_b"), cov),
    }, attrs={"nl_wavelength_m": LAMBDA_NL_M})
    coords = {"time": times, "sv": svs}
    return SimpleNamespace(
        times=times, svs=svs, col_of=col_of, amb=amb, n1=n1, n_wl=n_wl, b_true=b_true,
        hmw=xr.DataArray(hmw, dims=("time", "sv"), coords=coords),
        pass_id=xr.DataArray(pass_id, dims=("time", "sv"), coords=coords),
        biases=biases, products=products, truth=truth, sigma_hmw_cyc=sigma_hmw_cyc,
        clocks=clocks)


def arc_inputs(s: SimpleNamespace) -> tuple[xr.Dataset, xr.Dataset]:
    """``(residuals, obs)`` for resolve_arc: ``pass_index`` (time, sv), and L1C/L2W/C1W/C2W
    [m] with codes and L2W zero and ``L1C = (f1 − f2)/f1 · λ_WL · HMW``, so that the HMW
    combination ``f1 L1/(f1 − f2)`` [m] divided by ``λ_WL`` is the scenario's HMW."""
    lam_wl = C_LIGHT_M_S / (F1 - F2)
    l1 = s.hmw * lam_wl * (F1 - F2) / F1
    zero = xr.zeros_like(l1).where(np.isfinite(l1))
    obs = xr.Dataset({"L1C": l1, "L2W": zero, "C1W": zero, "C2W": zero})
    return xr.Dataset({"pass_index": s.pass_id}), obs
