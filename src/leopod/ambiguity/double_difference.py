"""Inter-satellite double-difference (DD) WL/NL ambiguity resolution between two LEO receivers.

Two LEOs A and B of a formation track the same GNSS satellites (Zhang et al. 2024, eqs. 1–4;
Kroes et al. 2005, GRACE; Allende-Alba et al. 2017, Swarm). With the float ionosphere-free
(IF) ambiguity of each receiver's own POD (:mod:`leopod.ambiguity.narrow_lane`),
``B_r^s = λ_NL N1 + λ_NL f2/(f1 − f2) N_WL + b_r,IF + b^s_IF``, and the HMW combination
``HMW_r^s/λ_WL = N_WL + w_r + w^s`` (:mod:`leopod.ambiguity.wide_lane`):

1. **Receiver single differences (nodes).** A pass ``a`` of receiver A and a pass ``b`` of
   receiver B of the same GNSS satellite ``s`` tracked at common epochs form the node
   ``(a, b)``: ``N_B,b − N_A,a``, in which the satellite biases ``w^s`` and ``b^s_IF`` cancel.
   The passes of each receiver are its own (a slip in one receiver ends only that receiver's
   pass), so one pass of A can belong to several nodes. The nodes of one satellite are the
   overlaps of two partitions of the time line: disjoint in time and, as vectors over the
   undifferenced ambiguities, linearly independent (their bipartite graph is a path).
2. **Double differences (edges).** Two nodes ``i`` (satellite ``s``) and ``j`` (satellite
   ``s0``) of the same system with at least ``min_common_s`` of common time give
   ``ΔN = (N_B^s − N_A^s) − (N_B^s0 − N_A^s0)`` (Zhang et al. 2024, eq. 3): the receiver biases
   ``w_r`` and ``b_r,IF`` cancel too, so no bias product is needed. Because the nodes are
   independent, the rank of a set of DDs over the undifferenced ambiguities is the graph rank
   of its edges over the nodes (:mod:`leopod.ambiguity.independent`).
3. **DD wide lane**: the receiver-SD HMW series ``h_B − h_A`` of every node is the input of
   :func:`~leopod.ambiguity.wide_lane.sd_wide_lane` with the node as "pass": the DD is
   averaged over the epochs common to all four passes, with the same sigma options (white or
   time-correlated, :mod:`leopod.ambiguity.correlation`).
4. **DD narrow lane** from the nodes' float IF values ``B_B,b − B_A,a`` and their covariance
   ``C_B[b, b'] + C_A[a, a']`` (:func:`~leopod.ambiguity.narrow_lane.sd_narrow_lane`). The two
   float solutions are separate POD runs and **their covariances are taken as independent**
   (no cross terms): a joint baseline solution will give them.
5. **Decisions** as for single differences (:func:`~leopod.ambiguity.resolve.decide`:
   rounding, Dong–Bock), or integer least squares of a maximal independent NL set with ratio
   and success-rate tests and partial fixing (``nl_method: ils``,
   :func:`~leopod.ambiguity.alternatives.ils_nl_decision`; LAMBDA of Teunissen 1995 and de
   Jonge & Tiberius 1996 in :mod:`leopod.ambiguity.ils`; partial fixing of the
   best-determined subset that passes the tests, Teunissen et al. 1999, Parkins 2011). With
   the fixed critical value of the ratio test, a large set is fixed only in part
   (Verhagen & Teunissen 2013: the fixed value is strict for many ambiguities): in the
   synthetic closed loop of a 24-h day (402 independent DDs, NL sigma ~0.065 cycles) ILS
   fixed 32 % of the independent DDs, rounding 99 %, both without a wrong fix.
6. **Independent set and constraints**: a maximal independent set of the fixed DDs,
   best-determined first, as pseudo-observations
   ``(B_B,b_i − B_A,a_i) − (B_B,b_j − B_A,a_j) = λ_NL (ΔN_NL + f2/(f1 − f2) ΔN_WL)`` [m]
   (Zhang et al. 2024, eq. 4) for a baseline solution (:func:`dd_constraint_matrix`).
"""

