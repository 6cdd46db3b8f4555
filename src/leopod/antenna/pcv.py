"""In-flight receiver PCV of a LEO by the residual method (rule ``pcv``).

The ionosphere-free phase residuals of the (fixed, else float) POD of the days of a period
are stacked on an antenna-frame grid; the value of a node is the mean of the residuals in its
neighbourhood, ± half a step in azimuth and zenith angle around it (Wang et al. 2024, eqs.
12-13, Fig. 6; Jäggi et al. 2009; the Lutan-1 orbits of Zhang et al. 2024 use the same)::

    ΔPCV(α, z) = PCV_true − PCV_used ≈ mean over the cell of (L_IF − Z_IF)

so the pattern to use next is ``PCV_used + ΔPCV``; the POD ↔ map loop (three iterations in
Wang et al. 2024) is a workflow matter: the written ANTEX is read back through
``satellites.<sat>.antenna`` (:mod:`leopod.gnss.leo_antenna`).

Estimator (``estimator``). ``mean``: the cell mean itself, the paper's averaging.
``bilinear``: the node values whose bilinear interpolation fits the residuals in the
least-squares sense (with a weak pull of every node towards zero, :data:`WEAK_SIGMA_M`). The
POD applies an ANTEX grid by bilinear interpolation (Wang et al. 2024, eqs. 7-9), so the
bilinear fit is a Gauss-Newton step of the map the POD uses; iterating cell means instead
drives the map towards node values whose *interpolation* has the cell means, which sharpens
noise and sub-cell roughness from one iteration to the next (benchmarks/pcv.py: map RMS
against the truth 3.66, 3.55, 3.90 mm over three iterations with cell means; 4.74, 4.15, 3.93,
3.88 mm over four with the bilinear fit).

Datum. A constant added to every node is a common range offset of every observation: the
receiver clock absorbs it exactly, and an elevation-dependent part that is linear in cos z
trades with the PCO-Z (the ambiguities absorb what is constant over a pass). The residual
method cannot separate a PCV from clock or PCO-Z without a condition; the one chosen
(``datum``) is removed from the map: ``mean`` - the unweighted mean of the well-observed
nodes is zero; ``zenith`` - the zenith node is zero. The PCO is kept as it was (no PCO-Z is
estimated here), so the map keeps what of the PCO-Z error the orbit and clock did not absorb.

Grid. Nodes of :class:`leopod.codebias.grid.AntennaGrid` (``az_step_deg`` ×
``zenith_step_deg``: rings of constant antenna elevation 0..90° − step and the zenith node),
laid out as ANTEX rows (zenith 0..90°, azimuth 0..360° − step; ANTEX repeats azimuth 0 at
360°). Azimuth is that of the residuals and of ANTEX: from the antenna frame's north (+X,
flight direction, by default) towards east (+Y).

Map Dataset (dims ``azimuth_deg``, ``zenith_deg``)
--------------------------------------------------
``pcv_if_m``
    Estimated correction ΔPCV of the ionosphere-free phase [m], datum removed; NaN where the
    node has fewer than ``min_count`` residuals.
``sigma_m``
    Standard deviation of the mean of the node's residuals [m] (sample std / sqrt(count)),
    or the formal sigma of the bilinear fit (residuals weighted by their pooled scatter).
``residual_std_m``
    Sample standard deviation of the node's residuals [m].
``count``
    Residuals in the node's neighbourhood [1].
attrs: ``estimator``, ``datum``, ``datum_offset_m`` (the constant removed), ``az_step_deg``,
``zenith_step_deg``, ``min_count``, ``n_residuals``, ``n_nodes_estimated``, ``period``,
``satellite``, ``solution``.

References
----------
Wang, Y., Guo, J., Ya, S., Jia, Y., Guo, H., Chang, X., Liu, X. (2024). Impact of
pseudo-stochastic pulse and phase center variation on precision orbit determination of
Haiyang-2A from experimental HY2 receiver GPS data. Remote Sensing 16(8), 1336.
doi:10.3390/rs16081336
Zhang, Y., Zhao, Q., Jiang, K., Guo, X., Li, M. (2024). High-precision inter-satellite baseline
determination method for Lutan-1 based on BDS-3. Geomatics and Information Science of Wuhan
University 49(10), 1763-1769. doi:10.13203/j.whugis20240198
Jäggi, A., Dach, R., Montenbruck, O., Hugentobler, U., Bock, H., Beutler, G. (2009). Phase
center modeling for LEO GPS receiver antennas and its impact on precise orbit determination.
Journal of Geodesy 83, 1145-1162. doi:10.1007/s00190-009-0333-2
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.codebias.grid import AntennaGrid
from leopod.frames.attitude import antenna_frame
from leopod.gnss.leo_antenna import LeoAntenna, antex_frequency
from leopod.io.antex import AntennaPattern
from leopod.settings import Settings

__all__ = ["WEAK_SIGMA_M", "PcvSettings", "apriori_pattern", "estimated_antenna",
           "estimated_pattern", "map_dataset", "pco_shift_neu", "map_differences", "map_rms_m", "stack_maps",
           "stack_residuals"]

log = logging.getLogger(__name__)

#: Antenna type of the estimated ANTEX entry (``satellites.<sat>.antenna.type``).
ESTIMATED_TYPE = "LEOPOD PCV"

_DATUMS = ("mean", "zenith")
_ESTIMATORS = ("mean", "bilinear")
_METHODS = ("residual", "direct")
WEAK_SIGMA_M = 0.05
"""A-priori sigma of a node value in the bilinear fit and the direct method [m]: a weak pull towards no correction
that keeps nodes without residuals determined (far above any PCV)."""


@dataclass(frozen=True)
class PcvSettings(Settings):
    """Residual-method PCV estimation (``pcv`` section of the campaign; module docstring).

    Attributes
    ----------
    az_step_deg, zenith_step_deg : float
        Node spacing [deg] (10 × 10 or 5 × 5 in Wang et al. 2024).
    min_count : int
        Nodes with fewer residuals are not estimated (NaN, no correction) [1].
    datum : {"mean", "zenith"}
        Condition removed from the map (module docstring).
    estimator : {"mean", "bilinear"}
        Node values from the residuals (module docstring).
    method : {"residual", "direct"}
        Residual method (this module) or the node values as parameters of the POD normal
        equations (:mod:`leopod.antenna.pcv_direct`).
    estimate_pco_z : bool
        Direct method: estimate a PCO-Z correction with the map (its datum then removes a
        cos z-like part from the map).
    no_horizontal_offset : bool
        Direct method: the datum also removes the parts like a horizontal offset (nearly
        singular with the orbit, :mod:`leopod.antenna.pcv_direct`).
    """

    SCHEMA_DEF = "pcv"

    az_step_deg: float
    zenith_step_deg: float
    min_count: int
    datum: str
    estimator: str
    method: str
    estimate_pco_z: bool
    no_horizontal_offset: bool

    def __post_init__(self):
        if self.method not in _METHODS:
            raise ValueError(f"pcv.method must be one of {_METHODS}, not {self.method!r}")
        if self.estimate_pco_z and self.method != "direct":
            raise ValueError("pcv.estimate_pco_z needs pcv.method: direct")
        if self.datum not in _DATUMS:
            raise ValueError(f"pcv.datum must be one of {_DATUMS}, not {self.datum!r}")
        if self.estimator not in _ESTIMATORS:
            raise ValueError(f"pcv.estimator must be one of {_ESTIMATORS}, not "
                             f"{self.estimator!r}")
        self.grid        # checks that the steps divide 360° and 90°

    @property
    def grid(self) -> AntennaGrid:
        """The node grid of the map."""
        return AntennaGrid(self.az_step_deg, self.zenith_step_deg)


def _residual_samples(res: xr.Dataset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Used phase residuals [m] with their antenna azimuth and elevation [deg], shape (n,)."""
    r = res.phase_residual_m.values.ravel()
    ok = np.isfinite(r)
    if "phase_rejected" in res:
        ok &= res.phase_rejected.values.ravel() == 0
    return r[ok], res.az_deg.values.ravel()[ok], res.el_deg.values.ravel()[ok]


