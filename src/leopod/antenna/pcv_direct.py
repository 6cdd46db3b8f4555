"""In-flight receiver PCV by the direct method: node values in the POD normal equations.

The PCV node values (and optionally a PCO-Z correction) are parameters of the observation
equations of the POD (Wang et al. 2024, eqs. 10-11; Jäggi et al. 2009): the ionosphere-free
code and phase of an observation in antenna direction (α, z) gain::

    ΔPCV(α, z) = Σ_j w_j(α, z) p_j        (+ cos-like PCO-Z term, below)

with ``w_j`` the bilinear weights of the four nodes around the direction
(:meth:`leopod.codebias.grid.AntennaGrid.weights`, Wang et al. 2024, eqs. 7-9) - the
interpolation the POD applies to an ANTEX grid, so ``p`` is the correction of the nodes that
the POD uses next. An observed range is the range to the mean phase centre plus the PCV
(ANTEX 1.4), so the partial of the computed observation with respect to ``p_j`` is ``+w_j``.
A PCO-Z correction ``δ`` moves the phase centre by ``δ`` along body +Z: its partial is
``−e·Z_body`` (``e`` the unit line of sight from the LEO), the same as the POD's own
``pco_z_m`` (:mod:`leopod.estimation.float_pod`).

Per day (:func:`day_normals`): the fixed (or float) POD of the arc is linearised at its float
solution (:class:`leopod.estimation.float_pod.FixedPod`), the rows get the antenna columns
(:func:`leopod.estimation.normals.accumulate`: receiver clocks pre-eliminated epoch by epoch),
the fixed single differences their constraints, and every arc parameter (initial state,
force-model parameters, pulses, ISBs, ambiguities; the POD's own PCO-Z if it estimates one) is
reduced out by the Schur complement::

    N_red = N_pp − N_pa N_aa⁻¹ N_ap,     b_red = b_p − N_pa N_aa⁻¹ b_a.

Per period (:func:`solve_normals`): the reduced systems of the days are summed and solved once.

Datum (tested in tests/antenna/test_pcv_direct.py on exact synthetic normal equations and in
tests/antenna/test_pcv_direct_closed_loop.py on a simulated arc). The interpolation weights of
a direction sum to one, so adding a constant ``c`` to every node adds ``c`` to every
observation of an epoch: the epoch clock absorbs it exactly and ``N_red 1 = 0``. With a PCO-Z
estimated and the antenna boresight along body −Z (the default antenna frame), the PCO-Z row
is ``−e·Z_body = +cos z`` (z the antenna zenith angle: moving the antenna towards nadir
lengthens every range by ``δ cos z``), so ``δ = 1`` with ``p_j = −cos z_j`` changes every row
by ``cos z − Σ w_j cos z_j``: zero up to the bilinear interpolation error of ``cos z``
(≤ Δz²/8, 0.4 % on a 10° grid) - a near-null direction.
A pattern constant over a pass is absorbed by its ambiguity only if it is constant over the
sky (the code rows, weak, tie the rest). Two more directions are nearly singular, through the
orbit: a horizontal offset ``Δ`` of the phase centre in the body frame is the PCV pattern
``Δ_X cos e cos α + Δ_Y cos e sin α`` (e elevation, α azimuth from +X), and the same range
change as moving the receiver by ``Δ`` - along-track (X) or cross-track (Y) in the nominal
attitude. A constant along-track offset is nearly a Keplerian motion (a shift in time), a
constant cross-track one is followed by the cross-track pulses: on a simulated day the
scaled eigenvalues of the reduced normal matrix are 1e-15 (constant), 7e-6 (X), 2e-4 (Y), then
0.26 (tests/antenna/test_pcv_direct_closed_loop.py). Whatever a map gets wrong in these
patterns the orbit takes as a constant T/N offset of the same size when the map is applied
(README, "Antenna calibration"). The conditions that fix the datum (hard constraints, Lagrange
multipliers), over the well-observed nodes ``W`` (``count ≥ min_count``):

- ``datum: mean``: ``Σ_{j∈W} p_j = 0``;  ``datum: zenith``: ``p_zenith = 0``;
- with a PCO-Z (``estimate_pco_z``, or a PCO-Z reduced with the days' arc parameters):
  ``Σ_{j∈W} (cos z_j − mean_W cos z) p_j = 0`` - the map has no cos z-like part, the PCO-Z
  takes it;
- ``no_horizontal_offset`` (default): the same for ``cos e cos α`` and ``cos e sin α`` - the
  map has no part like a horizontal offset, the horizontal PCO stays the a-priori one (as
  Wang et al. 2024, sec. 2.3, keep the ground PCO).

Nodes without any observation are not estimated; all observed nodes get a weak a-priori pull
towards no correction (σ :data:`leopod.antenna.pcv.WEAK_SIGMA_M`, in units of the phase
weights), and nodes with fewer than ``min_count`` phase observations (nearest-node counts, as
the residual method counts) are left out of the map (NaN) and of the datum.

Sigmas are formal, ``σ0 √Q_jj`` with ``Q`` the constrained inverse and the a-posteriori
sigma of unit weight ``σ0² = (Σ_days vᵀPv − x̂ᵀb) / (Σ_days f − u + c)``: ``vᵀPv`` and the
degrees of freedom ``f`` of each day's POD solution without the antenna parameters (its
observation rows, as :mod:`leopod.estimation.float_pod` counts them), ``x̂ᵀb`` what the
antenna parameters take from it (the identity ``min vᵀPv = lᵀPl − x̂ᵀb`` of least squares),
``u`` the antenna unknowns and ``c`` the datum conditions.

Day normal equations (netCDF, :func:`day_normals`; dims ``parameter``, ``parameter_2``)
--------------------------------------------------------------------------------------
``normal_matrix`` (parameter, parameter_2), ``rhs`` (parameter)
    Reduced normal equations of the nodes (node order of :class:`AntennaGrid`) and, last,
    the PCO-Z [1/m², 1/m].
``count`` (node)
    Used phase observations nearest to each node [1].
attrs: ``az_step_deg``, ``zenith_step_deg``, ``pco_z`` (1: last parameter is the PCO-Z),
``pod_pco_z`` (1: a daily PCO-Z was reduced), ``vtpv``, ``dof`` (of the day's POD solution),
``n_rows``, ``n_phase``, ``n_ambiguity_constraints``, ``date``, ``satellite``, ``solution``.

References
----------
Wang, Y., Guo, J., Ya, S., Jia, Y., Guo, H., Chang, X., Liu, X. (2024). Impact of
pseudo-stochastic pulse and phase center variation on precision orbit determination of
Haiyang-2A from experimental HY2 receiver GPS data. Remote Sensing 16(8), 1336.
doi:10.3390/rs16081336
Jäggi, A., Dach, R., Montenbruck, O., Hugentobler, U., Bock, H., Beutler, G. (2009). Phase
center modeling for LEO GPS receiver antennas and its impact on precise orbit determination.
Journal of Geodesy 83, 1145-1162. doi:10.1007/s00190-009-0333-2
"""

