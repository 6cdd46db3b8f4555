"""One float POD arc from the ingest/quality outputs of its days: the float_pod rule's logic.

Steps: arc limits from the day and the campaign's ``pod`` settings; ionosphere-free
observations (:mod:`leopod.estimation.inputs`); GNSS products of the arc's days merged;
force model of the estimator; a dynamic fit to the a-priori (code-only or SP3) positions
gives the initial state (or an earlier solution of the arc is continued: the fixed POD);
:func:`leopod.estimation.float_pod.float_pod`; output datasets
(:mod:`leopod.estimation.outputs`).
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.codebias.apply import correct_codes
from leopod.dynamics.force_config import build_force_model
from leopod.dynamics.model_files import resolve_model_paths
from leopod.dynamics.orbit_fit import fit_orbit
from leopod.estimation.float_pod import PodObservations, PodResult, PodSettings, float_pod
from leopod.estimation.inputs import pod_observations, receiver_pco_if, satellite_antenna
from leopod.estimation.outputs import (
    ambiguity_dataset,
    orbit_dataset,
    output_epochs,
    parameter_dataset,
    pod_start,
    residual_dataset,
)
from leopod.gnss.products import GnssProducts
from leopod.time.calendar import parse_date_id, seconds_since

__all__ = ["ArcOutputs", "arc_limits", "pod_settings", "run_arc"]

log = logging.getLogger(__name__)

def pod_settings(pod_cfg: dict) -> PodSettings:
    """PodSettings from the campaign's ``pod`` section (its keys that are PodSettings fields)."""
    names = {f.name for f in dataclasses.fields(PodSettings)}
    return PodSettings(**{k: (tuple(v) if isinstance(v, list) else v)
                          for k, v in pod_cfg.items() if k in names})


@dataclass(eq=False)
class ArcOutputs:
    """Result of :func:`run_arc` and its datasets (schemas in leopod.estimation.outputs)."""

    result: PodResult
    observations: PodObservations
    orbit: xr.Dataset
    residuals: xr.Dataset
    parameters: xr.Dataset
    ambiguities: xr.Dataset


def arc_limits(date: str, arc_before_s: float, arc_after_s: float):
    """Nominal arc ``[00:00 − before, 24:00 + after]`` of a day (GPS time, datetime64[ns])."""
    day = np.datetime64(parse_date_id(date), "ns")
    one_day = np.timedelta64(86400, "s")
    return (day - np.timedelta64(round(arc_before_s * 1e9), "ns"),
            day + one_day + np.timedelta64(round(arc_after_s * 1e9), "ns"))