def _ring_rows(grid: AntennaGrid, node_values: np.ndarray) -> np.ndarray:
    """Node vector (n_nodes,) -> (n_az, n_zen) in ANTEX order (zenith 0..90°)."""
    return grid.to_grid(node_values)[::-1].T


def stack_residuals(residuals: Sequence[xr.Dataset], settings: PcvSettings, *,
                    period: str = "", satellite: str = "", solution: str = "") -> xr.Dataset:
    """ΔPCV map of the stacked phase residuals of a period (module docstring).

    Parameters
    ----------
    residuals : sequence of xarray.Dataset
        Residual Datasets of the POD days (:mod:`leopod.estimation.outputs`):
        ``phase_residual_m``, ``el_deg``, ``az_deg`` (time, sv) and ``phase_rejected``;
        residuals that are NaN or rejected are left out.
    settings : PcvSettings
    period, satellite, solution : str
        Identification written into the attributes.

    Returns
    -------
    xarray.Dataset
        The map Dataset of the module docstring.

    Raises
    ------
    ValueError
        If no node has ``min_count`` residuals, or the zenith datum's node has too few.
    """
    grid = settings.grid
    parts = [_residual_samples(r) for r in residuals]
    r = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0)
    az = np.concatenate([p[1] for p in parts]) if parts else np.zeros(0)
    el = np.concatenate([p[2] for p in parts]) if parts else np.zeros(0)
    node = grid.nearest(az, el)
    use = node >= 0
    node, r = node[use], r[use]

    count = np.bincount(node, minlength=grid.n_nodes)
    total = np.bincount(node, weights=r, minlength=grid.n_nodes)
    mean = np.full(grid.n_nodes, np.nan)
    np.divide(total, count, out=mean, where=count > 0)
    dev2 = np.bincount(node, weights=(r - mean[node]) ** 2, minlength=grid.n_nodes)
    std = np.full(grid.n_nodes, np.nan)
    np.sqrt(dev2 / np.maximum(count - 1, 1), out=std, where=count > 1)
    if settings.estimator == "bilinear":
        mean, sigma = _bilinear_fit(grid, az[use], el[use], r, std, count)
    else:
        sigma = np.where(count > 1, std / np.sqrt(np.maximum(count, 1)), np.nan)
    well = count >= settings.min_count
    if not well.any():
        raise ValueError(f"PCV {satellite} {period}: no node has {settings.min_count} "
                         f"residuals ({r.size} residuals in all)")
    if settings.datum == "zenith":
        if not well[-1]:
            raise ValueError(f"PCV {satellite} {period}: zenith datum, but the zenith node "
                             f"has {count[-1]} residuals (< {settings.min_count})")
        offset = mean[-1]
    else:
        offset = float(np.mean(mean[well]))
    pcv = np.where(well, mean - offset, np.nan)
    log.info("PCV %s %s (%s): %d residuals, %d of %d nodes with >= %d, datum %s (%.2f mm "
             "removed), map RMS %.2f mm", satellite, period, settings.estimator, r.size,
             int(well.sum()), grid.n_nodes, settings.min_count, settings.datum, 1e3 * offset,
             1e3 * float(np.sqrt(np.nanmean(pcv**2))))
    ds = map_dataset(grid, pcv, sigma, std, count)
    ds.attrs.update(estimator=settings.estimator, datum=settings.datum, datum_offset_m=float(offset),
                    az_step_deg=float(settings.az_step_deg),
                    zenith_step_deg=float(settings.zenith_step_deg),
                    min_count=int(settings.min_count), n_residuals=int(r.size),
                    n_nodes_estimated=int(well.sum()), period=period, satellite=satellite,
                    solution=solution, method="residual (Wang et al. 2024, eqs. 12-13)")
    return ds


