"""Onboard GNSS observations of a simulated LEO, with their truth.

For every receiver epoch the generator solves the light time in the inertial frame, selects
the satellites above the antenna horizon (at most ``channels``, highest first), and forms
code and phase on two frequencies:

``P_f = ρ_f + c (dt_rx − dt_sv) + I_f + b_f + ε_P``
``Φ_f = ρ_f + c (dt_rx − dt_sv) − I_f + λ_f N_f + ε_Φ``

with ``ρ_f`` the geometric range from the transmitter to the frequency's receiver phase
centre (body-frame offset rotated by the nominal attitude), ``dt_sv`` the true satellite clock
(product clock plus the periodic relativistic term −2 r·v/c², IS-GPS-200 20.3.3.3.3.1),
``I_f = 40.3 STEC / f²`` from a thin-shell TEC model above the LEO, ``b_f`` satellite code
biases of the C/A code relative to P1 (P1−C1 DCB), integer ambiguities that change at every
acquisition and cycle slip, and white noise whose standard deviation grows at low elevation.

Not yet simulated (they come with the full simulator): phase wind-up, GNSS antenna offsets,
fractional phase biases, antenna-frame code-bias maps, model mismatch of the orbit.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S, R_EARTH_EQUATOR_M
from leopod.gnss import signals
from leopod.simulate.world import CircularOrbit, RandomWalkClock

__all__ = ["ObservationModel", "simulate_observations"]

_TEC_TO_M_HZ2 = 40.3e16  # ionospheric delay factor: I = 40.3 STEC[TECU] 1e16 / f² [m Hz²]


@dataclass(frozen=True)
class ObservationModel:
    """Settings of the simulated receiver and signals.

    Attributes
    ----------
    noise_m : dict
        Typical white-noise STD per RINEX 2 observation name [m], reached at 30° elevation
        (where the bulk of the observations lie). The default code values are the typical
        2-min STDs of epoch-differenced code minus carrier of seed 000 (C1 0.46, P1 0.09,
        P2 0.02 m) divided by √2, so the quality step should find those numbers again.
    low_elevation_factor : float
        Noise scales as ``(1 + factor · exp(−el / 10°)) / (1 + factor · exp(−3))``.
    channels : int
        Tracking channels (HY-2B: 12).
    elevation_mask_deg : float
        Antenna-frame elevation below which nothing is tracked.
    vtec_tecu : tuple of float
        Night and day vertical TEC above the LEO [TECU].
    slip_rate_per_h : float
        Expected cycle slips per hour of tracking of one satellite.
    lli_detected : float
        Probability that the receiver flags a slip with the LLI.
    gap_rate_per_h : float
        Expected short tracking gaps (1–5 epochs) per hour and satellite.
    pco_body_m : dict
        Antenna phase-centre offsets per band name in the body frame [m].
    """

    noise_m: dict = field(default_factory=lambda: {
        "C1": 0.46 / np.sqrt(2), "P1": 0.09 / np.sqrt(2), "P2": 0.02 / np.sqrt(2),
        "L1": 0.0015, "L2": 0.0015})
    low_elevation_factor: float = 3.0
    channels: int = 12
    elevation_mask_deg: float = 0.0
    vtec_tecu: tuple = (2.0, 8.0)
    slip_rate_per_h: float = 0.05
    lli_detected: float = 0.8
    gap_rate_per_h: float = 0.05
    pco_body_m: dict = field(default_factory=lambda: {"L1": [0.0, 0.0, -0.35],
                                                      "L2": [0.0, 0.0, -0.37]})


def _nominal_axes_inertial(pos: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """Rows X, Y, Z of the nominal body frame in inertial coordinates, shape (n, 3, 3)."""
    z = -pos / np.linalg.norm(pos, axis=-1, keepdims=True)
    y = np.cross(z, vel)
    y /= np.linalg.norm(y, axis=-1, keepdims=True)
    x = np.cross(y, z)
    return np.stack([x, y, z], axis=-2)


def simulate_observations(t_read_s: np.ndarray, leo: CircularOrbit, gnss: dict[str, CircularOrbit],
                          gnss_clocks: dict[str, RandomWalkClock], rx_clock: RandomWalkClock,
                          dcb_p1c1_s: dict[str, float], model: ObservationModel, seed: int,
                          sun_dir_in: np.ndarray = np.array([1.0, 0.0, 0.0])) -> xr.Dataset:
    """Simulate RINEX-2-like GPS observations (C1 P1 P2 L1 L2) of a LEO.

    Parameters
    ----------
    t_read_s : ndarray, shape (n,)
        Receiver epochs (clock readings) [s since the world's epoch].
    leo : CircularOrbit
    gnss : dict of CircularOrbit
        Transmitters by id (``"G01"``).
    gnss_clocks : dict of RandomWalkClock
        Product (broadcast-free) clocks of the transmitters [s].
    rx_clock : RandomWalkClock
        Receiver clock [s].
    dcb_p1c1_s : dict
        P1 − C1 satellite code bias [s]: ``C1 = P1 − c·DCB`` at the satellite.
    model : ObservationModel
    seed : int
        Seed of the random noise, ambiguities, slips and gaps.
    sun_dir_in : ndarray, shape (3,)
        Inertial direction of the Sun for the day/night TEC model.

    Returns
    -------
    xarray.Dataset
        Schema of :func:`leopod.io.rinex_obs.read_rinex_obs` for RINEX 2 (codes in m, phases
        in cycles, ``L1_lli``/``L2_lli``) plus truth variables ``true_range_if_m``,
        ``amb_L1_cyc``, ``amb_L2_cyc`` and ``pass_true`` (time, sv) and ``el_deg`` (time, sv).
    """
    rng = np.random.default_rng(seed)
    ids = sorted(gnss)
    n, s = len(t_read_s), len(ids)
    f = {"1": signals.frequency_hz("G", "1"), "2": signals.frequency_hz("G", "2")}
    lam = {k: C_LIGHT_M_S / v for k, v in f.items()}
    dt_rx = rx_clock(t_read_s)
    t_true = t_read_s - dt_rx
    r_rx, v_rx = leo.inertial(t_true)                                    # (n, 3)
    axes = _nominal_axes_inertial(r_rx, v_rx)                            # (n, 3, 3)
    pco_in = {b: np.einsum("nji,j->ni", axes, np.asarray(model.pco_body_m[f"L{b}"]))
              for b in ("1", "2")}
    # light time per satellite (iterate in the inertial frame)
    tau = np.full((n, s), 0.07)
    for _ in range(4):
        r_tx = np.stack([gnss[k].inertial(t_true - tau[:, j])[0] for j, k in enumerate(ids)], axis=1)
        tau = np.linalg.norm(r_tx - r_rx[:, None, :], axis=2) / C_LIGHT_M_S
    r_tx = np.empty((n, s, 3))
    v_tx = np.empty((n, s, 3))
    for j, k in enumerate(ids):
        r_tx[:, j], v_tx[:, j] = gnss[k].inertial(t_true - tau[:, j])
    los = r_tx - r_rx[:, None, :]
    unit = los / np.linalg.norm(los, axis=2, keepdims=True)
    body = np.einsum("nij,nsj->nsi", axes, unit)
    el = np.degrees(np.arcsin(np.clip(-body[..., 2], -1, 1)))
    # tracking: above the mask, at most `channels` satellites, highest first
    visible = el > model.elevation_mask_deg
    order = np.argsort(-np.where(visible, el, -1e9), axis=1)
    rank = np.empty_like(order)
    np.put_along_axis(rank, order, np.arange(s)[None, :].repeat(n, 0), axis=1)
    tracked = visible & (rank < model.channels)
    dt = float(np.median(np.diff(t_read_s))) if n > 1 else 30.0
    # short random gaps
    p_gap = model.gap_rate_per_h * dt / 3600.0
    gap_start = tracked & (rng.random((n, s)) < p_gap)
    for i, j in zip(*np.nonzero(gap_start)):
        tracked[i:i + rng.integers(1, 6), j] = False
    # passes: a new one at each acquisition; slips inside with random integer jumps
    starts = tracked & ~np.vstack([np.zeros((1, s), bool), tracked[:-1]])
    slips = tracked & ~starts & (rng.random((n, s)) < model.slip_rate_per_h * dt / 3600.0)
    new_pass = starts | slips
    pass_true = np.cumsum(new_pass.ravel(order="F")).reshape((n, s), order="F") - 1
    pass_true = np.where(tracked, pass_true, -1)
    n_pass = int(new_pass.sum())
    amb1_pass = rng.integers(-500, 500, n_pass).astype(float)
    amb2_pass = rng.integers(-500, 500, n_pass).astype(float)
    amb1 = np.where(tracked, amb1_pass[np.clip(pass_true, 0, None)], np.nan)
    amb2 = np.where(tracked, amb2_pass[np.clip(pass_true, 0, None)], np.nan)
    # clocks and relativity
    dt_sv = np.stack([gnss_clocks[k](t_true - tau[:, j]) for j, k in enumerate(ids)], axis=1)
    rel = -2.0 * np.einsum("nsc,nsc->ns", r_tx, v_tx) / C_LIGHT_M_S**2
    clock_m = C_LIGHT_M_S * (dt_rx[:, None] - (dt_sv + rel))
    # ionosphere: thin shell 400 km above the LEO, day/night VTEC by the Sun angle
    h_leo = np.linalg.norm(r_rx, axis=1) - R_EARTH_EQUATOR_M
    r_shell = R_EARTH_EQUATOR_M + h_leo + 400e3
    cos_zen_shell = np.sqrt(1 - (np.linalg.norm(r_rx, axis=1)[:, None] * np.cos(np.radians(el)) / r_shell[:, None]) ** 2)
    sun_cos = r_rx @ sun_dir_in / np.linalg.norm(r_rx, axis=1)
    vtec = model.vtec_tecu[0] + (model.vtec_tecu[1] - model.vtec_tecu[0]) * np.clip(sun_cos, 0, 1)
    stec = vtec[:, None] / np.clip(cos_zen_shell, 0.1, None)
    iono = {b: _TEC_TO_M_HZ2 * stec / f[b] ** 2 for b in ("1", "2")}
    # geometry per frequency phase centre
    rho = {b: np.linalg.norm(r_tx - (r_rx + pco_in[b])[:, None, :], axis=2) for b in ("1", "2")}
    noise_scale = ((1.0 + model.low_elevation_factor * np.exp(-np.clip(el, 0, 90) / 10.0))
                   / (1.0 + model.low_elevation_factor * np.exp(-3.0)))
    dcb = np.array([dcb_p1c1_s.get(k, 0.0) for k in ids]) * C_LIGHT_M_S

    def noisy(name):
        return rng.normal(0.0, 1.0, (n, s)) * model.noise_m[name] * noise_scale

    p1 = rho["1"] + clock_m + iono["1"] + noisy("P1")
    p2 = rho["2"] + clock_m + iono["2"] + noisy("P2")
    c1 = rho["1"] + clock_m + iono["1"] - dcb[None, :] + noisy("C1")
    l1 = (rho["1"] + clock_m - iono["1"] + noisy("L1")) / lam["1"] + amb1
    l2 = (rho["2"] + clock_m - iono["2"] + noisy("L2")) / lam["2"] + amb2
    lli = np.where(starts | (slips & (rng.random((n, s)) < model.lli_detected)), 1, 0).astype(np.int8)
    lli = np.where(tracked, lli, -1).astype(np.int8)
    mask = lambda x: np.where(tracked, x, np.nan)  # noqa: E731
    rho_if = (f["1"] ** 2 * rho["1"] - f["2"] ** 2 * rho["2"]) / (f["1"] ** 2 - f["2"] ** 2)
    data = {
        "C1": (("time", "sv"), mask(c1), {"units": "m", "long_name": "pseudorange C/A L1"}),
        "P1": (("time", "sv"), mask(p1), {"units": "m", "long_name": "pseudorange P L1"}),
        "P2": (("time", "sv"), mask(p2), {"units": "m", "long_name": "pseudorange P L2"}),
        "L1": (("time", "sv"), mask(l1), {"units": "1", "long_name": "carrier phase L1 [cycles]"}),
        "L2": (("time", "sv"), mask(l2), {"units": "1", "long_name": "carrier phase L2 [cycles]"}),
        "L1_lli": (("time", "sv"), lli, {"units": "1", "long_name": "loss-of-lock indicator L1"}),
        "L2_lli": (("time", "sv"), lli.copy(), {"units": "1", "long_name": "loss-of-lock indicator L2"}),
        "true_range_if_m": (("time", "sv"), mask(rho_if), {"units": "m", "long_name": "true ionosphere-free geometric range"}),
        "amb_L1_cyc": (("time", "sv"), amb1, {"units": "1", "long_name": "true L1 ambiguity [cycles]"}),
        "amb_L2_cyc": (("time", "sv"), amb2, {"units": "1", "long_name": "true L2 ambiguity [cycles]"}),
        "pass_true": (("time", "sv"), pass_true.astype(np.int32), {"units": "1", "long_name": "true pass number (-1: not tracked)"}),
        "el_deg": (("time", "sv"), np.where(tracked, el, np.nan), {"units": "degree", "long_name": "true antenna-frame elevation"}),
        "rx_clock_true_s": (("time",), dt_rx, {"units": "s", "long_name": "true receiver clock offset"}),
    }
    return xr.Dataset(data, coords={"sv": np.array(ids)})