from __future__ import annotations

import logging
from typing import NamedTuple

import numpy as np
import xarray as xr

from leopod.ambiguity.alternatives import ils_nl_decision, wl_candidate_check
from leopod.ambiguity.consistency import float_consistent
from leopod.ambiguity.independent import fixing_rate, independent_edges
from leopod.ambiguity.narrow_lane import fixed_sd_if_m, sd_covariance_m2, sd_narrow_lane
from leopod.ambiguity.pairs import sd_pairs
from leopod.ambiguity.resolve import (
    ArSettings,
    arc_hmw,
    decide,
    require_common_data,
    wl_sigma_method,
)
from leopod.ambiguity.wide_lane import sd_wide_lane
from leopod.gnss.combinations import narrow_lane_wavelength_m
from leopod.signals import frequency_hz

__all__ = ["DdConstraints", "DdResolution", "ReceiverArc", "ReceiverSd", "dd_constraint_matrix",
           "receiver_sd", "receiver_sd_float", "resolve_dd", "resolve_dd_systems"]

log = logging.getLogger(__name__)


class ReceiverArc(NamedTuple):
    """The float POD arc of one receiver (inputs of :func:`resolve_dd`).

    Attributes
    ----------
    amb : xarray.Dataset
        Float ambiguities (:func:`leopod.estimation.outputs.ambiguity_dataset`:
        ``pass_index``, ``value_m``, ``covariance_m2``).
    residuals : xarray.Dataset
        Float residuals with ``pass_index`` on (time, sv).
    obs : xarray.Dataset
        Observations of the arc (codes corrected as the campaign wishes).
    antenna : xarray.Dataset or None
        Antenna range terms per band (:func:`leopod.ambiguity.resolve.resolve_arc`).
    """

    amb: xr.Dataset
    residuals: xr.Dataset
    obs: xr.Dataset
    antenna: xr.Dataset | None = None


class ReceiverSd(NamedTuple):
    """Receiver single differences (nodes) ``N_B,pass_b − N_A,pass_a`` of one satellite each.

    Attributes
    ----------
    sv : ndarray of str, shape (k,)
        GNSS satellite of the node.
    pass_a, pass_b : ndarray of int64, shape (k,)
        Pass ids of receivers A and B.
    amb_a, amb_b : ndarray of int64, shape (k,)
        Indices of the two passes in each receiver's float ambiguity dataset.
    start, end : ndarray of datetime64[ns], shape (k,)
        First and last epoch at which both passes are tracked.
    node_id : xarray.DataArray of int64, (time, sv)
        Node of each epoch and satellite tracked by both receivers, −1 elsewhere.
    hmw_cyc : xarray.DataArray, (time, sv)
        Receiver-SD HMW ``HMW_B/λ_WL − HMW_A/λ_WL`` [WL cycles] (NaN where either is missing).
    """

    sv: np.ndarray
    pass_a: np.ndarray
    pass_b: np.ndarray
    amb_a: np.ndarray
    amb_b: np.ndarray
    start: np.ndarray
    end: np.ndarray
    node_id: xr.DataArray
    hmw_cyc: xr.DataArray


def _amb_index(amb: xr.Dataset, passes: np.ndarray, name: str) -> np.ndarray:
    """Index in ``amb`` of every pass id (ValueError naming the receiver and the passes)."""
    lookup = {int(p): k for k, p in enumerate(amb["pass_index"].values)}
    missing = sorted({int(p) for p in passes} - lookup.keys())
    if missing:
        raise ValueError(f"receiver {name}: passes {missing} of the residuals' pass_index have "
                         "no float ambiguity")
    return np.array([lookup[int(p)] for p in passes], dtype=np.int64)


