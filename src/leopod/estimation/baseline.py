"""Baseline of a formation pair: both orbits estimated jointly with fixed DD ambiguities.

The two arcs of a leader A and a follower B are each linearised once at their float
solutions (:meth:`leopod.estimation.float_pod.FixedPod.normals`: receiver clocks
pre-eliminated epoch by epoch, :mod:`leopod.estimation.normals`). Their reduced normal
equations are stacked block-diagonally and the fixed double differences
(:func:`leopod.ambiguity.double_difference.resolve_dd_systems`) are added as
pseudo-observations coupling the ambiguities of A and B (Zhang et al. 2024, eq. 4)::

    N = diag(N_A, N_B) + Dᵀ W D,    b = [b_A; b_B] + Dᵀ W (v − D x₀)

with ``D`` the (k, n) design of the DD constraints over the ambiguity columns (−1 at
``a_i``, +1 at ``b_i``, +1 at ``a_j``, −1 at ``b_j``), ``W = diag(1/σ²)`` and ``x₀`` the
float ambiguity values at the linearisation. One solve gives both corrections and their
joint covariance; each orbit is corrected through its partials
(:class:`leopod.estimation.orbit_correction.CorrectedOrbit`). The baseline
``Δr = r_B − r_A`` has the covariance
``G_B C_BB G_Bᵀ + G_A C_AA G_Aᵀ − G_B C_BA G_Aᵀ − G_A C_AB G_Bᵀ`` (cross terms from the
joint solve; Kroes et al. 2005, GRACE baseline).

**Relative dynamics** (``baseline.dynamics: relative``). Two satellites a few km apart feel
nearly the same unmodelled forces (the same thermospheric density structures of hundreds of
km, the same Sun and Earth radiation on twins of one design); what the estimator's empirical
accelerations, drag and SRP scales and pulses absorb is therefore nearly common, and the
baseline needs only the differential part. Each parameter of the follower that has a
counterpart of the leader (the same force-model parameter name on the same arc, or the pulse
of the same epoch in the same direction) gets the pseudo-observation::

    x_B,j − x_A,j = 0 ± σ_rel,j

with ``σ_rel`` the expected differential level (:class:`BaselineSettings`; the campaign's
comment derives it from the simulated differential acceleration). The initial states, the
follower's burn accelerations, the receiver-specific ISBs and the ambiguities stay free: the
common orbit errors then cancel in ``r_B − r_A`` while each orbit is still fitted to its own
undifferenced data (in the spirit of the relative dynamics of GRACE baseline filters, Kroes
et al. 2005; here as pseudo-observations of the joint normal equations).
``independent`` (default): no such rows, the two dynamics as in two PODs.

**Reference fixed** (``baseline.mode: reference_fixed``, Zhang et al. 2024, sec. 2): the
leader's parameters are held at its single-difference-fixed POD (``dx_A`` given) and only the
follower is estimated: the conditional of the joint system on ``x_A``,
``(N_B + D_Bᵀ W D_B) dx_B = b_B + D_Bᵀ W (v − D x₀ − D_A dx_A)``, with the DD constraints
tying the follower's ambiguities to the leader's fixed ones and, with relative dynamics, its
pulses and empirical accelerations to the leader's fixed values. The leader then has no
covariance: the baseline's formal sigma is the follower's.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import xarray as xr

from leopod.ambiguity.double_difference import DdConstraints
from leopod.estimation.float_pod import ArcNormals, PodResult
from leopod.estimation.normals import NormalEquations, solve
from leopod.frames.earth_rotation import gcrf_to_itrf
from leopod.frames.rtn import rtn_matrix
from leopod.settings import Settings
from leopod.time.calendar import seconds_since

__all__ = ["BaselineSettings", "JointSolution", "baseline_rtn", "constraint_residuals",
           "dd_rows", "fixed_baseline", "fixed_correction", "float_baseline", "joint_solve",
           "reference_fixed_solve", "relative_rows"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class BaselineSettings(Settings):
    """How the two arcs of a pair are tied together (config ``baseline``).

    Attributes
    ----------
    mode : str
        ``joint``: both arcs estimated together; ``reference_fixed``: the leader held at its
        fixed POD, the follower estimated (module docstring).
    dynamics : str
        ``independent``: each arc with its own a-priori constraints only; ``relative``: the
        parameters the two arcs share tied by differential sigmas (module docstring).
    relative_pulse_sigma_m_s : tuple of 3 float
        σ of ``Δv_B − Δv_A`` of pulses of the same epoch, R, T, N [m/s].
    relative_empirical_sigma_m_s2 : float
        σ of the difference of an empirical acceleration coefficient [m/s²].
    relative_drag_scale_sigma : float
        σ of the difference of a drag scale factor [1].
    relative_srp_scale_sigma : float
        σ of the difference of an SRP scale factor [1].
    dd_constraint_sigma_m : float or None
        σ of the fixed DD constraints [m]; None: the ambiguity step's ``constraint_sigma_m``.
    """

    SCHEMA_DEF = "baseline"

    mode: str
    dynamics: str
    relative_pulse_sigma_m_s: tuple[float, float, float]
    relative_empirical_sigma_m_s2: float
    relative_drag_scale_sigma: float
    relative_srp_scale_sigma: float
    dd_constraint_sigma_m: float | None


def _pulse_matches(a: ArcNormals, b: ArcNormals, tolerance_s: float = 1.0):
    """Index pairs (i_a, i_b) of the pulse parameters of the same epoch and direction."""
    if a.pulse_epochs_s is None or b.pulse_epochs_s is None:
        return np.empty(0, int), np.empty(0, int), np.empty(0, int)
    ta = a.pulse_epochs_s + float(seconds_since(np.datetime64(a.t_ref, "ns"), b.t_ref))
    tb = b.pulse_epochs_s
    if ta.size == 0 or tb.size == 0:
        return np.empty(0, int), np.empty(0, int), np.empty(0, int)
    nearest = np.clip(np.searchsorted(ta, tb), 0, ta.size - 1)
    better = np.clip(nearest - 1, 0, ta.size - 1)
    nearest = np.where(np.abs(ta[better] - tb) < np.abs(ta[nearest] - tb), better, nearest)
    ok = np.abs(ta[nearest] - tb) <= tolerance_s
    j = np.flatnonzero(ok)
    axis = np.arange(3)
    ia = (a.names.index("pulse_R_0") + 3 * nearest[j])[:, None] + axis     # R, T, N of each
    ib = (b.names.index("pulse_R_0") + 3 * j)[:, None] + axis
    return ia.ravel(), ib.ravel(), np.tile(axis, j.size)


def relative_rows(a: ArcNormals, b: ArcNormals, settings: BaselineSettings
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """Pseudo-observations ``x_B,j − x_A,j = 0 ± σ_rel`` of the shared dynamic parameters.

    Parameters
    ----------
    a, b : ArcNormals
        Leader and follower (``names``, ``values``, ``t_ref``, ``pulse_epochs_s`` set).
    settings : BaselineSettings

    Returns
    -------
    design : ndarray, shape (p, n_A + n_B)
    misclosure : ndarray, shape (p,)
        ``0 − (x_B,j − x_A,j)`` at the linearisation [parameter units].
    weight : ndarray, shape (p,)
        ``1/σ_rel²``.
    counts : dict of str to int
        Rows per kind (``pulse``, ``empirical``, ``drag_scale``, ``srp_scale``).

    Notes
    -----
    Force-model parameters are paired by name only when both arcs have the same reference
    epoch (their intervals then coincide); otherwise only pulses are paired (by epoch).
    """
    n_a, n_b = a.normals.rhs.size, b.normals.rhs.size
    ia, ib, sig = [], [], []
    counts = {"pulse": 0, "empirical": 0, "drag_scale": 0, "srp_scale": 0}
    pa, pb, axis = _pulse_matches(a, b)
    ia += list(pa)
    ib += list(pb)
    sig += list(np.asarray(settings.relative_pulse_sigma_m_s, dtype=float)[axis])
    counts["pulse"] = int(pa.size)
    if np.datetime64(a.t_ref, "ns") == np.datetime64(b.t_ref, "ns"):
        index_a = {name: i for i, name in enumerate(a.names)}
        kinds = (("emp_", "empirical", settings.relative_empirical_sigma_m_s2),
                 ("drag_scale_", "drag_scale", settings.relative_drag_scale_sigma),
                 ("srp_scale_", "srp_scale", settings.relative_srp_scale_sigma))
        for j, name in enumerate(b.names):
            for prefix, kind, sigma in kinds:
                if name.startswith(prefix) and name in index_a:
                    ia.append(index_a[name])
                    ib.append(j)
                    sig.append(sigma)
                    counts[kind] += 1
    else:
        log.warning("leader and follower arcs have different reference epochs (%s, %s): "
                    "only pulses are tied", a.t_ref, b.t_ref)
    ia, ib = np.asarray(ia, int), np.asarray(ib, int)
    design = np.zeros((ia.size, n_a + n_b))
    design[np.arange(ia.size), ia] = -1.0
    design[np.arange(ib.size), n_a + ib] = 1.0
    misclosure = -(b.values[ib] - a.values[ia])
    return design, misclosure, 1.0 / np.asarray(sig, dtype=float) ** 2, counts


def constraint_residuals(design: np.ndarray, misclosure: np.ndarray, dx_a: np.ndarray,
                         dx_b: np.ndarray) -> np.ndarray:
    """Residuals ``D dx − misclosure`` (p,) of pseudo-observations after a joint solve (the
    value of each constrained combination minus its constraint) [constraint units]."""
    return design @ np.concatenate([dx_a, dx_b]) - misclosure


class JointSolution(NamedTuple):
    """Result of :func:`joint_solve`.

    Attributes
    ----------
    dx_a, dx_b : ndarray, shape (k_A + a_A,), (k_B + a_B,)
        Corrections of the parameters of each arc (columns of its :class:`ArcNormals`).
    covariance : ndarray, shape (n, n)
        Joint ``N⁻¹`` (units of the weights) over ``[x_A; x_B]``, n = n_A + n_B.
    n_a : int
        Size of A's block.
    n_constraints : int
        DD constraints used (both ambiguities of A and B active).
    """

    dx_a: np.ndarray
    dx_b: np.ndarray
    covariance: np.ndarray
    n_a: int
    n_constraints: int


def dd_rows(a: ArcNormals, b: ArcNormals, pass_a: np.ndarray, pass_b: np.ndarray,
            c: DdConstraints) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Design, misclosure and weight of the DD constraints over ``[x_A; x_B]``.

    Parameters
    ----------
    a, b : ArcNormals
    pass_a, pass_b : ndarray of int
        Pass id of each row of the float ambiguity datasets of A and B (the indices of
        ``c`` refer to these rows).
    c : DdConstraints

    Returns
    -------
    design : ndarray, shape (p, n_A + n_B)
    misclosure : ndarray, shape (p,)
        ``value − D x₀`` [m] at the float ambiguities.
    weight : ndarray, shape (p,)
        ``1/σ²`` [1/m²]. Constraints on a pass without used phase are dropped.
    """
    n_a = a.normals.rhs.size

    def columns(arc: ArcNormals, passes: np.ndarray, offset: int) -> np.ndarray:
        col = np.full(max(int(passes.max(initial=0)), int(arc.active.max(initial=0))) + 1, -1)
        col[arc.active] = offset + arc.k + np.arange(arc.active.size)
        return col[passes]

    ai = columns(a, pass_a[c.amb_a_i], 0)
    aj = columns(a, pass_a[c.amb_a_j], 0)
    bi = columns(b, pass_b[c.amb_b_i], n_a)
    bj = columns(b, pass_b[c.amb_b_j], n_a)
    ok = (ai >= 0) & (aj >= 0) & (bi >= 0) & (bj >= 0)
    if not ok.all():
        log.warning("%d of %d DD constraints dropped: an ambiguity without used phase",
                    int((~ok).sum()), ok.size)
    ai, aj, bi, bj = ai[ok], aj[ok], bi[ok], bj[ok]
    p = np.arange(ai.size)
    design = np.zeros((ai.size, n_a + b.normals.rhs.size))
    for cols, sign in ((ai, -1.0), (bi, 1.0), (aj, 1.0), (bj, -1.0)):
        np.add.at(design, (p, cols), sign)
    x0 = np.concatenate([np.zeros(a.k), a.ambiguity_m, np.zeros(b.k), b.ambiguity_m])
    misclosure = c.value_m[ok] - design @ x0
    return design, misclosure, 1.0 / c.sigma_m[ok] ** 2