def map_dataset(grid: AntennaGrid, pcv: np.ndarray, sigma: np.ndarray, std: np.ndarray,
                count: np.ndarray) -> xr.Dataset:
    """The map Dataset (module docstring, without attributes) of node vectors (n_nodes,):
    correction, its sigma, the residual scatter [m] and the counts of the nodes."""
    dims = ("azimuth_deg", "zenith_deg")
    ds = xr.Dataset(
        {"pcv_if_m": (dims, _ring_rows(grid, pcv),
                      {"units": "m", "long_name": "estimated correction of the ionosphere-free "
                       "phase centre variation (datum removed)"}),
         "sigma_m": (dims, _ring_rows(grid, sigma),
                     {"units": "m", "long_name": "standard deviation of the node value"}),
         "residual_std_m": (dims, _ring_rows(grid, std),
                            {"units": "m", "long_name": "standard deviation of the residuals "
                             "of the node"}),
         "count": (dims, _ring_rows(grid, count).astype(np.int64),
                   {"units": "1", "long_name": "phase observations in the node's "
                    "neighbourhood"})},
        coords={"azimuth_deg": grid.azimuth_deg,
                "zenith_deg": 90.0 - grid.elevation_deg[::-1]})
    ds["azimuth_deg"].attrs.update(units="degree", long_name="azimuth in the antenna frame "
                                   "(from north, +X by default, towards east)")
    ds["zenith_deg"].attrs.update(units="degree", long_name="zenith angle in the antenna frame")
    return ds