def receiver_sd(hmw_a: xr.DataArray, pid_a: xr.DataArray, hmw_b: xr.DataArray,
                pid_b: xr.DataArray, amb_a: xr.Dataset, amb_b: xr.Dataset,
                names=("A", "B")) -> ReceiverSd:
    """Nodes of the two receivers: pairs of passes of one satellite tracked at common epochs.

    Parameters
    ----------
    hmw_a, hmw_b : xarray.DataArray, (time, sv)
        HMW combinations [WL cycles] of receivers A and B.
    pid_a, pid_b : xarray.DataArray of int, (time, sv)
        Pass ids (−1: none) on the same grids as the HMW; the grids of A and B may differ
        (outer union, missing cells untracked).
    amb_a, amb_b : xarray.Dataset
        Float ambiguities of each receiver (``pass_index``).
    names : tuple of two str
        Receiver names for messages.

    Returns
    -------
    ReceiverSd
        Nodes sorted by (pass_a, pass_b).

    Raises
    ------
    ValueError
        If a pass of the residuals has no float ambiguity.
    """
    hmw_a, pid_a = xr.align(hmw_a, pid_a, join="exact")
    hmw_b, pid_b = xr.align(hmw_b, pid_b, join="exact")
    pa, pb = xr.align(pid_a.astype(np.int64), pid_b.astype(np.int64), join="outer",
                      fill_value=-1)
    pa, pb = pa.transpose("time", "sv"), pb.transpose("time", "sv")
    ha = hmw_a.reindex_like(pa).transpose("time", "sv").values
    hb = hmw_b.reindex_like(pa).transpose("time", "sv").values
    both = (pa.values >= 0) & (pb.values >= 0)
    t_idx, s_idx = np.nonzero(both)                  # row-major: time ascending
    keys = np.stack([pa.values[both], pb.values[both]], axis=1)
    uniq, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    last = np.zeros(uniq.shape[0], dtype=np.int64)
    np.maximum.at(last, inverse, t_idx)
    node = np.full(both.shape, -1, dtype=np.int64)
    node[both] = inverse
    times = pa["time"].values
    svs = pa["sv"].values.astype(str)
    if np.any(svs[s_idx] != svs[s_idx[first]][inverse]):
        raise ValueError("a pair of passes occurs in more than one satellite column")
    hmw = np.where(both, hb - ha, np.nan)
    log.debug("%d receiver single differences (%s-%s)", uniq.shape[0], names[1], names[0])
    return ReceiverSd(
        sv=svs[s_idx[first]], pass_a=uniq[:, 0], pass_b=uniq[:, 1],
        amb_a=_amb_index(amb_a, uniq[:, 0], names[0]),
        amb_b=_amb_index(amb_b, uniq[:, 1], names[1]),
        start=times[t_idx[first]], end=times[last],
        node_id=pa.copy(data=node), hmw_cyc=pa.copy(data=hmw).astype(float))


