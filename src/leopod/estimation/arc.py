"""One float POD arc from the ingest/quality outputs of its days: the float_pod rule's logic.

Steps (:func:`setup_arc`): arc limits from the day and the :class:`ArcSettings`;
ionosphere-free observations (:mod:`leopod.estimation.inputs`); GNSS products of the arc's
days merged; force model of the estimator. Then (:func:`run_arc`) a dynamic fit to the
a-priori (code-only or SP3) positions gives the initial state;
:func:`leopod.estimation.float_pod.float_pod`; output datasets (:func:`arc_outputs`,
:mod:`leopod.estimation.outputs`). The fixed POD (:mod:`leopod.estimation.fixed_arc`) sets
the arc up the same way.

The initial fit only starts the float POD from metre-level (code-only) positions, so it
uses a cheap force model (:func:`leopod.dynamics.orbit_fit.starting_forces`: the gravity
field to ``apriori_fit_degree``, one drag and one SRP scale factor, no empirical
accelerations) and the longer step that this degree allows
(:func:`~leopod.dynamics.orbit_fit.starting_step_s`); the float POD's first iteration takes
the orbit to the full model.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from leopod.codebias.apply import CodeCorrection, correct_codes
from leopod.codebias.scb import correct_bds2_scb
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.force_config import ForceModelSettings, arc_environment, build_force_model
from leopod.dynamics.forces import ForceModel, tabulated_orbit
from leopod.dynamics.orbit_fit import FitResult, fit_orbit, starting_forces, starting_step_s
from leopod.estimation.float_pod import PodObservations, PodResult, PodSettings, float_pod
from leopod.estimation.inputs import (
    as_system_signals,
    pod_observations,
    receiver_antenna,
    receiver_pco_if,
    satellite_antennas,
)
from leopod.estimation.outputs import (
    ambiguity_dataset,
    orbit_dataset,
    output_epochs,
    parameter_dataset,
    residual_dataset,
)
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.leo_attitude import LeoAttitude
from leopod.gnss.attitude import satellite_families
from leopod.gnss.products import GnssProducts
from leopod.gnss.signal_bias import SignalBiases, correct_signal_biases, read_signal_biases
from leopod.io.manoeuvre import Manoeuvre, read_manoeuvres
from leopod.io.netcdf import load_netcdf, merge_days
from leopod.io.product_netcdf import read_antenna_product, read_clock_product, read_orbit_product
from leopod.settings import Settings
from leopod.signals import SystemSignals
from leopod.time.calendar import parse_date_id, seconds_since

__all__ = ["ArcData", "ArcOutputs", "ArcProblem", "ArcSettings", "arc_limits",
           "arc_output_epochs", "arc_outputs", "run_arc", "setup_arc"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ArcSettings(Settings):
    """How the arc of a day is cut, sampled and started (config ``pod``).

    Attributes
    ----------
    system : str or tuple of str
        GNSS of the POD (RINEX letter), or letters of a combined POD (the first is the
        reference of the inter-system biases).
    sampling_s : float
        Observation sampling [s].
    arc_before_s, arc_after_s : float
        Arc start before 00:00 and end after 24:00 of the day [s].
    output_step_s : float
        Step of the written orbit [s].
    output_margin_s : float
        The written orbit holds the epochs of its step inside the arc that are at most this
        before the first or after the last observation [s] (:func:`arc_output_epochs`).
    apriori_fit_sigma_m : float
        Sigma of the a-priori positions in the initial dynamic fit [m].
    apriori_fit_degree : int
        Degree of the gravity field in the initial dynamic fit.
    gnss_attitude : str
        ``eclipse_models``: GNSS satellite PCO/PCV and wind-up with the published yaw laws of
        each block (ANTEX block type, :mod:`leopod.gnss.attitude`); ``nominal``: yaw steering.
    """

    SCHEMA_DEF = "pod"

    system: str | tuple[str, ...]
    sampling_s: float
    arc_before_s: float
    arc_after_s: float
    output_step_s: float
    output_margin_s: float
    apriori_fit_sigma_m: float
    apriori_fit_degree: int
    gnss_attitude: str

    @property
    def systems(self) -> tuple[str, ...]:
        """The systems of the POD, reference first."""
        return (self.system,) if isinstance(self.system, str) else tuple(self.system)

    def limits(self, date: str) -> tuple[np.datetime64, np.datetime64]:
        """Arc start and end of the day ``date`` (:func:`arc_limits`)."""
        return arc_limits(date, self.arc_before_s, self.arc_after_s)


@dataclass(eq=False)
class ArcData:
    """Inputs of one arc, read: ingest/quality outputs of its days and the GNSS products.

    Attributes
    ----------
    obs, quality, leo : list of xarray.Dataset
        Ingest observations, quality outputs and a-priori orbits of the arc's days in time
        order (the day and its neighbours). :meth:`read` opens the quality files lazily:
        the POD uses 3 or 4 of their ~50 variables, read on first use.
    orbit, clock : xarray.Dataset
        GNSS orbits and clocks covering the arc (schemas of :func:`leopod.io.sp3.read_sp3`
        and :func:`leopod.io.clock.read_rinex_clock`).
    antex : leopod.io.antex.AntexFile or None
        GNSS satellite antenna model (the whole ANTEX file, or the satellite entries kept by
        the gnss_products rule: :func:`leopod.io.product_netcdf.read_antenna_product`).
    code_maps : xarray.Dataset or None
        Code-bias maps (:mod:`leopod.codebias`).
    signal_biases : leopod.gnss.signal_bias.SignalBiases or None
        Bias products (OSB, DCB) of the arc's days, removed from every code (and phase, in
        ``absolute`` mode) before the POD (None: nothing removed).
    files : list of str
        The files read (provenance).
    manoeuvres : tuple of Manoeuvre
        Burns of the satellite (:func:`leopod.io.manoeuvre.read_manoeuvres`), modelled by the
        force model's ``manoeuvre`` section.
    """

    obs: list[xr.Dataset]
    quality: list[xr.Dataset]
    leo: list[xr.Dataset]
    orbit: xr.Dataset
    clock: xr.Dataset
    antex: object = None
    code_maps: xr.Dataset | None = None
    files: list[str] = field(default_factory=list)
    signal_biases: SignalBiases | None = None
    manoeuvres: tuple[Manoeuvre, ...] = ()

    @property
    def coordinate_system(self) -> str:
        """The reference frame of the GNSS orbits (their SP3 header's coordinate system, e.g.
        ``IGS05``, ``IGS14``, ``IGS20``), which the LEO orbit inherits; ``ITRF`` if the
        header leaves it blank."""
        return str(self.orbit.attrs.get("coordinate_system") or "ITRF")

    @classmethod
    def read(cls, files: Mapping, signal_bias: Mapping | None = None,
             sampling_s: float | None = None) -> ArcData:
        """Read the files of an arc: ``obs``, ``quality``, ``leo`` (daily netCDF), ``orbit``
        and ``clock`` (daily GNSS products) lists of paths, optional ``antenna`` (satellite
        antennas) and ``code_bias`` (maps) paths, optional ``signal_bias_osb`` and
        ``signal_bias_dcb`` lists described by ``signal_bias``
        (:func:`leopod.gnss.signal_bias.read_signal_biases`), an optional ``manoeuvres`` file
        (:mod:`leopod.io.manoeuvre`); other keys are ignored.

        The products are the netCDF files of the gnss_products rule, parsed once per day
        (``.nc``), or the SP3, RINEX clock and ANTEX files themselves
        (:mod:`leopod.io.product_netcdf`). A damaged netCDF file (e.g. of an earlier run) is
        refused with a :class:`leopod.io.FormatError` naming it
        (:func:`leopod.io.netcdf.load_netcdf`). With ``sampling_s`` [s] (the POD sampling,
        ``ArcSettings.sampling_s``) only the epochs on its grid are read from the daily
        observation and quality files - those the POD uses
        (:func:`leopod.estimation.inputs.pod_observations`) - so that 1-s data costs the memory
        of the POD's sampling (the a-priori orbit, a few variables, is read whole: it is also
        the reference at the output epochs); None reads every epoch.
        """
        obs, quality, leo = files["obs"], files["quality"], files["leo"]
        orbit, clock = files["orbit"], files["clock"]
        antenna, code_bias = files.get("antenna"), files.get("code_bias")
        manoeuvres = files.get("manoeuvres")
        return cls(obs=[load_netcdf(p, "ingest observation", step_s=sampling_s) for p in obs],
                   quality=[load_netcdf(p, "quality", lazy=True, step_s=sampling_s)
                            for p in quality],
                   leo=[load_netcdf(p, "a-priori orbit") for p in leo],
                   orbit=merge_days([read_orbit_product(p) for p in orbit]),
                   clock=merge_days([read_clock_product(p) for p in clock]),
                   antex=read_antenna_product(antenna) if antenna else None,
                   code_maps=load_netcdf(code_bias, "code-bias map") if code_bias else None,
                   files=[*map(str, obs), *map(str, quality), *map(str, leo), *map(str, orbit),
                          *map(str, clock), *([str(antenna)] if antenna else []),
                          *([str(manoeuvres)] if manoeuvres else [])],
                   signal_biases=read_signal_biases(files, signal_bias),
                   manoeuvres=read_manoeuvres(manoeuvres)[0] if manoeuvres else ())


@dataclass(eq=False)
class ArcOutputs:
    """Result of :func:`run_arc` and its datasets (schemas in leopod.estimation.outputs).

    ``fit`` is the initial dynamic fit (None for a solution continued from another).
    """

    result: PodResult
    observations: PodObservations
    orbit: xr.Dataset
    residuals: xr.Dataset
    parameters: xr.Dataset
    ambiguities: xr.Dataset
    fit: FitResult | None = None


@dataclass(eq=False)
class ArcProblem:
    """An arc set up for its POD (:func:`setup_arc`).

    Attributes
    ----------
    observations : PodObservations
    t_ref : datetime64
        First epoch of the observations: time origin of the force model.
    products : GnssProducts
        GNSS orbits and clocks of the POD's system.
    force_model : ForceModel
        The estimator's force model over the arc.
    antennas : dict
        ``leo_pco_body_m``, ``sat_pco_body_m``, ``sat_pcv_m``, ``leo_attitude``,
        ``leo_antenna`` keywords of :func:`leopod.estimation.float_pod.float_pod`.
    apriori_itrf_m : xarray.DataArray (time, xyz)
        A-priori ITRF positions [m]: the start of the initial fit and the reference of
        ``apriori_diff_rtn_m``.
    output_times : ndarray of datetime64[ns], shape (o,)
        Epochs of the orbit datasets (:func:`arc_output_epochs`); the integrations cover them.
    eop : EarthOrientation or None
    environment : ArcEnvironment
        The grids of ``force_model``, shared by other force models of the arc.
    """

    observations: PodObservations
    t_ref: np.datetime64
    products: GnssProducts
    force_model: ForceModel
    antennas: dict
    apriori_itrf_m: xr.DataArray
    output_times: np.ndarray
    eop: object = None
    environment: ArcEnvironment | None = None

    @property
    def output_span_s(self) -> tuple[float, float]:
        """First and last output epoch [s since ``t_ref``]."""
        t = seconds_since(self.output_times[[0, -1]], self.t_ref)
        return float(t[0]), float(t[1])


def arc_limits(date: str, arc_before_s: float, arc_after_s: float):
    """Nominal arc ``[00:00 − before, 24:00 + after]`` of a day (GPS time, datetime64[ns])."""
    day = np.datetime64(parse_date_id(date), "ns")
    one_day = np.timedelta64(86400, "s")
    return (day - np.timedelta64(round(arc_before_s * 1e9), "ns"),
            day + one_day + np.timedelta64(round(arc_after_s * 1e9), "ns"))


def arc_output_epochs(obs_times: np.ndarray, start, end, step_s: float,
                      margin_s: float) -> np.ndarray:
    """Epochs of an arc's written orbit: those of the ``step_s`` grid of the day in the arc
    ``[start, end)`` and no more than ``margin_s`` before the first or after the last
    observation epoch (datetime64[ns]).

    With the default margin a daily file covers its day from 00:00:00 to the last epoch
    before 24:00 although the data of a day often start and end some seconds inside it
    (GRACE-A 2007-080: first POD epoch 00:00:30, last 23:59:30); the dynamic orbit there is
    integrated beyond the data, and its formal sigmas say how well it is known.

    Parameters
    ----------
    obs_times : ndarray of datetime64, shape (m,)
        Epochs of the arc's observations (sorted).
    start, end : datetime64
        The arc (:func:`arc_limits`); ``end`` is not included.
    step_s : float
        Output step [s].
    margin_s : float
        Largest extension beyond the observations [s].
    """
    margin = np.timedelta64(round(margin_s * 1e9), "ns")
    lo = max(np.datetime64(start, "ns"), np.datetime64(obs_times[0], "ns") - margin)
    hi = min(np.datetime64(end, "ns") - np.timedelta64(1, "ns"),
             np.datetime64(obs_times[-1], "ns") + margin)
    return output_epochs(lo, hi, step_s)


def setup_arc(date: str, data: ArcData, signals: SystemSignals, arc: ArcSettings,
              forces: ForceModelSettings, pco_body_m: Mapping | None, *,
              code_correction: CodeCorrection | None = None, yaw_flips=None, eop=None,
              limits=None, apriori_orbit: xr.DataArray | None = None,
              attitude: LeoAttitude | None = None) -> ArcProblem:
    """Observations, GNSS products, antennas and force model of the arc of ``date``.

    Parameters
    ----------
    date : str
        Day ``YYYY-DDD``.
    data : ArcData
        The arc's observations and GNSS products.
    signals : SystemSignals or mapping of str to SystemSignals
        Signals of the POD's system (``arc.system``), or of each of its systems.
    arc : ArcSettings
    forces : ForceModelSettings
        The estimator's force model, model files resolved to paths
        (:func:`leopod.dynamics.model_files.resolve_model_paths`).
    pco_body_m : mapping or LeoAntenna or None
        LEO antenna PCO per band name in the body frame [m]; a
        :class:`leopod.gnss.leo_antenna.LeoAntenna` (ANTEX) adds its antenna frame and
        ionosphere-free PCV to the observation model.
    code_correction : CodeCorrection, optional
        Codes corrected with ``data.code_maps`` on every day (none if its ``apply`` is empty
        or there are no maps), and the BDS-2 SCB correction with the nadir angles of
        ``data.quality`` if its ``bds2_scb`` is set.
    yaw_flips : sequence of datetime-like, optional
        Yaw-flip epochs selecting the maps' attitude mode.
    eop : EarthOrientation, optional
    limits : (datetime64, datetime64), optional
        Arc start and end instead of those of ``arc`` (e.g. sub-arcs).
    apriori_orbit : xarray.DataArray (time, xyz), optional
        ITRF positions [m] replacing the ingest a-priori orbit (the fixed POD refers to the
        float orbit this way).
    attitude : LeoAttitude, optional
        Attitude law of the LEO (``satellites.<sat>``); None: nominal.

    Returns
    -------
    ArcProblem
    """
    systems = arc.systems
    by_system = as_system_signals(signals, systems)
    observed = list(dict.fromkeys(o for sig in by_system.values() for o in sig.observations))
    start, end = (arc.limits(date) if limits is None
                  else (np.datetime64(limits[0], "ns"), np.datetime64(limits[1], "ns")))
    # satellite code (and phase) biases of each hour's own day (leopod.gnss.signal_bias)
    obs_days = [correct_signal_biases(obs, data.signal_biases, observed)[0]
                for obs in data.obs]
    if code_correction is not None and code_correction.bds2_scb:
        obs_days = [correct_bds2_scb(obs, qual)[0]
                    for obs, qual in zip(obs_days, data.quality, strict=True)]
    if data.code_maps is not None and code_correction is not None and code_correction.apply:
        obs_days = [correct_codes(obs, qual, data.code_maps, code_correction.apply,
                                  empty_cells=code_correction.empty_cells,
                                  yaw_flips=yaw_flips)[0]
                    for obs, qual in zip(obs_days, data.quality, strict=True)]
    po = pod_observations(obs_days, data.quality, data.leo, by_system, systems, start,
                          end - np.timedelta64(1, "ns"), float(arc.sampling_s))
    t_ref = po.times[0]
    products = GnssProducts.from_datasets(data.orbit, data.clock, t_ref, systems=list(systems),
                                          max_extrapolation_s=0.0)
    if arc.gnss_attitude == "eclipse_models" and data.antex is not None:
        products.attitude = satellite_families(data.antex, products.sv, t_ref)
    sat_pco, sat_pcv = None, None
    if data.antex is not None:
        sat_pco, sat_pcv = satellite_antennas(data.antex, po.sv, t_ref, by_system)
        missing = ~np.isfinite(sat_pco).all(axis=1)
        if missing.any():
            log.warning("no ANTEX entry for %s: their observations are not used",
                        " ".join(po.sv[missing]))
            drop = missing[po.sat]
            po.code_m[drop] = np.nan
            po.phase_m[drop] = np.nan
            po.pass_index[drop] = -1
        sat_pco = np.nan_to_num(sat_pco)
    if len(systems) == 1:
        leo_pco = receiver_pco_if(pco_body_m, systems[0], by_system[systems[0]])
    else:       # each satellite with the ionosphere-free PCO of its system's pair
        per_system = {x: receiver_pco_if(pco_body_m, x, sig) for x, sig in by_system.items()}
        leo_pco = np.array([per_system[str(sv)[0]] for sv in po.sv]).reshape(-1, 3)
    t_s = seconds_since(po.times, t_ref)
    output_times = arc_output_epochs(po.times, start, end, float(arc.output_step_s),
                                     float(arc.output_margin_s))
    t_out = seconds_since(output_times[[0, -1]], t_ref)
    # the grids cover the output epochs too, the force model's intervals start at t_s[0]
    environment = arc_environment(forces, t_ref, min(t_s[0], t_out[0]), max(t_s[-1], t_out[1]),
                                  eop=eop)
    force_model = build_force_model(forces, t_ref, t_s[0], t_s[-1], eop=eop,
                                    environment=environment, manoeuvres=data.manoeuvres,
                                    attitude=attitude)
    if apriori_orbit is None:
        apriori = xr.concat([leo.pos_m for leo in data.leo], dim="time")
        _, first = np.unique(apriori.time.values, return_index=True)
        apriori = apriori.isel(time=np.sort(first))
    else:
        apriori = apriori_orbit
    # forces tabulated along a reference orbit (drag) follow the a-priori one
    ok = np.isfinite(apriori.values).all(axis=1)
    pos_gcrf, _ = itrf_to_gcrf(apriori.time.values[ok], apriori.values[ok], eop=eop)
    force_model.follow(tabulated_orbit(seconds_since(apriori.time.values[ok], t_ref), pos_gcrf))
    return ArcProblem(observations=po, t_ref=t_ref, products=products,
                      force_model=force_model,
                      antennas={"leo_pco_body_m": leo_pco, "sat_pco_body_m": sat_pco,
                                "sat_pcv_m": sat_pcv, "leo_attitude": attitude,
                                "leo_antenna": receiver_antenna(pco_body_m, po.sv, by_system)},
                      apriori_itrf_m=apriori, output_times=output_times, eop=eop,
                      environment=environment)


def arc_outputs(problem: ArcProblem, result: PodResult,
                fit: FitResult | None = None) -> ArcOutputs:
    """The datasets of a solution of the arc (:mod:`leopod.estimation.outputs`)."""
    po = problem.observations
    out_times = problem.output_times
    orbit_ds = orbit_dataset(result, out_times, eop=problem.eop,
                             apriori_itrf_m=problem.apriori_itrf_m.reindex(time=out_times).values)
    return ArcOutputs(result=result, observations=po, orbit=orbit_ds,
                      residuals=residual_dataset(result, po),
                      parameters=parameter_dataset(result),
                      ambiguities=ambiguity_dataset(result, po), fit=fit)


def run_arc(date: str, data: ArcData, signals: SystemSignals, arc: ArcSettings,
            pod: PodSettings, forces: ForceModelSettings, pco_body_m: Mapping | None, *,
            code_correction: CodeCorrection | None = None, yaw_flips=None, eop=None,
            limits=None, attitude: LeoAttitude | None = None) -> ArcOutputs:
    """Float POD of the arc of ``date`` (module docstring).

    Parameters
    ----------
    date, data, signals, arc, forces, pco_body_m, code_correction, yaw_flips, eop, limits,
    attitude
        As for :func:`setup_arc`.
    pod : PodSettings

    Returns
    -------
    ArcOutputs
    """
    problem = setup_arc(date, data, signals, arc, forces, pco_body_m,
                        code_correction=code_correction, yaw_flips=yaw_flips, eop=eop,
                        limits=limits, attitude=attitude)
    po = problem.observations
    degree = arc.apriori_fit_degree
    fit = fit_orbit(po.times, problem.apriori_itrf_m.reindex(time=po.times).values,
                    starting_forces(forces, degree), t_ref=problem.t_ref,
                    sigma_obs_m=float(arc.apriori_fit_sigma_m), eop=eop,
                    step_s=starting_step_s(degree), environment=problem.environment,
                    attitude=attitude)
    log.info("initial dynamic fit to the a-priori orbit (gravity to degree %d, %d force "
             "parameters, %.0f-s step): RMS R %.2f T %.2f N %.2f m; %d integrations, %d force "
             "evaluations", degree, fit.force_model.n_params, starting_step_s(degree),
             *fit.rms_rtn_m, fit.integrations, fit.force_evaluations)
    problem.force_model.follow(fit.trajectory.positions)    # closer than the a-priori orbit
    result = float_pod(po, problem.products, problem.force_model, problem.t_ref,
                       fit.state0_gcrf, pod, eop=eop, cover_s=problem.output_span_s,
                       **problem.antennas)
    return arc_outputs(problem, result, fit)