def _bilinear_fit(grid: AntennaGrid, az, el, r, std, count):
    """Node values (n_nodes,) whose bilinear interpolation fits the residuals ``r`` [m], and
    their formal sigmas [m], the residuals weighted by the pooled scatter of the nodes."""
    a = grid.design(az, el)
    sigma0 = float(np.sqrt(np.nansum(std**2 * np.maximum(count - 1, 0))
                           / max(int(np.sum(np.maximum(count - 1, 0))), 1))) or 1e-3
    n = (a.T @ a).toarray() / sigma0**2 + np.eye(grid.n_nodes) / WEAK_SIGMA_M**2
    values = np.linalg.solve(n, a.T @ r / sigma0**2)
    sigma = np.sqrt(np.diag(np.linalg.inv(n)))
    return values, sigma


def _nodes_once(shape: tuple[int, int]) -> np.ndarray:
    """Mask (n_az, n_zen) that counts the zenith node once (azimuth 0 of zenith 0)."""
    once = np.ones(shape, dtype=bool)
    once[1:, 0] = False
    return once


def _remove_datum(values: np.ndarray, datum: str) -> tuple[np.ndarray, float]:
    """``values`` (n_az, n_zen) minus the datum constant of their finite nodes, and that
    constant: the mean of the nodes (zenith once) or the zenith value."""
    if datum == "zenith":
        offset = float(values[0, 0])
        if not np.isfinite(offset):
            raise ValueError("zenith datum, but the zenith node is not estimated")
    else:
        offset = float(np.nanmean(values[_nodes_once(values.shape)]))
    return values - offset, offset


def stack_maps(maps: Sequence[xr.Dataset], settings: PcvSettings) -> xr.Dataset:
    """Maps of several periods stacked: per node the inverse-variance mean of the periods
    that estimated it, the datum applied again; ``count`` summed.

    Parameters
    ----------
    maps : sequence of xarray.Dataset
        Map Datasets of :func:`stack_residuals` in time order, on one grid, corrections of
        the same a-priori antenna (attribute ``apriori_antenna``, when present).
    settings : PcvSettings
        Its ``datum`` is applied to the stack.

    Returns
    -------
    xarray.Dataset
        A map Dataset (module docstring) with the attributes of the first map,
        ``period`` listing the periods and, for direct-method maps with a PCO-Z, the
        inverse-variance mean ``pco_z_m`` and its ``pco_z_sigma_m``.

    Raises
    ------
    ValueError
        If the maps differ in grid, estimator or a-priori antenna.
    """
    first = maps[0]
    for m in maps[1:]:
        same_grid = (np.array_equal(m.azimuth_deg.values, first.azimuth_deg.values)
                     and np.array_equal(m.zenith_deg.values, first.zenith_deg.values))
        if not same_grid or any(m.attrs.get(k) != first.attrs.get(k)
                                for k in ("estimator", "apriori_antenna")):
            raise ValueError(f"PCV maps of {first.attrs.get('period')} and "
                             f"{m.attrs.get('period')} differ in grid, estimator or a-priori "
                             "antenna: they cannot be stacked")
    value = np.stack([m.pcv_if_m.values for m in maps])
    sigma = np.stack([m.sigma_m.values for m in maps])
    weight = np.zeros(value.shape)
    usable = np.isfinite(value) & np.isfinite(sigma) & (sigma > 0)
    weight[usable] = sigma[usable] ** -2.0
    total = weight.sum(axis=0)
    have = total > 0
    mean = np.full(total.shape, np.nan)
    mean[have] = (weight * np.nan_to_num(value)).sum(axis=0)[have] / total[have]
    mean, offset = _remove_datum(mean, settings.datum)
    out = first.copy()
    out["pcv_if_m"] = (first.pcv_if_m.dims, mean, first.pcv_if_m.attrs)
    out["sigma_m"] = (first.sigma_m.dims, np.where(have, 1.0 / np.sqrt(np.where(have, total,
                                                                                  1.0)),
                                                   np.nan), first.sigma_m.attrs)
    out["count"] = sum(m["count"] for m in maps)
    out["count"].attrs.update(first["count"].attrs)
    out["residual_std_m"] = (first.residual_std_m.dims,
                             np.sqrt(np.nanmean(np.stack([m.residual_std_m.values**2
                                                          for m in maps]), axis=0)),
                             {"units": "m", "long_name": "root mean square over the periods "
                              "of the standard deviation of the node's residuals"})
    pco = np.array([float(m.attrs.get("pco_z_m", np.nan)) for m in maps])
    if np.isfinite(pco).all():      # direct-method PCO-Z: inverse-variance mean
        w = np.array([float(m.attrs["pco_z_sigma_m"]) for m in maps]) ** -2.0
        out.attrs.update(pco_z_m=float(np.sum(w * pco) / w.sum()),
                         pco_z_sigma_m=float(w.sum() ** -0.5))
    out.attrs.update(period=" ".join(str(m.attrs.get("period", "?")) for m in maps),
                     datum=settings.datum, datum_offset_m=offset,
                     n_residuals=int(sum(int(m.attrs.get("n_residuals", 0)) for m in maps)),
                     n_nodes_estimated=int(np.sum(have & _nodes_once(have.shape))))
    return out