def joint_solve(a: ArcNormals, b: ArcNormals, design: np.ndarray, misclosure: np.ndarray,
                weight: np.ndarray) -> JointSolution:
    """One solve of the stacked normal equations with the DD constraints (module docstring).

    Parameters
    ----------
    a, b : ArcNormals
    design, misclosure, weight
        Of :func:`dd_rows` (or any pseudo-observations over ``[x_A; x_B]``).
    """
    n_a, n_b = a.normals.rhs.size, b.normals.rhs.size
    matrix = np.zeros((n_a + n_b, n_a + n_b))
    matrix[:n_a, :n_a] = a.normals.matrix
    matrix[n_a:, n_a:] = b.normals.matrix
    wd = design * weight[:, None]
    matrix += design.T @ wd
    rhs = np.concatenate([a.normals.rhs, b.normals.rhs]) + wd.T @ misclosure
    ne = NormalEquations(matrix=matrix, rhs=rhs, ltpl=a.normals.ltpl + b.normals.ltpl,
                         n_rows=a.normals.n_rows + b.normals.n_rows)
    dx, cov = solve(ne)
    return JointSolution(dx_a=dx[:n_a], dx_b=dx[n_a:], covariance=cov, n_a=n_a,
                         n_constraints=int(weight.size))


def reference_fixed_solve(a: ArcNormals, b: ArcNormals, design: np.ndarray,
                          misclosure: np.ndarray, weight: np.ndarray,
                          dx_a: np.ndarray) -> JointSolution:
    """The follower's solution with the leader's correction held at ``dx_a`` (module
    docstring, Reference fixed).

    Parameters
    ----------
    a, b : ArcNormals
    design, misclosure, weight
        Pseudo-observations over ``[x_A; x_B]`` (:func:`dd_rows`, :func:`relative_rows`).
    dx_a : ndarray, shape (k_A + a_A,)
        The leader's correction from its linearisation to its fixed solution.

    Returns
    -------
    JointSolution
        ``dx_a`` as given; ``covariance`` zero in the leader's rows and columns.
    """
    n_a, n_b = a.normals.rhs.size, b.normals.rhs.size
    d_a, d_b = design[:, :n_a], design[:, n_a:]
    reduced = misclosure - d_a @ dx_a
    wd = d_b * weight[:, None]
    ne = NormalEquations(matrix=b.normals.matrix + d_b.T @ wd,
                         rhs=b.normals.rhs + wd.T @ reduced, ltpl=b.normals.ltpl,
                         n_rows=b.normals.n_rows)
    dx_b, cov_b = solve(ne)
    cov = np.zeros((n_a + n_b, n_a + n_b))
    cov[n_a:, n_a:] = cov_b
    return JointSolution(dx_a=np.asarray(dx_a, dtype=float).copy(), dx_b=dx_b, covariance=cov,
                         n_a=n_a, n_constraints=int(weight.size))