def run_arc(date: str, obs_days, quality_days, leo_days, orbit: xr.Dataset,
            clock: xr.Dataset, antex, signal_cfg: dict, pod_cfg: dict,
            pco_body_m: dict | None, *, eop=None, limits=None, code_maps=None,
            code_bias_cfg: dict | None = None, yaw_flips=None,
            ambiguity_constraints=None, apriori_orbit: xr.DataArray | None = None,
            continue_from: tuple[xr.Dataset, xr.Dataset, xr.Dataset] | None = None
            ) -> ArcOutputs:
    """Float POD of the arc of ``date`` (module docstring).

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    obs_days, quality_days, leo_days : list of xarray.Dataset
        Ingest/quality outputs of the arc's days in time order (the day and neighbours).
    orbit, clock : xarray.Dataset
        GNSS orbits (SP3) and clocks (RINEX clock) covering the arc (:func:`merge_days`).
    antex : leopod.io.antex.AntexFile or None
        GNSS satellite antenna model.
    signal_cfg : dict
        Campaign ``signals``.
    pod_cfg : dict
        Campaign ``pod`` section (schema defaults applied).
    pco_body_m : dict or None
        LEO antenna PCO per band in the body frame [m].
    eop : EarthOrientation, optional
    limits : (datetime64, datetime64), optional
        Arc start and end instead of those of the ``pod`` settings (e.g. sub-arcs).
    code_maps : xarray.Dataset, optional
        Code-bias maps (:mod:`leopod.codebias`) subtracted from the codes listed in
        ``code_bias_cfg["apply"]`` (policy ``code_bias_cfg["empty_cells"]``) on every day.
    code_bias_cfg : dict, optional
        Campaign ``code_bias`` section.
    yaw_flips : sequence of datetime-like, optional
        Yaw-flip epochs selecting the maps' attitude mode.
    ambiguity_constraints : tuple, optional
        Fixed single-difference ambiguities ``(pass_i, pass_j, value_m, sigma_m)``
        (:func:`leopod.ambiguity.resolve.resolve_arc`): the ambiguity-fixed solution.
    apriori_orbit : xarray.DataArray (time, xyz), optional
        ITRF positions [m] replacing the ingest a-priori orbit as the start of the dynamic
        fit and the reference of ``apriori_diff_rtn_m`` (the fixed POD reports fixed minus
        float this way).
    continue_from : (parameters, ambiguities, residuals), optional
        Datasets of an earlier solution of the arc to continue from
        (:func:`leopod.estimation.outputs.pod_start`; no dynamic fit): the fixed POD
        continues from the float one.

    Returns
    -------
    ArcOutputs
    """
    system = pod_cfg.get("system", "G")
    sig = signal_cfg[system]
    start, end = (arc_limits(date, pod_cfg["arc_before_s"], pod_cfg["arc_after_s"])
                  if limits is None else (np.datetime64(limits[0], "ns"),
                                          np.datetime64(limits[1], "ns")))
    sampling = float(pod_cfg["sampling_s"])
    if code_maps is not None and code_bias_cfg and code_bias_cfg.get("apply"):
        obs_days = [correct_codes(obs, qual, code_maps, code_bias_cfg["apply"],
                                  empty_cells=code_bias_cfg.get("empty_cells", "drop"),
                                  yaw_flips=yaw_flips)[0]
                    for obs, qual in zip(obs_days, quality_days, strict=True)]
    po = pod_observations(obs_days, quality_days, leo_days, sig, system, start,
                          end - np.timedelta64(1, "ns"), sampling)
    t_ref = po.times[0]
    products = GnssProducts.from_datasets(orbit, clock, t_ref, systems=[system],
                                          max_extrapolation_s=0.0)
    sat_pco, sat_pcv = None, None
    if antex is not None:
        sat_pco, sat_pcv = satellite_antenna(antex, po.sv, t_ref, system, sig)
        missing = ~np.isfinite(sat_pco).all(axis=1)
        if missing.any():
            log.warning("no ANTEX entry for %s: their observations are not used",
                        " ".join(po.sv[missing]))
            drop = missing[po.sat]
            po.code_m[drop] = np.nan
            po.phase_m[drop] = np.nan
            po.pass_index[drop] = -1
        sat_pco = np.nan_to_num(sat_pco)
    leo_pco = receiver_pco_if(pco_body_m, system, sig)
    t_s = seconds_since(po.times, t_ref)
    forces = resolve_model_paths(pod_cfg["forces"])
    force_model = build_force_model(forces, t_ref, t_s[0], t_s[-1], eop=eop)
    if apriori_orbit is None:
        apriori = xr.concat([leo.pos_m for leo in leo_days], dim="time")
        _, first = np.unique(apriori.time.values, return_index=True)
        apriori = apriori.isel(time=np.sort(first))
    else:
        apriori = apriori_orbit
    settings = pod_settings(pod_cfg)
    if continue_from is None:
        fit = fit_orbit(po.times, apriori.reindex(time=po.times).values,
                        force_model=force_model, t_ref=t_ref,
                        sigma_obs_m=float(pod_cfg.get("apriori_fit_sigma_m", 1.0)), eop=eop)
        log.info("initial dynamic fit to the a-priori orbit: RMS R %.2f T %.2f N %.2f m",
                 *fit.rms_rtn_m)
        state0, warm = fit.state0_gcrf, None
    else:
        state0, warm = None, pod_start(*continue_from, po)
        log.info("continuing from the earlier solution of the arc (warm start)")
    result = float_pod(po, products, force_model, t_ref, state0, settings, eop=eop,
                       leo_pco_body_m=leo_pco, sat_pco_body_m=sat_pco, sat_pcv_m=sat_pcv,
                       ambiguity_constraints=ambiguity_constraints, start=warm)
    out_times = output_epochs(po.times[0], po.times[-1], float(pod_cfg["output_step_s"]))
    orbit_ds = orbit_dataset(result, out_times, eop=eop,
                             apriori_itrf_m=apriori.reindex(time=out_times).values)
    return ArcOutputs(result=result, observations=po, orbit=orbit_ds,
                      residuals=residual_dataset(result, po),
                      parameters=parameter_dataset(result),
                      ambiguities=ambiguity_dataset(result, po))