from __future__ import annotations

import logging
from collections.abc import Iterable

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import xarray as xr

from leopod.antenna.pcv import WEAK_SIGMA_M, PcvSettings, map_dataset
from leopod.codebias.grid import AntennaGrid
from leopod.estimation.fixed_arc import FixedSolutions, run_fixed_arc
from leopod.estimation.float_pod import FixedPod

__all__ = ["AntennaColumns", "arc_normals", "datum_conditions", "day_normals",
           "reduce_normals", "solve_normals"]

log = logging.getLogger(__name__)

_POD_PCO_Z = "pco_z_m"


class AntennaColumns:
    """Columns of the antenna parameters for :meth:`FixedPod.normals` (module docstring).

    Parameters
    ----------
    grid : AntennaGrid
    pco_z : bool
        Append the PCO-Z column.

    Attributes
    ----------
    count : ndarray of int, shape (n_nodes,)
        Phase rows nearest to each node, set by the last call.
    el_deg, az_deg : ndarray, shape (r,)
        Antenna elevation and azimuth of the rows of the last call [deg].
    """

    def __init__(self, grid: AntennaGrid, pco_z: bool):
        self.grid, self.pco_z = grid, pco_z
        self.count = np.zeros(grid.n_nodes, dtype=np.int64)
        self.el_deg = self.az_deg = np.zeros(0)

    def __call__(self, model, pair: np.ndarray, is_phase: np.ndarray) -> sp.csr_matrix:
        """Sparse (r, n_nodes [+ 1]) partials of the rows ``pair`` (observation indices of
        ``model``, a :class:`leopod.estimation.obsmodel.ModelResult`)."""
        el, az = model.el_deg[pair], model.az_deg[pair]
        self.el_deg, self.az_deg = el, az
        node = self.grid.nearest(az[is_phase], el[is_phase])
        self.count = np.bincount(node[node >= 0], minlength=self.grid.n_nodes)
        a = self.grid.design(az, el)
        if self.pco_z:
            up = -np.sum(model.los_gcrf[pair] * model.z_body_gcrf[pair], axis=1)
            a = sp.hstack([a, sp.csr_matrix(up[:, None])]).tocsr()
        return a


