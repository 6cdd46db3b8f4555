"""Code-only single point positioning of a LEO receiver: the a-priori (kinematic) orbit.

Per epoch, position and receiver clock are estimated by iterated least squares from the
ionosphere-free code combination, with precise GNSS orbits and clocks, transmit-time
iteration, the Earth-rotation (Sagnac) correction and the periodic relativistic clock
correction ``-2 r·v / c²`` (IS-GPS-200, 20.3.3.3.3.1). There is no troposphere above a LEO.
GNSS satellite antenna offsets are applied when given (ANTEX); variations are not. The
result is an a-priori orbit at the decimetre-to-metre level, good for elevation angles,
attitude and as the start of a dynamic fit, not a product.

All epochs are solved at once with batched 4×4 normal equations (numpy), so a day of 10-s
data takes well under a second.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from leopod.constants import C_LIGHT_M_S, OMEGA_EARTH_WGS84_RAD_S
from leopod.gnss.attitude import gnss_body_axes
from leopod.gnss.products import GnssProducts

__all__ = ["SppResult", "solve_spp"]

log = logging.getLogger(__name__)


@dataclass
class SppResult:
    """Single point positioning solution at the epochs of the observations.

    Attributes
    ----------
    pos_m : ndarray, shape (n, 3)
        Earth-fixed receiver antenna position at the true reception time [m] (NaN if unsolved).
    clk_rx_m : ndarray, shape (n,)
        Receiver clock offset times c [m].
    n_used : ndarray of int, shape (n,)
        Satellites used per epoch.
    rms_m : ndarray, shape (n,)
        RMS of the post-fit code residuals per epoch [m].
    pdop : ndarray, shape (n,)
        Position dilution of precision.
    residual_m : ndarray, shape (n, s)
        Post-fit residuals [m] (NaN where not used).
    """

    pos_m: np.ndarray
    clk_rx_m: np.ndarray
    n_used: np.ndarray
    rms_m: np.ndarray
    pdop: np.ndarray
    residual_m: np.ndarray


def _rotate_z(vec: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotate vectors (p, 3) about +Z by ``-angle`` (Earth rotation during signal travel)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.empty_like(vec)
    out[:, 0] = c * vec[:, 0] + s * vec[:, 1]
    out[:, 1] = -s * vec[:, 0] + c * vec[:, 1]
    out[:, 2] = vec[:, 2]
    return out


def solve_spp(t_s: np.ndarray, sv: np.ndarray, code_if_m: np.ndarray, products: GnssProducts,
              *, sat_pco_body_m: np.ndarray | None = None, sun_ef_m: np.ndarray | None = None,
              min_sv: int = 5, max_residual_m: float = 30.0, iterations: int = 8) -> SppResult:
    """Solve position and clock per epoch from ionosphere-free code.

    Parameters
    ----------
    t_s : ndarray, shape (n,)
        Receiver time tags [s since ``products.ref``].
    sv : ndarray of str, shape (s,)
        Satellite ids of the columns of ``code_if_m``.
    code_if_m : ndarray, shape (n, s)
        Ionosphere-free code [m], NaN where absent.
    products : GnssProducts
        GNSS orbits and clocks consistent with the code (same reference signals).
    sat_pco_body_m : ndarray, shape (s, 3), optional
        Ionosphere-free antenna phase-centre offsets of the transmitters in their body frame
        [m] (NaN rows: satellite not used). Without them the solution is biased by up to
        metres for satellites with large offsets (GPS Block IIA: 2.5 m).
    sun_ef_m : ndarray, shape (n, 3), optional
        Earth-fixed Sun position per epoch [m]; required with ``sat_pco_body_m`` for the
        yaw-steering attitude.
    min_sv : int
        Minimum number of satellites for a solution (5 gives one redundant observation,
        which is what outlier screening needs).
    max_residual_m : float
        Observations with a larger post-fit residual are rejected one at a time (the
        largest first) and the epoch re-solved [m].
    iterations : int
        Gauss-Newton iterations per solve.

    Returns
    -------
    SppResult
    """
    n, s = code_if_m.shape
    isv = products.sv_index(sv)
    valid = np.isfinite(code_if_m) & (isv[None, :] >= 0)
    # transmit time from the pseudorange, then satellite position, velocity and clock there
    ep, col = np.nonzero(valid)
    p_obs = code_if_m[ep, col]
    t_tx = t_s[ep] - p_obs / C_LIGHT_M_S
    dt_sv = products.clock(isv[col], t_tx)
    t_tx = t_tx - np.nan_to_num(dt_sv)
    pos_sv, vel_sv, _ = products.position(isv[col], t_tx)
    dt_sv = products.clock(isv[col], t_tx)
    if sat_pco_body_m is not None:
        axes = gnss_body_axes(pos_sv, sun_ef_m[ep])
        pos_sv = pos_sv + np.einsum("pji,pj->pi", axes, sat_pco_body_m[col])
    rel_s = -2.0 * np.einsum("pc,pc->p", pos_sv, vel_sv) / C_LIGHT_M_S**2
    corr_obs = p_obs + C_LIGHT_M_S * (dt_sv + rel_s)       # = geometric range + receiver clock
    ok = np.isfinite(corr_obs) & np.isfinite(pos_sv).all(axis=1)

    obs = np.full((n, s), np.nan)
    obs[ep[ok], col[ok]] = corr_obs[ok]
    sat = np.full((n, s, 3), np.nan)
    sat[ep[ok], col[ok]] = pos_sv[ok]
    use = np.isfinite(obs)

    x = np.zeros((n, 4))
    for _round in range(s):
        x = _gauss_newton(obs, sat, use, x, iterations)
        res = _residuals(obs, sat, x)
        res_abs = np.where(use, np.abs(res), -1.0)
        worst = res_abs.argmax(axis=1)
        worst_val = res_abs[np.arange(n), worst]
        n_use = use.sum(axis=1)
        drop = (worst_val > max_residual_m) & (n_use > min_sv)
        if not drop.any():
            break
        use[np.nonzero(drop)[0], worst[drop]] = False
    res = _residuals(obs, sat, x)
    res = np.where(use, res, np.nan)
    n_used = use.sum(axis=1)
    solved = n_used >= min_sv
    rms = np.sqrt(np.nansum(res**2, axis=1) / np.maximum(n_used, 1))
    pdop = _pdop(sat, use, x)
    pos = np.where(solved[:, None], x[:, :3], np.nan)
    clk = np.where(solved, x[:, 3], np.nan)
    bad_fit = solved & (rms > max_residual_m)
    pos[bad_fit] = np.nan
    clk[bad_fit] = np.nan
    log.info("SPP: %d of %d epochs solved (>= %d satellites), median RMS %.2f m",
             np.isfinite(pos[:, 0]).sum(), n, min_sv, np.nanmedian(rms) if solved.any() else np.nan)
    return SppResult(pos_m=pos, clk_rx_m=clk, n_used=n_used, rms_m=np.where(solved, rms, np.nan),
                     pdop=pdop, residual_m=res)


def _geometry(sat: np.ndarray, x: np.ndarray):
    """Sagnac-rotated satellite positions, ranges and unit vectors for states ``x``."""
    n, s, _ = sat.shape
    rx = x[:, None, :3]
    diff = sat - rx
    rho0 = np.linalg.norm(diff, axis=2)
    angle = OMEGA_EARTH_WGS84_RAD_S * rho0 / C_LIGHT_M_S
    rot = _rotate_z(sat.reshape(-1, 3), angle.reshape(-1)).reshape(n, s, 3)
    diff = rot - rx
    rho = np.linalg.norm(diff, axis=2)
    return rho, diff / rho[..., None]


def _residuals(obs, sat, x):
    rho, _ = _geometry(sat, x)
    return obs - (rho + x[:, None, 3])


def _gauss_newton(obs, sat, use, x, iterations):
    n = obs.shape[0]
    x = x.copy()
    for _ in range(iterations):
        rho, unit = _geometry(sat, x)
        design = np.concatenate([-unit, np.ones(unit.shape[:2] + (1,))], axis=2)  # (n, s, 4)
        w = use.astype(float)
        design = np.where(use[..., None], design, 0.0)
        resid = np.where(use, obs - (rho + x[:, None, 3]), 0.0)
        normal = np.einsum("nsi,ns,nsj->nij", design, w, design)
        rhs = np.einsum("nsi,ns,ns->ni", design, w, resid)
        good = use.sum(axis=1) >= 4
        normal[~good] = np.eye(4)
        rhs[~good] = 0.0
        try:
            dx = np.linalg.solve(normal, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            dx = np.stack([np.linalg.lstsq(normal[k], rhs[k], rcond=None)[0] for k in range(n)])
        x += dx
        if np.nanmax(np.abs(dx[:, :3])) < 1e-4:
            break
    return x


def _pdop(sat, use, x):
    _, unit = _geometry(sat, x)
    design = np.concatenate([-unit, np.ones(unit.shape[:2] + (1,))], axis=2)
    design = np.where(use[..., None], design, 0.0)
    normal = np.einsum("nsi,nsj->nij", design, design)
    good = use.sum(axis=1) >= 4
    normal[~good] = np.eye(4)
    cov = np.linalg.inv(normal)
    pdop = np.sqrt(np.trace(cov[:, :3, :3], axis1=1, axis2=2))
    return np.where(good, pdop, np.nan)