def fixed_correction(a: ArcNormals, parameters: xr.Dataset, ambiguities: xr.Dataset
                     ) -> np.ndarray:
    """The correction ``dx_A`` (k + a,) from the leader's linearisation (its float solution)
    to its fixed POD: parameter ``estimate`` by name minus ``a.values``, ambiguity
    ``value_m`` by ``pass_index`` minus ``a.ambiguity_m``.

    Raises
    ------
    ValueError
        If a parameter or an active pass of ``a`` is missing from the fixed solution.
    """
    names = [str(n) for n in parameters.parameter.values]
    missing = sorted(set(a.names) - set(names))
    if missing:
        raise ValueError(f"fixed POD parameters lack {missing[:5]}")
    est = parameters.estimate.values
    index = {n: i for i, n in enumerate(names)}
    dx_par = np.array([est[index[n]] for n in a.names]) - a.values
    value = dict(zip(ambiguities.pass_index.values.tolist(), ambiguities.value_m.values))
    lost = [int(p) for p in a.active if int(p) not in value]
    if lost:
        raise ValueError(f"fixed POD ambiguities lack passes {lost[:5]}")
    dx_amb = np.array([value[int(p)] for p in a.active]) - a.ambiguity_m
    return np.concatenate([dx_par, dx_amb])