def map_differences(maps: Sequence[xr.Dataset]) -> list[tuple[str, str, float, int]]:
    """RMS of the differences of consecutive period maps over their common estimated nodes
    (zenith once), the mean difference removed: ``(period_a, period_b, rms_m, n_nodes)``."""
    out = []
    for a, b in zip(maps[:-1], maps[1:]):
        d = b.pcv_if_m.values - a.pcv_if_m.values
        common = np.isfinite(d) & _nodes_once(d.shape)
        rms = float(np.std(d[common])) if common.any() else float("nan")
        out.append((str(a.attrs.get("period", "?")), str(b.attrs.get("period", "?")), rms,
                    int(common.sum())))
    return out


def apriori_pattern(antenna) -> tuple[AntennaPattern, LeoAntenna | None]:
    """The receiver pattern a POD used, and the :class:`LeoAntenna` if it was one.

    A plain PCO table (band -> body-frame offset [m], ``antenna_pco_body_m``) becomes a
    pattern without PCV in the default antenna frame (north +X, up −Z) with the ARP at the
    centre of mass, so that ``ARP + Fᵀ PCO_neu`` is the same phase centre.
    """
    if isinstance(antenna, LeoAntenna):
        return antenna.pattern, antenna
    if not isinstance(antenna, Mapping) or not antenna:
        raise ValueError("the POD's antenna is neither an ANTEX antenna nor a PCO table "
                         "(satellites.<sat>.antenna_pco_body_m): no frequency to write")
    frame = antenna_frame((1.0, 0.0, 0.0), (0.0, 0.0, -1.0))
    pco = {antex_frequency(b): frame @ np.asarray(v, dtype=float) for b, v in antenna.items()}
    zen = np.array([0.0, 90.0])
    pattern = AntennaPattern(
        kind="receiver", antenna_type="PCO TABLE", serial="", svn="", cospar_id="",
        valid_from=np.datetime64("NaT", "ns"), valid_until=np.datetime64("NaT", "ns"),
        zenith_deg=zen, dazi_deg=0.0, frequencies=tuple(pco), pco=pco,
        noazi={f: np.zeros(2) for f in pco}, grid={}, meta={})
    return pattern, None


def pco_shift_neu(antenna, pcv_map: xr.Dataset) -> np.ndarray:
    """The estimated PCO-Z correction of a map (attribute ``pco_z_m``, along body +Z) in the
    antenna frame of the POD's antenna (north, east, up) [m], shape (3,); zeros without one."""
    dz = float(pcv_map.attrs.get("pco_z_m", np.nan))
    if not np.isfinite(dz):
        return np.zeros(3)
    frame = (antenna.frame if isinstance(antenna, LeoAntenna)
             else antenna_frame((1.0, 0.0, 0.0), (0.0, 0.0, -1.0)))
    return np.asarray(frame, dtype=float) @ np.array([0.0, 0.0, dz])


