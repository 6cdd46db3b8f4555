"""Kinematic baseline of a formation pair: the follower's epoch-wise position relative to the
leader from receiver single differences with fixed double-difference ambiguities.

The kinematic counterpart of the reduced-dynamic baseline (Zhang et al. 2024, sec. 2.3 and
Table 6: dynamic − kinematic baseline 11.6 / 10.4 / 7.3 mm 3D for GPS / BDS-3 / both; Kroes
et al. 2005 and Jäggi et al. 2007 for GRACE). No force model: at every epoch ``e`` the
follower B's position offset ``δr_e`` from a reference orbit (its float reduced-dynamic orbit)
and the differential clock ``c (dt_B − dt_A)`` are estimated from the between-receiver single
differences (SD) of ionosphere-free code and phase of the GNSS satellites that both receivers
track at that epoch, with the leader A held at its own orbit::

    SD_e^s = L_B^s − L_A^s = ρ_B^s(r_B) − ρ_A^s(r_A) + c (dt_B − dt_A) + (B_B,b − B_A,a) + ε

The GNSS clock and orbit errors cancel (to the baseline over the GNSS range, ~2.5e-4 for
5 km: a 1-cm error of A's orbit moves B's estimate and leaves the baseline within 3 µm), and
so do the satellite biases. One ambiguity per *node* ``(a, b)`` (a pass of A and a pass of B
of the same satellite overlapping in time, :mod:`leopod.ambiguity.double_difference`) is
common to all its epochs; the fixed DDs of the baseline step, ``(B_B,b_i − B_A,a_i) −
(B_B,b_j − B_A,a_j) = value``, tie the nodes together as tight pseudo-observations (the
*DD-fixed* kinematic baseline; without them the *float* one). The estimation, screening,
variance factors, PDOP checks and positions at the nominal epochs are those of the kinematic
POD (:func:`leopod.estimation.kinematic.solve_kinematic`): the SD rows take the place of one
receiver's rows, the elevation weights those of the follower (the two receivers see a GNSS
satellite within hundredths of a degree), with an a-priori variance factor 2 for the
difference of two equally weighted observations (then estimated).

SDs rather than DDs: the SDs of different GNSS satellites at an epoch share no observation, so
they are uncorrelated and the differential clock takes up the receiver clocks exactly as the DD
would eliminate them (the two are equivalent estimators). Several GNSS in one solution (the
paper's G+C): the between-receiver code biases differ by system, so one differential code
inter-system bias per further system is estimated with the ambiguities
(:func:`leopod.estimation.kinematic.solve_kinematic`); the phase biases go into the node
ambiguities.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.estimation.float_pod import PodObservations, PodSettings
from leopod.estimation.kinematic import (
    KinematicModel,
    KinematicResult,
    KinematicSettings,
    orbit_state,
    solve_kinematic,
)
from leopod.estimation.obsmodel import ModelResult
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices
from leopod.frames.rtn import rtn_matrix
from leopod.gnss.products import GnssProducts

__all__ = ["KinematicBaseline", "ReceiverDifferences", "baseline_dataset",
           "dd_node_constraints", "receiver_differences"]

log = logging.getLogger(__name__)

#: A-priori variance factor of a single difference of two equally weighted observations.
_SD_VARIANCE_FACTOR = 2.0


@dataclass(eq=False)
class ReceiverDifferences:
    """Between-receiver single differences of the chosen systems (:func:`receiver_differences`).

    Attributes
    ----------
    obs : PodObservations
        The SD rows on the follower's epochs: ``code_m``/``phase_m`` B − A [m],
        ``pass_index`` the node of a phase row (−1: no phase SD), ``sat`` into ``obs.sv``.
    rows_a, rows_b : ndarray of int, shape (n,)
        Row of each SD in the leader's and the follower's observations.
    nodes : ndarray of int, shape (k, 2)
        ``(pass_a, pass_b)`` of each node (index = node number).
    """

    obs: PodObservations
    rows_a: np.ndarray
    rows_b: np.ndarray
    nodes: np.ndarray


def receiver_differences(obs_a: PodObservations, obs_b: PodObservations,
                         systems: str) -> ReceiverDifferences:
    """Single differences B − A of the rows of ``systems`` at common epochs and satellites.

    Parameters
    ----------
    obs_a, obs_b : PodObservations
        The leader's and the follower's rows (e.g. of :func:`leopod.estimation.arc.setup_arc`).
    systems : str
        GNSS letters, the reference of the inter-system bias first (e.g. ``"G"``, ``"GC"``).

    Returns
    -------
    ReceiverDifferences
        Code SD where both codes exist, phase SD where both phases belong to a pass; the
        clocks ``obs.clk_rx_m`` are B's a-priori clocks minus A's at the same epoch (0 where A
        has no epoch).
    """
    sv = np.union1d(obs_a.sv, obs_b.sv)
    sv = sv[np.isin(sv.astype("U1"), list(systems))]
    sv_a = np.searchsorted(sv, obs_a.sv)[obs_a.sat]
    sv_b = np.searchsorted(sv, obs_b.sv)[obs_b.sat]
    epoch_a = np.searchsorted(obs_b.times, obs_a.times)         # A's epochs on B's axis
    on_grid = (epoch_a < obs_b.times.size) & (
        obs_b.times[np.minimum(epoch_a, obs_b.times.size - 1)] == obs_a.times)
    use_a = on_grid[obs_a.epoch] & np.isin(obs_a.sv.astype("U1"), list(systems))[obs_a.sat]
    use_b = np.isin(obs_b.sv.astype("U1"), list(systems))[obs_b.sat]
    cand_a, cand_b = np.flatnonzero(use_a), np.flatnonzero(use_b)
    key_a = epoch_a[obs_a.epoch[cand_a]] * sv.size + sv_a[cand_a]     # one row per
    key_b = obs_b.epoch[cand_b] * sv.size + sv_b[cand_b]               # (epoch, satellite)
    _, ka, kb = np.intersect1d(key_a, key_b, assume_unique=True, return_indices=True)
    order = np.argsort(cand_b[kb], kind="stable")
    rows_a, rows_b = cand_a[ka][order], cand_b[kb][order]
    pa, pb = obs_a.pass_index[rows_a], obs_b.pass_index[rows_b]
    phase = (pa >= 0) & (pb >= 0)
    node_key = np.where(phase, pa.astype(np.int64) * (int(pb.max(initial=0)) + 1) + pb, -1)
    _, first, node = np.unique(node_key[phase], return_index=True, return_inverse=True)
    nodes = np.stack([pa[phase][first], pb[phase][first]], axis=1).reshape(-1, 2)
    pass_index = np.full(rows_b.size, -1)
    pass_index[phase] = node
    clk_a = np.zeros(obs_b.times.size)
    clk_a[epoch_a[on_grid]] = np.nan_to_num(np.asarray(obs_a.clk_rx_m, dtype=float))[on_grid]
    sd = PodObservations(
        times=obs_b.times, sv=sv, epoch=obs_b.epoch[rows_b], sat=sv_b[rows_b],
        code_m=obs_b.code_m[rows_b] - obs_a.code_m[rows_a],
        phase_m=np.where(phase, obs_b.phase_m[rows_b] - obs_a.phase_m[rows_a], np.nan),
        pass_index=pass_index,
        clk_rx_m=np.nan_to_num(np.asarray(obs_b.clk_rx_m, dtype=float)) - clk_a,
        nl_wavelength_m=0.0, systems=tuple(systems))
    return ReceiverDifferences(obs=sd, rows_a=rows_a, rows_b=rows_b, nodes=nodes)


def dd_node_constraints(table: xr.Dataset, nodes: np.ndarray, systems: str,
                        sigma_m: float) -> tuple:
    """Constraints ``(node_i, node_j, value_m, sigma_m)`` of the constrained DDs of ``systems``
    (GNSS letters).

    Parameters
    ----------
    table : xarray.Dataset
        DD table of the baseline step (``constrained``, ``system``, ``pass_a_i``,
        ``pass_b_i``, ``pass_a_j``, ``pass_b_j``, ``fixed_if_m``;
        :func:`leopod.ambiguity.double_difference.resolve_dd_systems`).
    nodes : ndarray of int, shape (k, 2)
        ``(pass_a, pass_b)`` of the SD nodes (:class:`ReceiverDifferences`).
    systems : str
    sigma_m : float
        Sigma of every constraint [m].

    Returns
    -------
    tuple of ndarray
        In the format of :func:`leopod.estimation.fixed_arc.constraints_of` over node numbers;
        DDs whose nodes have no SD phase here are left out.
    """
    sel = (table.constrained.values == 1) & np.isin(table.system.values.astype(str),
                                                    list(systems))
    lookup = {(int(a), int(b)): k for k, (a, b) in enumerate(nodes)}
    ni = np.array([lookup.get((int(a), int(b)), -1) for a, b in
                   zip(table.pass_a_i.values[sel], table.pass_b_i.values[sel])], dtype=int)
    nj = np.array([lookup.get((int(a), int(b)), -1) for a, b in
                   zip(table.pass_a_j.values[sel], table.pass_b_j.values[sel])], dtype=int)
    keep = (ni >= 0) & (nj >= 0)
    if (~keep).any():
        log.info("%d of %d constrained %s DDs have a node without SD phase here: left out",
                 int((~keep).sum()), keep.size, systems)
    value = table.fixed_if_m.values[sel][keep]
    return ni[keep], nj[keep], value, np.full(value.shape, float(sigma_m))


class KinematicBaseline:
    """Kinematic positions of the follower from SDs with the leader (module docstring): the
    leader's model and each system selection's SD rows built once, then one solve per set of
    constraints (float, DD-fixed).

    Parameters
    ----------
    obs_a, obs_b : PodObservations
        The leader's and the follower's rows; their ``clk_rx_m`` are the receiver clocks of
        their float POD [m] (they set the reception times).
    products : GnssProducts
    reference_a : xarray.Dataset
        The leader's orbit, held (``pos_gcrf_m``, ``vel_gcrf_m_s`` on ``time``).
    reference_b : xarray.Dataset
        The follower's reference orbit (linearisation), e.g. its float orbit.
    t_ref : datetime64
    pod : PodSettings
    settings : KinematicSettings
    eop : EarthOrientation, optional
    antennas_a, antennas_b : dict
        Each receiver's antenna terms (``leo_pco_body_m``, ``sat_pco_body_m``, ``sat_pcv_m``,
        ``leo_attitude``; :attr:`leopod.estimation.arc.ArcProblem.antennas`).

    Attributes
    ----------
    leader_state : ndarray, shape (m, 6)
        The leader's held GCRF position [m] and velocity [m/s] at the follower's nominal epochs.
    """

    def __init__(self, obs_a: PodObservations, obs_b: PodObservations, products: GnssProducts,
                 reference_a: xr.Dataset, reference_b: xr.Dataset, t_ref, pod: PodSettings,
                 settings: KinematicSettings, *, eop=None, antennas_a: dict, antennas_b: dict):
        self._obs_a, self._obs_b = obs_a, obs_b
        self._pod, self._settings = pod, settings
        self._lin_b = KinematicModel(obs_b, products, reference_b, t_ref, eop, antennas_b)
        self._model_a, _ = KinematicModel(obs_a, products, reference_a, t_ref, eop,
                                          antennas_a).model(
            np.zeros((obs_a.times.size, 3)), np.nan_to_num(np.asarray(obs_a.clk_rx_m,
                                                                        dtype=float)))
        self._sd: dict[str, ReceiverDifferences] = {}
        self.leader_state = orbit_state(reference_a, obs_b.times, t_ref)

    def differences(self, systems: str) -> ReceiverDifferences:
        """The SD rows of ``systems`` (:func:`receiver_differences`, built once)."""
        if systems not in self._sd:
            self._sd[systems] = receiver_differences(self._obs_a, self._obs_b, systems)
        return self._sd[systems]

    def solve(self, systems: str, constraints_table: xr.Dataset | None = None,
              constraint_sigma_m: float = 1e-3) -> KinematicResult:
        """The follower's kinematic orbit from the SDs of ``systems``.

        Parameters
        ----------
        systems : str
            GNSS letters of the solution, the reference of the inter-system bias first.
        constraints_table : xarray.Dataset, optional
            DD table of the baseline step: its constrained DDs make the DD-fixed solution;
            None: float.
        constraint_sigma_m : float
            Sigma of a DD constraint [m].

        Returns
        -------
        KinematicResult
            Its ``clock_m`` is the differential clock B − A.
        """
        sd = self.differences(systems)
        constraints = (None if constraints_table is None else dd_node_constraints(
            constraints_table, sd.nodes, systems, constraint_sigma_m))
        clock_a = np.nan_to_num(np.asarray(self._obs_b.clk_rx_m, dtype=float)) - sd.obs.clk_rx_m
        ia, ib, model_a, lin_b = sd.rows_a, sd.rows_b, self._model_a, self._lin_b

        def model_at(offset: np.ndarray, clock_diff: np.ndarray):
            model_b, pos_b = lin_b.model(offset, clock_a + clock_diff)
            return ModelResult(code_m=model_b.code_m[ib] - model_a.code_m[ia],
                               phase_m=model_b.phase_m[ib] - model_a.phase_m[ia],
                               los_gcrf=model_b.los_gcrf[ib], el_deg=model_b.el_deg[ib],
                               az_deg=model_b.az_deg[ib], z_body_gcrf=model_b.z_body_gcrf[ib],
                               valid=model_b.valid[ib] & model_a.valid[ia]), pos_b

        log.info("kinematic baseline %s: %d SD rows (%d code, %d phase) over %d nodes, %s",
                 systems, ib.size, int(np.isfinite(sd.obs.code_m).sum()),
                 int((sd.obs.pass_index >= 0).sum()), sd.nodes.shape[0],
                 "float" if constraints is None else f"{constraints[0].size} DD constraints")
        return solve_kinematic(sd.obs, model_at, lin_b.reference_at, sd.obs.clk_rx_m,
                               self._pod, self._settings, constraints=constraints,
                               clock_offset_m=clock_a,
                               variance_factors=(_SD_VARIANCE_FACTOR, _SD_VARIANCE_FACTOR),
                               label=f"kinematic baseline {systems}")


def baseline_dataset(result: KinematicResult, leader_state: np.ndarray, *,
                     eop=None) -> xr.Dataset:
    """The kinematic baseline B − A as a Dataset.

    Parameters
    ----------
    result : KinematicResult
        Of :meth:`KinematicBaseline.solve`.
    leader_state : ndarray, shape (m, 6)
        The leader's held GCRF position [m] and velocity [m/s] at the nominal epochs.
    eop : EarthOrientation, optional

    Returns
    -------
    xarray.Dataset
        ``baseline_itrf_m`` (time, xyz), ``baseline_rtn_m`` and ``sigma_rtn_m`` (time, rtn)
        in the leader's radial, along-track, cross-track frame, ``solved``, ``n_satellites``
        (SD code), ``pdop``, ``clock_diff_m`` (c (dt_B − dt_A)); attributes ``sigma0``,
        ``dd_constraints``, ``epochs_solved``, ``epochs``, ``isb_m`` (differential code
        inter-system biases of the systems after the first [m]).
    """
    rot, _ = gcrf_from_itrf_matrices(result.times, eop=eop)            # ITRF -> GCRF
    base_gcrf = result.pos_gcrf_m - leader_state[:, :3]
    base_itrf = np.einsum("mji,mj->mi", rot, base_gcrf)
    rtn = rtn_matrix(leader_state[:, :3], leader_state[:, 3:])
    cov_rtn = np.einsum("mij,mjk,mlk->mil", rtn, result.cov_gcrf_m2, rtn)
    return xr.Dataset(
        {
            "baseline_itrf_m": (("time", "xyz"), base_itrf, {
                "units": "m", "reference_frame": "ITRF",
                "long_name": "kinematic baseline follower minus leader (NaN: not solved)"}),
            "baseline_rtn_m": (("time", "rtn"), np.einsum("mij,mj->mi", rtn, base_gcrf), {
                "units": "m", "long_name": "kinematic baseline in the leader's radial, "
                "along-track, cross-track frame"}),
            "sigma_rtn_m": (("time", "rtn"),
                            np.sqrt(np.abs(np.diagonal(cov_rtn, axis1=1, axis2=2))),
                            {"units": "m", "long_name": "formal sigma (sigma0-scaled)"}),
            "clock_diff_m": (("time",), result.clock_m, {
                "units": "m", "long_name": "differential receiver clock c (dt_B - dt_A)"}),
            "pdop": (("time",), result.pdop, {"units": "1",
                                              "long_name": "PDOP of the SD code geometry"}),
            "n_satellites": (("time",), result.n_satellites,
                             {"units": "1", "long_name": "satellites with SD code"}),
            "solved": (("time",), result.solved.astype("i1"),
                       {"units": "1", "long_name": "1: epoch solved"}),
        },
        coords={"time": result.times, "xyz": ["x", "y", "z"], "rtn": ["R", "T", "N"]},
        attrs={"sigma0": result.sigma0, "dd_constraints": result.n_constraints,
               "iterations": result.iterations, "converged": int(result.converged),
               "epochs_solved": int(result.solved.sum()), "epochs": int(result.times.size),
               "isb_m": np.asarray(result.isb_m, dtype=float)},
    )