def baseline_rtn(pos_a_gcrf: np.ndarray, vel_a_gcrf: np.ndarray, baseline_gcrf: np.ndarray,
                 cov_gcrf: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Baseline (m, 3) and covariance (m, 3, 3) in the leader's radial/along/cross frame."""
    r = rtn_matrix(pos_a_gcrf, vel_a_gcrf)
    return (np.einsum("mij,mj->mi", r, baseline_gcrf),
            np.einsum("mij,mjk,mlk->mil", r, cov_gcrf, r))


def fixed_baseline(times: np.ndarray, res_a: PodResult, res_b: PodResult,
                   joint: JointSolution, *, eop=None,
                   label: str = "DD-fixed joint solution") -> xr.Dataset:
    """The DD-fixed baseline ``r_B − r_A`` with its formal covariance (cross terms included).

    Parameters
    ----------
    times : ndarray of datetime64, shape (m,)
        Epochs inside both arcs.
    res_a, res_b : PodResult
        The joint solution of each arc (:meth:`FixedPod.solution`); their covariances are
        scaled by each arc's σ0², the cross block of ``joint`` by ``σ0_A σ0_B``.
    joint : JointSolution
    label : str
        The solution type named in the sigma attributes.

    Returns
    -------
    xarray.Dataset
        ``baseline_itrf_m`` (time, xyz), ``baseline_rtn_m`` and ``sigma_rtn_m`` (time, rtn),
        ``sigma_3d_m`` (time,), ``sigma_rtn_no_cross_m`` (the sigma without the cross terms).
    """
    t_a = seconds_since(times, res_a.t_ref)
    t_b = seconds_since(times, res_b.t_ref)
    st_a, cov_a, g_a = res_a.orbit_at(t_a)
    st_b, cov_b, g_b = res_b.orbit_at(t_b)
    k_a, k_b = g_a.shape[2], g_b.shape[2]
    c_ba = joint.covariance[joint.n_a:joint.n_a + k_b, :k_a] * res_a.sigma0 * res_b.sigma0
    cross = np.einsum("mik,kl,mjl->mij", g_b, c_ba, g_a)
    independent = cov_a + cov_b
    cov = independent - cross - np.swapaxes(cross, 1, 2)
    base = st_b[:, :3] - st_a[:, :3]
    return _dataset(times, st_a, st_b, base, cov, independent, eop, label)


def float_baseline(orbit_a: xr.Dataset, orbit_b: xr.Dataset, times: np.ndarray) -> xr.Dataset:
    """The float baseline: difference of the two float orbits (orbit datasets of the float
    POD) at ``times``, formal sigmas from the two independent solutions.

    The float orbit files hold each orbit's sigmas in its own RTN frame; for a formation a few
    km apart the two frames differ by ~|Δr|/r (< 1e-3 rad), so the leader-frame sigmas are
    taken as ``sqrt(σ_A² + σ_B²)`` per component.
    """
    a, b = orbit_a.sel(time=times), orbit_b.sel(time=times)
    base_itrf = b.pos_itrf_m.values - a.pos_itrf_m.values
    r = rtn_matrix(a.pos_gcrf_m.values, a.vel_gcrf_m_s.values)
    rtn = np.einsum("mij,mj->mi", r, b.pos_gcrf_m.values - a.pos_gcrf_m.values)
    sigma = np.sqrt(a.sigma_rtn_m.values**2 + b.sigma_rtn_m.values**2)
    return xr.Dataset({
        "baseline_itrf_m": (("time", "xyz"), base_itrf,
                            {"units": "m", "long_name": "follower minus leader position",
                             "reference_frame": "ITRF"}),
        "baseline_rtn_m": (("time", "rtn"), rtn, {"units": "m", "long_name":
                           "follower minus leader in the leader's radial/along/cross axes"}),
        "sigma_rtn_m": (("time", "rtn"), sigma, {"units": "m", "long_name":
                        "formal sigma (two independent float solutions)"}),
        "sigma_3d_m": (("time",), np.sqrt(np.sum(sigma**2, axis=1)),
                       {"units": "m", "long_name": "formal 3D sigma"}),
    }, coords={"time": times, "xyz": ["x", "y", "z"], "rtn": ["R", "T", "N"]})


def _dataset(times, st_a, st_b, base_gcrf, cov, independent, eop, label) -> xr.Dataset:
    pos_a, _ = gcrf_to_itrf(times, st_a[:, :3], st_a[:, 3:], eop=eop)
    pos_b, _ = gcrf_to_itrf(times, st_b[:, :3], st_b[:, 3:], eop=eop)
    rtn, cov_rtn = baseline_rtn(st_a[:, :3], st_a[:, 3:], base_gcrf, cov)
    _, ind_rtn = baseline_rtn(st_a[:, :3], st_a[:, 3:], base_gcrf, independent)

    def sig(c):
        return np.sqrt(np.maximum(np.diagonal(c, axis1=1, axis2=2), 0.0))

    return xr.Dataset({
        "baseline_itrf_m": (("time", "xyz"), pos_b - pos_a,
                            {"units": "m", "long_name": "follower minus leader position",
                             "reference_frame": "ITRF"}),
        "baseline_rtn_m": (("time", "rtn"), rtn, {"units": "m", "long_name":
                           "follower minus leader in the leader's radial/along/cross axes"}),
        "sigma_rtn_m": (("time", "rtn"), sig(cov_rtn),
                        {"units": "m", "long_name": f"formal sigma ({label}, cross terms)"}),
        "sigma_3d_m": (("time",), np.sqrt(np.maximum(np.trace(cov, axis1=1, axis2=2), 0.0)),
                       {"units": "m", "long_name": "formal 3D sigma"}),
        "sigma_rtn_no_cross_m": (("time", "rtn"), sig(ind_rtn),
                                 {"units": "m", "long_name": "formal sigma without the cross "
                                  "terms of the joint solution"}),
    }, coords={"time": times, "xyz": ["x", "y", "z"], "rtn": ["R", "T", "N"]})