def reduce_normals(matrix: np.ndarray, rhs: np.ndarray, n_keep: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Schur complement of ``N x = b`` onto its last ``n_keep`` unknowns.

    Parameters
    ----------
    matrix : ndarray, shape (n, n)
    rhs : ndarray, shape (n,)
    n_keep : int

    Returns
    -------
    matrix_reduced : ndarray, shape (n_keep, n_keep)
        ``N_pp − N_pa N_aa⁻¹ N_ap``.
    rhs_reduced : ndarray, shape (n_keep,)
        ``b_p − N_pa N_aa⁻¹ b_a``.
    """
    r = matrix.shape[0] - n_keep
    n_aa, n_ap = matrix[:r, :r], matrix[:r, r:]
    d = np.sqrt(np.diag(n_aa))
    if np.any(~np.isfinite(d)) or np.any(d == 0):
        raise ValueError("a reduced parameter has no observation")
    factor = scipy.linalg.cho_factor(n_aa / np.outer(d, d), lower=True, check_finite=False)
    x = scipy.linalg.cho_solve(factor, np.column_stack([n_ap, rhs[:r]]) / d[:, None],
                               check_finite=False) / d[:, None]
    reduced = matrix[r:, r:] - n_ap.T @ x[:, :-1]
    return 0.5 * (reduced + reduced.T), rhs[r:] - n_ap.T @ x[:, -1]


def day_normals(pod: FixedPod, grid: AntennaGrid, *, constraints=None, pco_z: bool = False,
                sigma0: float, date: str = "", satellite: str = "",
                solution: str = "") -> xr.Dataset:
    """Reduced normal equations of the antenna parameters of one arc (module docstring).

    Parameters
    ----------
    pod : FixedPod
        The arc linearised at its float solution.
    grid : AntennaGrid
        Nodes of the PCV map.
    constraints : tuple, optional
        Fixed single differences ``(pass_i, pass_j, value_m, sigma_m)`` of the fixed POD
        (:func:`leopod.estimation.fixed_arc.constraints_of`); None: the float solution.
    pco_z : bool
        Keep a PCO-Z correction with the nodes (it must not be one of the POD's own arc
        parameters then: ``pod.estimate_pco_z`` false).
    sigma0 : float
        A-posteriori sigma of unit weight of the day's POD solution (``PodResult.sigma0``:
        with the degrees of freedom of the rows, ``vᵀPv`` for the sigmas of the period).
    date, satellite, solution : str
        Identification written into the attributes.

    Returns
    -------
    xarray.Dataset
        The day normal equations of the module docstring.
    """
    columns = AntennaColumns(grid, pco_z)
    arc = pod.normals(constraints, columns=columns)
    names = list(arc.names)
    pod_pco_z = _POD_PCO_Z in names
    if pco_z and pod_pco_z:
        raise ValueError("pcv.estimate_pco_z with pod.estimate_pco_z: the PCO-Z would be a "
                         "parameter of every day and of the period at once; switch one off")
    ne = arc.normals
    n_keep = grid.n_nodes + int(pco_z)
    matrix, rhs = reduce_normals(ne.matrix, ne.rhs, n_keep)
    rows = arc.rows
    dof = max(rows.epoch.size - arc.k - arc.active.size - np.unique(rows.epoch).size, 1)
    n_constraints = 0 if constraints is None else int(np.asarray(constraints[0]).size)
    log.info("PCV normal equations %s %s: %d rows (%d phase), %d arc parameters and %d "
             "ambiguities reduced, %d of %d nodes observed%s", satellite, date,
             rows.epoch.size, int((rows.amb >= 0).sum()), arc.k, arc.active.size,
             int(np.sum(np.diag(matrix)[:grid.n_nodes] > 0)), grid.n_nodes,
             ", PCO-Z kept" if pco_z else "")
    az, el = grid.node_directions()
    dims = ("parameter", "parameter_2")
    ds = xr.Dataset(
        {"normal_matrix": (dims, matrix, {"units": "m-2", "long_name": "reduced normal "
                                          "matrix of the PCV nodes (and PCO-Z, last)"}),
         "rhs": ("parameter", rhs, {"units": "m-1", "long_name": "reduced right-hand side"}),
         "count": ("node", columns.count.astype(np.int64),
                   {"units": "1", "long_name": "used phase observations nearest to the node"}),
         "node_azimuth_deg": ("node", az, {"units": "degree", "long_name": "node azimuth in "
                                           "the antenna frame"}),
         "node_elevation_deg": ("node", el, {"units": "degree", "long_name": "node elevation "
                                             "in the antenna frame"})},
        coords={"parameter": np.arange(n_keep), "parameter_2": np.arange(n_keep),
                "node": np.arange(grid.n_nodes)})
    ds.attrs.update(az_step_deg=float(grid.az_step_deg), zenith_step_deg=float(grid.el_step_deg),
                    pco_z=int(pco_z), pod_pco_z=int(pod_pco_z), vtpv=float(sigma0**2 * dof),
                    dof=int(dof),
                    n_rows=int(rows.epoch.size), n_phase=int((rows.amb >= 0).sum()),
                    n_ambiguity_constraints=n_constraints, date=date, satellite=satellite,
                    solution=solution, method="direct (Wang et al. 2024, eqs. 10-11)")
    return ds


def arc_normals(date: str, data, signals, arc, pod, forces, antenna, float_solution,
                settings: PcvSettings, *, table: xr.Dataset | None = None, ambiguity=None,
                satellite: str = "", **arc_options) -> xr.Dataset:
    """Day normal equations (:func:`day_normals`) of the arc of ``date`` at its fixed POD
    (``table`` and ``ambiguity`` given: :func:`leopod.estimation.fixed_arc.run_fixed_arc`,
    its kept constraints) or at its float solution (``table`` None).

    Parameters
    ----------
    date, data, signals, arc, pod, forces, antenna, float_solution
        As for :func:`leopod.estimation.fixed_arc.run_fixed_arc` (the POD's own).
    settings : PcvSettings
        Grid and ``estimate_pco_z``.
    table : xarray.Dataset, optional
        Single differences of the ambiguity step.
    ambiguity : leopod.ambiguity.resolve.ArSettings, optional
        Needed with ``table``.
    satellite : str
    **arc_options
        ``code_correction``, ``yaw_flips``, ``eop``, ``attitude``, ``limits`` of the POD.
    """
    if table is None:
        fixed = FixedSolutions(date, data, signals, arc, pod, forces, antenna, float_solution,
                               **arc_options)
        pod_system, constraints = fixed.pod, None
        sigma0, solution = fixed.solve(None).result.sigma0, "float_pod"
    else:
        result = run_fixed_arc(date, data, signals, arc, pod, forces, antenna, table,
                               float_solution, ambiguity, **arc_options)
        pod_system, constraints = result.pod, result.constraints
        sigma0, solution = result.arc.result.sigma0, "fixed_pod"
    return day_normals(pod_system, settings.grid, constraints=constraints,
                       pco_z=settings.estimate_pco_z, sigma0=sigma0, date=date,
                       satellite=satellite, solution=solution)


def datum_conditions(grid: AntennaGrid, well: np.ndarray, datum: str, cos_z_term: bool,
                     n_params: int, horizontal: bool = False) -> np.ndarray:
    """Rows ``C`` (c, n_params) of the datum conditions ``C x = 0`` (module docstring).

    Parameters
    ----------
    grid : AntennaGrid
    well : ndarray of bool, shape (n_nodes,)
        Well-observed nodes.
    datum : {"mean", "zenith"}
    cos_z_term : bool
        Add the condition that removes the cos z-like part (a PCO-Z is estimated).
    n_params : int
        Unknowns: the nodes and, after them, the PCO-Z if any.
    horizontal : bool
        Add the conditions that remove the parts like a horizontal offset, ``cos e cos α``
        and ``cos e sin α`` (e elevation, α azimuth of the node).
    """
    c = np.zeros(n_params)
    if datum == "zenith":
        c[grid.n_nodes - 1] = 1.0
    else:
        c[:grid.n_nodes] = well
    rows = [c]
    az, el = (np.radians(v) for v in grid.node_directions())
    terms = ([np.sin(el)] if cos_z_term else []) + (
        [np.cos(el) * np.cos(az), np.cos(el) * np.sin(az)] if horizontal else [])
    for term in terms:
        c = np.zeros(n_params)
        c[:grid.n_nodes] = np.where(well, term - term[well].mean(), 0.0)
        rows.append(c)
    return np.array(rows)


def _constrained_solve(matrix, rhs, conditions):
    """Solution and inverse of ``N x = b`` subject to ``C x = 0`` (bordered system)."""
    n, c = matrix.shape[0], conditions.shape[0]
    bordered = np.zeros((n + c, n + c))
    bordered[:n, :n] = matrix
    bordered[:n, n:] = conditions.T
    bordered[n:, :n] = conditions
    d = np.sqrt(np.r_[np.diag(matrix), np.ones(c)])
    inverse = np.linalg.inv(bordered / np.outer(d, d)) / np.outer(d, d)
    x = inverse[:n, :n] @ rhs
    return x, inverse[:n, :n]


def _summed(days: Iterable[xr.Dataset], grid: AntennaGrid) -> dict:
    """Normal equations, counts, ``vᵀPv`` and degrees of freedom summed over the days (one
    day in memory at a time); the days must share grid and PCO-Z."""
    total: dict = {"n_days": 0}
    for d in days:
        pco_z = int(d.attrs["pco_z"])
        if (float(d.attrs["az_step_deg"]) != grid.az_step_deg
                or float(d.attrs["zenith_step_deg"]) != grid.el_step_deg
                or pco_z != total.get("pco_z", pco_z)):
            raise ValueError(f"PCV normal equations of {d.attrs.get('date')}: grid "
                             f"{d.attrs['az_step_deg']} x {d.attrs['zenith_step_deg']} deg, "
                             f"PCO-Z {pco_z}; the period needs {grid.az_step_deg:g} x "
                             f"{grid.el_step_deg:g} deg and the PCO-Z of its first day")
        if not total["n_days"]:
            total.update(pco_z=pco_z, pod_pco_z=0, matrix=0.0, rhs=0.0, count=0, vtpv=0.0,
                         dof=0)
        total["matrix"] = total["matrix"] + d.normal_matrix.values
        total["rhs"] = total["rhs"] + d.rhs.values
        total["count"] = total["count"] + d["count"].values
        total["vtpv"] += float(d.attrs["vtpv"])
        total["dof"] += int(d.attrs["dof"])
        total["pod_pco_z"] |= int(d.attrs["pod_pco_z"])
        total["n_days"] += 1
    if not total["n_days"]:
        raise ValueError("PCV: no day normal equations to solve")
    return total


def solve_normals(days: Iterable[xr.Dataset], settings: PcvSettings, *, period: str = "",
                  satellite: str = "", solution: str = "") -> xr.Dataset:
    """PCV map (and PCO-Z) of the summed day normal equations of a period.

    Parameters
    ----------
    days : iterable of xarray.Dataset
        Day normal equations of :func:`day_normals` on the grid of ``settings`` (read one at
        a time if an iterator).
    settings : PcvSettings
        Grid, ``min_count``, ``datum``, ``no_horizontal_offset``.
    period, satellite, solution : str
        Identification written into the attributes.

    Returns
    -------
    xarray.Dataset
        The map Dataset of :mod:`leopod.antenna.pcv` (``residual_std_m`` NaN: no residuals
        here) with attributes ``pco_z_m``, ``pco_z_sigma_m`` (NaN without a PCO-Z),
        ``sigma0`` and ``estimator`` = ``direct``.

    Raises
    ------
    ValueError
        If there is no day, the days differ in grid or parameters, no node is well observed,
        or the zenith datum's node is not.
    """
    grid = settings.grid
    total = _summed(days, grid)
    pco_z = bool(total["pco_z"])
    matrix, rhs, count = total["matrix"], total["rhs"], total["count"]
    n = grid.n_nodes
    observed = np.r_[np.diag(matrix)[:n] > 0, np.ones(int(pco_z), bool)]
    well = count >= settings.min_count
    if not well.any():
        raise ValueError(f"PCV {satellite} {period}: no node has {settings.min_count} phase "
                         f"observations ({int(count.sum())} in all)")
    if settings.datum == "zenith" and not well[-1]:
        raise ValueError(f"PCV {satellite} {period}: zenith datum, but the zenith node has "
                         f"{count[-1]} phase observations (< {settings.min_count})")
    cos_z_term = pco_z or bool(total["pod_pco_z"])
    conditions = datum_conditions(grid, well, settings.datum, cos_z_term, matrix.shape[0],
                                  settings.no_horizontal_offset)
    use = np.flatnonzero(observed)
    pull = np.r_[np.full(n, WEAK_SIGMA_M**-2), np.zeros(int(pco_z))]
    x_use, q_use = _constrained_solve(matrix[np.ix_(use, use)] + np.diag(pull[use]),
                                      rhs[use], conditions[:, use])
    vtpv = total["vtpv"] - float(x_use @ rhs[use])
    dof = total["dof"] - use.size + conditions.shape[0]
    sigma0 = float(np.sqrt(max(vtpv, 0.0) / max(dof, 1)))
    x = np.full(matrix.shape[0], np.nan)
    sigma = np.full(matrix.shape[0], np.nan)
    x[use] = x_use
    sigma[use] = sigma0 * np.sqrt(np.maximum(np.diag(q_use), 0.0))
    pcv = np.where(well, x[:n], np.nan)
    log.info("PCV %s %s (direct): %d days, %d of %d nodes with >= %d phase observations, "
             "datum %s%s, sigma0 %.3f, map RMS %.2f mm%s", satellite, period, total["n_days"],
             int(well.sum()), n, settings.min_count, settings.datum,
             (" + no cos z term" if cos_z_term else "")
             + (" + no horizontal-offset terms" if settings.no_horizontal_offset else ""), sigma0,
             1e3 * float(np.sqrt(np.nanmean(pcv**2))),
             f", PCO-Z {1e3 * x[-1]:.2f} ± {1e3 * sigma[-1]:.2f} mm" if pco_z else "")
    ds = map_dataset(grid, pcv, np.where(well, sigma[:n], np.nan), np.full(n, np.nan), count)
    ds.attrs.update(estimator="direct", datum=settings.datum, datum_offset_m=0.0,
                    az_step_deg=float(grid.az_step_deg), zenith_step_deg=float(grid.el_step_deg),
                    min_count=int(settings.min_count), n_residuals=int(count.sum()),
                    n_nodes_estimated=int(well.sum()), period=period, satellite=satellite,
                    solution=solution, n_days=total["n_days"], sigma0=sigma0,
                    pco_z_m=float(x[-1]) if pco_z else float("nan"),
                    pco_z_sigma_m=float(sigma[-1]) if pco_z else float("nan"),
                    datum_cos_z=int(cos_z_term),
                    datum_horizontal=int(settings.no_horizontal_offset),
                    method="direct (Wang et al. 2024, eqs. 10-11)")
    return ds