def estimated_pattern(apriori: AntennaPattern, pcv_map: xr.Dataset, *,
                      antenna_type: str = ESTIMATED_TYPE, serial: str = "",
                      pco_shift_neu_m=(0.0, 0.0, 0.0)) -> AntennaPattern:
    """The a-priori pattern with the estimated correction: ``PCV_f + ΔPCV`` on the map's grid.

    The ionosphere-free correction is added to every frequency, so the ionosphere-free PCV
    of any pair gains exactly ΔPCV and the Melbourne-Wübbena combination none (as the
    ionosphere-free values filled in for both frequencies of GOCE, Jäggi et al. 2009). Nodes
    without an estimate keep the a-priori value; the PCOs are kept, plus
    ``pco_shift_neu_m`` (north, east, up [m], every frequency: :func:`pco_shift_neu`).
    ``NOAZI`` is the azimuth mean of each zenith row.
    """
    zen = pcv_map.zenith_deg.values
    az = np.r_[pcv_map.azimuth_deg.values, 360.0]
    delta = np.nan_to_num(pcv_map.pcv_if_m.values)
    delta = np.concatenate([delta, delta[:1]])                   # 360° = 0°
    zz, aa = np.meshgrid(zen, az)
    grid = {}
    for f in apriori.frequencies:
        before = apriori.pcv_m(f, zz, aa, outside="nearest")
        grid[f] = before + delta
    return AntennaPattern(
        kind="receiver", antenna_type=antenna_type, serial=serial, svn="", cospar_id="",
        valid_from=np.datetime64("NaT", "ns"), valid_until=np.datetime64("NaT", "ns"),
        zenith_deg=zen.astype(float), dazi_deg=float(pcv_map.attrs["az_step_deg"]),
        frequencies=tuple(apriori.frequencies),
        pco={f: apriori.pco_m(f) + np.asarray(pco_shift_neu_m, dtype=float)
             for f in apriori.frequencies},
        noazi={f: grid[f][:-1].mean(axis=0) for f in apriori.frequencies}, grid=grid,
        meta={"calibration_method": ("DIRECT" if pcv_map.attrs.get("estimator") == "direct"
                                     else "RESIDUAL"), "calibrated_by": "LEOPOD"})


def estimated_antenna(antenna, pcv_map: xr.Dataset) -> LeoAntenna:
    """The POD's antenna (a :class:`LeoAntenna` or a PCO table) with the estimated map, in the
    same antenna frame and ARP (those of :func:`apriori_pattern` for a table)."""
    pattern, leo = apriori_pattern(antenna)
    new = estimated_pattern(pattern, pcv_map, pco_shift_neu_m=pco_shift_neu(antenna, pcv_map))
    if leo is None:
        return LeoAntenna(new, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0),
                          source=f"estimated {ESTIMATED_TYPE}")
    return LeoAntenna(new, leo.arp_body_m, leo.frame[0], leo.frame[2],
                      source=f"estimated {ESTIMATED_TYPE} (a priori {leo.source})")


def map_rms_m(estimate: xr.Dataset, truth_if_m: np.ndarray, *, min_count: int,
              pco_z: bool = False, horizontal: bool = False) -> float:
    """RMS of estimate minus truth over the nodes with ``count >= min_count`` [m], the mean
    over those nodes removed from both (the datum, module docstring).

    Parameters
    ----------
    estimate : xarray.Dataset
        Map Dataset (``pcv_if_m``, ``count``), shape (n_az, n_zen).
    truth_if_m : ndarray, shape (n_az, n_zen)
        True ionosphere-free PCV minus the PCV used, at the same nodes [m].
    pco_z : bool
        Also remove the least-squares ``b cos z`` of the difference: what a PCO-Z error of
        ``-b`` gives a PCV (range change ``-ΔPCO_U cos z``), inseparable from it without a
        PCO datum.
    horizontal : bool
        Also remove the least-squares ``cos e cos α`` and ``cos e sin α`` (a horizontal
        offset, nearly inseparable from the orbit: :mod:`leopod.antenna.pcv_direct`).
    """
    well = ((estimate["count"].values >= min_count) & np.isfinite(estimate.pcv_if_m.values)
            & _nodes_once(estimate.pcv_if_m.shape))
    d = estimate.pcv_if_m.values[well] - truth_if_m[well]
    zen = np.radians(np.broadcast_to(estimate.zenith_deg.values, well.shape)[well])
    az = np.radians(np.broadcast_to(estimate.azimuth_deg.values[:, None], well.shape)[well])
    terms = [np.ones_like(d)] + ([np.cos(zen)] if pco_z else []) + (
        [np.sin(zen) * np.cos(az), np.sin(zen) * np.sin(az)] if horizontal else [])
    basis = np.stack(terms, axis=1)
    d = d - basis @ np.linalg.lstsq(basis, d, rcond=None)[0]
    return float(np.sqrt(np.mean(d**2)))