def receiver_sd_float(amb_a: xr.Dataset, amb_b: xr.Dataset, nodes: ReceiverSd
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Float IF values ``B_B,b − B_A,a`` [m] of the nodes and their covariance [m²].

    The covariances of the two float solutions are taken as independent: ``C = C_B[b, b'] +
    C_A[a, a']`` (module docstring, step 4).

    Returns
    -------
    value_m : ndarray, shape (k,)
    covariance_m2 : ndarray, shape (k, k)
    """
    a, b = nodes.amb_a, nodes.amb_b
    value = amb_b["value_m"].values[b] - amb_a["value_m"].values[a]
    cov = (amb_b["covariance_m2"].values[np.ix_(b, b)]
           + amb_a["covariance_m2"].values[np.ix_(a, a)])
    return value, cov


class DdConstraints(NamedTuple):
    """Pseudo-observations ``(B_B[amb_b_i] − B_A[amb_a_i]) − (B_B[amb_b_j] − B_A[amb_a_j]) =
    value_m ± sigma_m`` on the undifferenced float IF ambiguities of both receivers.

    Attributes
    ----------
    amb_a_i, amb_b_i, amb_a_j, amb_b_j : ndarray of int64, shape (k,)
        Indices in the float ambiguity datasets of A and B.
    value_m, sigma_m : ndarray, shape (k,)
        Fixed DD IF ambiguity and its sigma [m].
    """

    amb_a_i: np.ndarray
    amb_b_i: np.ndarray
    amb_a_j: np.ndarray
    amb_b_j: np.ndarray
    value_m: np.ndarray
    sigma_m: np.ndarray


def dd_constraint_matrix(c: DdConstraints, n_a: int, n_b: int) -> np.ndarray:
    """Design matrix (k, n_a + n_b) of the DD pseudo-observations over ``[B_A; B_B]``.

    Row: −1 at ``amb_a_i``, +1 at ``n_a + amb_b_i``, +1 at ``amb_a_j``, −1 at
    ``n_a + amb_b_j`` (Zhang et al. 2024, eq. 4).
    """
    m = np.zeros((c.value_m.size, n_a + n_b))
    k = np.arange(c.value_m.size)
    np.add.at(m, (k, c.amb_a_i), -1.0)
    np.add.at(m, (k, n_a + c.amb_b_i), 1.0)
    np.add.at(m, (k, c.amb_a_j), 1.0)
    np.add.at(m, (k, n_a + c.amb_b_j), -1.0)
    return m


class DdResolution(NamedTuple):
    """Result of :func:`resolve_dd`: the table (dim ``dd``) and the constraints."""

    table: xr.Dataset
    constraints: DdConstraints


def _convention_attrs(phases, names) -> dict:
    p1, p2 = phases
    a, b = names
    return {
        "convention_dd": (f"dd = (N_{b}^s_i - N_{a}^s_i) - (N_{b}^s_j - N_{a}^s_j): node i minus "
                          f"node j, node = receiver {b} minus receiver {a}"),
        "convention_wl_integer": f"wl_integer = DD of N_{p1} - N_{p2}",
        "convention_nl_integer": f"nl_integer = DD of N_{p1} (signal-1 integer)",
        "convention_fixed_if_m": ("fixed_if_m = lambda_NL (nl_integer + f2/(f1 - f2) "
                                  "wl_integer): DD of the float IF ambiguities [m]"),
        "float_covariance": ("the two receivers' float covariances taken as independent "
                             "(separate POD runs, no cross terms)"),
    }


def resolve_dd(arc_a: ReceiverArc, arc_b: ReceiverArc, system: str, phases, codes,
               settings: ArSettings, *, names=("A", "B")) -> DdResolution:
    """Resolve the DD ambiguities of one system between two receivers (module docstring).

    Parameters
    ----------
    arc_a, arc_b : ReceiverArc
        Float POD arcs of receivers A (reference) and B.
    system : str
        GNSS letter (only its satellites are used).
    phases, codes : sequence of two str
        Phase and code signals of the ionosphere-free pair (e.g. L1C L2W, C1W C2W).
    settings : ArSettings
        Config ``ambiguity``: ``min_common_s``, ``decision``, WL/NL bounds, ``alpha``,
        ``wl_sigma``, ``wl_candidate_check``, ``nl_method`` (``ils``: LAMBDA with
        ``ils_min_ratio``, ``ils_min_success_rate``), ``nl_max_shift_sigma``,
        ``constraint_sigma_m``; the product guard does not apply (no product).
    names : tuple of two str
        Receiver names (table attributes and messages).

    Returns
    -------
    DdResolution
        ``table``: one row per DD candidate (dim ``dd``) with nodes, passes, float values,
        sigmas, integers, decisions, reasons, independent/constrained flags; attributes with
        the fixing rates in both definitions (graph rank of Jiang et al. 2023 and share of
        the candidates). ``constraints``: the constrained DDs (:class:`DdConstraints`).
    """
    f1, f2 = frequency_hz(system, phases[0]), frequency_hz(system, phases[1])
    hmw, pid = [], []
    for arc in (arc_a, arc_b):
        p = arc.residuals.pass_index
        p = p.sel(sv=[s for s in p.sv.values if str(s).startswith(system)])
        pid.append(p)
        hmw.append(arc_hmw(arc.obs, p, system, phases, codes, arc.antenna))
    nodes = receiver_sd(hmw[0], pid[0], hmw[1], pid[1], arc_a.amb, arc_b.amb, names)
    pairs = sd_pairs(nodes.sv, nodes.start, nodes.end, min_common_s=settings.min_common_s)
    i, j = pairs.i, pairs.j
    n_dd = i.size
    wl = sd_wide_lane(nodes.hmw_cyc, nodes.node_id, i, j, None,
                      sigma_method=wl_sigma_method(settings))
    wl_dec = require_common_data(
        decide(wl.value_cyc, wl.sigma_cyc, settings.wl_max_dev_cyc, settings.wl_max_sigma_cyc,
               settings, dof=wl.dof),
        wl.n_common, nodes.node_id.time.values, settings.min_common_s)
    node_value, node_cov = receiver_sd_float(arc_a.amb, arc_b.amb, nodes)
    n_wl = np.where(wl_dec.fixed, wl_dec.integer, 0).astype(np.int64)
    nl = sd_narrow_lane(node_value, node_cov, i, j, n_wl, f1, f2)

    def decide_nl(value, sigma):
        return decide(value, sigma, settings.nl_max_dev_cyc, settings.nl_max_sigma_cyc, settings)

    nl_dec = decide_nl(nl.value_cyc, nl.sigma_cyc)
    if settings.wl_candidate_check:
        wl_dec, nl_value, nl_dec = wl_candidate_check(
            wl.value_cyc, wl_dec, nl.value_cyc, nl_dec, nl.sigma_cyc, f2 / (f1 - f2), decide_nl)
        nl = nl._replace(value_cyc=nl_value)
        n_wl = np.where(wl_dec.fixed, wl_dec.integer, 0).astype(np.int64)
    if settings.nl_method == "ils":
        nl_dec = ils_nl_decision(
            nl.value_cyc, sd_covariance_m2(node_cov, i, j) / narrow_lane_wavelength_m(f1, f2) ** 2,
            i, j, wl_dec.fixed, min_ratio=settings.ils_min_ratio,
            min_success_rate=settings.ils_min_success_rate)
    shift_ok, shift_reason = float_consistent(nl_dec.fraction_cyc, nl.sigma_cyc,
                                              settings.nl_max_shift_sigma)
    nl_fixed = nl_dec.fixed & wl_dec.fixed & shift_ok
    nl_reason = np.where(wl_dec.fixed, np.where(nl_dec.fixed, shift_reason, nl_dec.reason),
                         "wide lane not fixed")
    independent = independent_edges(i, j, key=nl.sigma_cyc)
    chosen = independent_edges(i[nl_fixed], j[nl_fixed], key=nl.sigma_cyc[nl_fixed])
    constrained = np.zeros(n_dd, bool)
    constrained[np.flatnonzero(nl_fixed)[chosen]] = True
    value_if = fixed_sd_if_m(n_wl, np.where(nl_fixed, nl_dec.integer, 0), f1, f2)
    c = constrained
    constraints = DdConstraints(
        nodes.amb_a[i[c]], nodes.amb_b[i[c]], nodes.amb_a[j[c]], nodes.amb_b[j[c]],
        value_if[c].astype(float), np.full(int(c.sum()), float(settings.constraint_sigma_m)))
    rates = {
        "wl_fixing_rate": fixing_rate(i, j, wl_dec.fixed) if n_dd else np.nan,
        "nl_fixing_rate": fixing_rate(i, j, nl_fixed) if n_dd else np.nan,
        "wl_dd_fixed_share": float(wl_dec.fixed.mean()) if n_dd else np.nan,
        "nl_dd_fixed_share": float(nl_fixed.mean()) if n_dd else np.nan,
    }
    log.info("DD ambiguities %s-%s (%s): %d nodes, %d DDs (%d independent); WL fixed %d, NL "
             "fixed %d; rates WL %.1f %%, NL %.1f %% (graph rank); %d constraints", names[1],
             names[0], system, nodes.sv.size, n_dd, int(independent.sum()),
             int(wl_dec.fixed.sum()), int(nl_fixed.sum()), 100 * rates["wl_fixing_rate"],
             100 * rates["nl_fixing_rate"], int(c.sum()))
    table = _table(nodes, pairs, wl, wl_dec, nl, nl_dec, nl_fixed, nl_reason, independent,
                   constrained, value_if)
    table.attrs.update({
        **rates, "system": system, "receiver_a": names[0], "receiver_b": names[1],
        "n_nodes": int(nodes.sv.size), "n_independent": int(independent.sum()),
        "decision": settings.decision, "min_common_s": settings.min_common_s,
        "wl_sigma": wl_sigma_method(settings), "nl_method": settings.nl_method,
        "wl_candidate_check": int(settings.wl_candidate_check),
        "nl_max_shift_sigma": settings.nl_max_shift_sigma, "ar_product": "none (DD)",
        **_convention_attrs(phases, names)})
    return DdResolution(table=table, constraints=constraints)


def _table(nodes, pairs, wl, wl_dec, nl, nl_dec, nl_fixed, nl_reason, independent,
           constrained, value_if) -> xr.Dataset:
    """The netCDF-ready DD table of :func:`resolve_dd`."""
    i, j = pairs.i, pairs.j
    d = ("dd",)

    def var(values, long_name, units="1"):
        return (d, values, {"units": units, "long_name": long_name})

    return xr.Dataset({
        "node_i": var(i.astype(np.int32), "first receiver single difference"),
        "node_j": var(j.astype(np.int32), "second receiver single difference"),
        "sv_i": var(nodes.sv[i].astype(str), "GNSS satellite of node i"),
        "sv_j": var(nodes.sv[j].astype(str), "GNSS satellite of node j"),
        "pass_a_i": var(nodes.pass_a[i].astype(np.int32), "pass of receiver A in node i"),
        "pass_b_i": var(nodes.pass_b[i].astype(np.int32), "pass of receiver B in node i"),
        "pass_a_j": var(nodes.pass_a[j].astype(np.int32), "pass of receiver A in node j"),
        "pass_b_j": var(nodes.pass_b[j].astype(np.int32), "pass of receiver B in node j"),
        "amb_a_i": var(nodes.amb_a[i].astype(np.int32), "ambiguity of receiver A in node i"),
        "amb_b_i": var(nodes.amb_b[i].astype(np.int32), "ambiguity of receiver B in node i"),
        "amb_a_j": var(nodes.amb_a[j].astype(np.int32), "ambiguity of receiver A in node j"),
        "amb_b_j": var(nodes.amb_b[j].astype(np.int32), "ambiguity of receiver B in node j"),
        "common_start": (d, pairs.common_start, {"long_name": "start of common time"}),
        "common_end": (d, pairs.common_end, {"long_name": "end of common time"}),
        "wl_float_cyc": var(wl.value_cyc, "float DD WL"),
        "wl_sigma_cyc": var(wl.sigma_cyc, "sigma of DD WL"),
        "wl_std_cyc": var(wl.std_cyc, "STD of the DD HMW series"),
        "wl_n_common": var(wl.n_common, "common epochs of the four passes"),
        "wl_n_eff": var(wl.n_common if wl.n_eff is None else wl.n_eff,
                        "effective number of independent HMW epochs"),
        "wl_integer": var(wl_dec.integer.astype(np.int64), "nearest integer DD WL"),
        "wl_fraction_cyc": var(wl_dec.fraction_cyc, "float minus nearest integer"),
        "wl_fixed": var(wl_dec.fixed.astype(np.int8), "WL fixed"),
        "wl_reason": var(np.asarray(wl_dec.reason).astype(str), "why the WL is not fixed"),
        "nl_float_cyc": var(nl.value_cyc, "float DD NL"),
        "nl_sigma_cyc": var(nl.sigma_cyc, "sigma of DD NL"),
        "nl_integer": var(nl_dec.integer.astype(np.int64), "DD NL integer"),
        "nl_fraction_cyc": var(nl_dec.fraction_cyc, "float minus integer"),
        "nl_fixed": var(nl_fixed.astype(np.int8), "NL fixed"),
        "nl_reason": var(np.asarray(nl_reason).astype(str), "why the NL is not fixed"),
        "independent": var(independent.astype(np.int8), "in the maximal independent set"),
        "constrained": var(constrained.astype(np.int8), "constrained in a baseline solution"),
        "fixed_if_m": var(np.where(constrained, value_if, np.nan),
                          "fixed DD ionosphere-free ambiguity", "m"),
    })


def resolve_dd_systems(arc_a: ReceiverArc, arc_b: ReceiverArc, signals, settings: ArSettings,
                       *, names=("A", "B")) -> DdResolution:
    """:func:`resolve_dd` of each system of two combined float arcs, joined.

    DDs are formed only between satellites of one system (its own signal pair and
    wavelengths, :func:`~leopod.ambiguity.pairs.sd_pairs`).

    Parameters
    ----------
    arc_a, arc_b, settings, names
        As for :func:`resolve_dd`.
    signals : mapping of str to leopod.signals.SystemSignals
        Signals (``phase`` and ``pod_code`` pairs) per system letter.

    Returns
    -------
    DdResolution
        Tables concatenated along ``dd`` with a ``system`` variable and node numbers made
        unique across systems; attributes ``<system>_<attribute>`` of each system's table and
        the fixing rates of all systems together.

    Raises
    ------
    ValueError
        If neither receiver tracks any of the systems.
    """
    tables, parts, offset = [], [], 0
    for x, sig in signals.items():
        if not any(str(s).startswith(x) for s in arc_a.residuals.sv.values):
            continue
        res = resolve_dd(arc_a, arc_b, x, sig.phase, sig.pod_code, settings, names=names)
        t = res.table
        for v in ("node_i", "node_j"):
            t[v] = t[v] + np.int32(offset)
        t["system"] = (("dd",), np.full(t.sizes["dd"], x), {"units": "1",
                                                          "long_name": "GNSS of the DD"})
        offset += t.attrs["n_nodes"]
        tables.append(t)
        parts.append(res.constraints)
    if not tables:
        raise ValueError(f"receiver {names[0]} tracks none of the systems {' '.join(signals)}")
    joined = xr.concat([t.drop_attrs(deep=False) for t in tables], dim="dd")
    for t in tables:
        joined.attrs.update({f"{t.attrs['system']}_{k}": v for k, v in t.attrs.items()})
    i, j = joined.node_i.values, joined.node_j.values
    wl, nl = joined.wl_fixed.values == 1, joined.nl_fixed.values == 1
    joined.attrs.update({
        "systems": " ".join(t.attrs["system"] for t in tables),
        "receiver_a": names[0], "receiver_b": names[1],
        "wl_fixing_rate": fixing_rate(i, j, wl) if i.size else np.nan,
        "nl_fixing_rate": fixing_rate(i, j, nl) if i.size else np.nan,
        "wl_dd_fixed_share": float(wl.mean()) if i.size else np.nan,
        "nl_dd_fixed_share": float(nl.mean()) if i.size else np.nan})
    constraints = DdConstraints(*(np.concatenate([c[k] for c in parts]) for k in range(6)))
    return DdResolution(table=joined, constraints=constraints)
