"""Datasets of a float POD result: orbit, residuals, parameters, ambiguities.

Schemas (all written with :func:`leopod.io.netcdf.write_netcdf`):

orbit (dims ``time``, ``xyz``, ``rtn``)
    ``pos_itrf_m``, ``vel_itrf_m_s``, ``pos_gcrf_m``, ``vel_gcrf_m_s`` (time, xyz) centre of
    mass; ``sigma_rtn_m`` (time, rtn) and ``sigma_itrf_m`` (time, xyz) formal sigmas
    (σ0-scaled; the ITRF ones give the SP3 accuracy exponents); ``apriori_diff_rtn_m``
    (time, rtn) a-priori minus estimated orbit (NaN where no a-priori).
residuals (dims ``time``, ``sv``)
    ``code_residual_m``, ``phase_residual_m`` (NaN where not used), ``el_deg``, ``az_deg``
    (antenna frame), ``pass_index`` (−1: none), ``code_rejected``, ``phase_rejected``
    (int8), and ``clk_rx_m`` and ``isb_piece`` (index of the inter-system-bias piece of
    the epoch) (time).
parameters (dim ``parameter``)
    ``estimate``, ``sigma`` (units in ``unit``), ``covariance`` (parameter, parameter_b);
    inter-system biases are the parameters ``isb_<system>[_<piece>]_m``. Per variance group
    (dim ``group``: ``<system>_code``, ``<system>_phase``): ``variance_factor``,
    ``variance_factor_sigma``, ``redundancy`` (VCE, :mod:`leopod.estimation.vce`),
    ``apriori_sigma_m`` (scaled by the square root of the factor), ``residual_rms_m`` and
    ``n_obs``; attribute ``systems`` (reference first).
ambiguities (dim ``ambiguity``)
    ``sv``, ``pass_index``, ``start``, ``end``, ``n_obs``, ``value_m``, ``sigma_m``
    (float ionosphere-free ambiguity incl. phase biases), ``covariance_m2`` (ambiguity,
    ambiguity_b), and attrs with the signal pair and narrow-lane wavelength.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.estimation.float_pod import PodObservations, PodResult, PodStart
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices, gcrf_to_itrf, itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.time.calendar import seconds_since

__all__ = ["ambiguity_dataset", "orbit_dataset", "output_epochs", "parameter_dataset",
           "pod_start", "residual_dataset", "sp3_dataset"]

_XYZ = ["x", "y", "z"]
_RTN = ["R", "T", "N"]


def _unit(name: str) -> str:
    if name.endswith("_m_s") or name.startswith("pulse_"):
        return "m s-1"
    if name.endswith("_m") or name in ("x0_m", "y0_m", "z0_m"):
        return "m"
    if name.startswith(("emp_", "man_")):
        return "m s-2"
    return "1"


def orbit_dataset(result: PodResult, times: np.ndarray, *, eop=None,
                  apriori_itrf_m: np.ndarray | None = None) -> xr.Dataset:
    """Estimated orbit at epochs (GPS time) inside the arc, with formal RTN sigmas.

    Parameters
    ----------
    result : PodResult
    times : ndarray of datetime64, shape (m,)
    eop : EarthOrientation, optional
    apriori_itrf_m : ndarray, shape (m, 3), optional
        A-priori positions at ``times`` for ``apriori_diff_rtn_m``.
    """
    times = np.asarray(times, dtype="datetime64[ns]")
    states, cov, _ = result.orbit_at(seconds_since(times, result.t_ref))
    rtn = rtn_matrix(states[:, :3], states[:, 3:])
    cov_rtn = np.einsum("mij,mjk,mlk->mil", rtn, cov, rtn)
    sigma = np.sqrt(np.maximum(np.diagonal(cov_rtn, axis1=1, axis2=2), 0.0))
    # r_itrf = Rᵀ r_gcrf: C_itrf = Rᵀ C R
    matrices = gcrf_from_itrf_matrices(times, eop)
    cov_itrf = np.einsum("mji,mjk,mkl->mil", matrices[0], cov, matrices[0])
    sigma_itrf = np.sqrt(np.maximum(np.diagonal(cov_itrf, axis1=1, axis2=2), 0.0))
    pos_itrf, vel_itrf = gcrf_to_itrf(times, states[:, :3], states[:, 3:], eop=eop,
                                      matrices=matrices)
    diff = np.full((times.size, 3), np.nan)
    if apriori_itrf_m is not None:
        apr_gcrf, _ = itrf_to_gcrf(times, np.nan_to_num(apriori_itrf_m), eop=eop,
                                   matrices=matrices)
        d = np.einsum("mij,mj->mi", rtn, apr_gcrf - states[:, :3])
        diff = np.where(np.isfinite(apriori_itrf_m).all(axis=1)[:, None], d, np.nan)
    frame = {"reference_frame": "ITRF"}
    return xr.Dataset(
        {
            "pos_itrf_m": (("time", "xyz"), pos_itrf,
                           {"units": "m", "long_name": "centre-of-mass position", **frame}),
            "vel_itrf_m_s": (("time", "xyz"), vel_itrf,
                             {"units": "m s-1", "long_name": "Earth-fixed velocity", **frame}),
            "pos_gcrf_m": (("time", "xyz"), states[:, :3],
                           {"units": "m", "long_name": "centre-of-mass position",
                            "reference_frame": "GCRF"}),
            "vel_gcrf_m_s": (("time", "xyz"), states[:, 3:],
                             {"units": "m s-1", "long_name": "inertial velocity",
                              "reference_frame": "GCRF"}),
            "sigma_rtn_m": (("time", "rtn"), sigma,
                            {"units": "m", "long_name": "formal standard deviation of the "
                             "position (a-posteriori, sigma0-scaled)"}),
            "sigma_itrf_m": (("time", "xyz"), sigma_itrf,
                             {"units": "m", "long_name": "formal standard deviation of the "
                              "position per ITRF axis (a-posteriori, sigma0-scaled)", **frame}),
            "apriori_diff_rtn_m": (("time", "rtn"), diff,
                                   {"units": "m", "long_name": "a-priori minus estimated "
                                    "position in radial, along-track, cross-track"}),
        },
        coords={"time": times, "xyz": _XYZ, "rtn": _RTN},
    )


def residual_dataset(result: PodResult, obs: PodObservations) -> xr.Dataset:
    """Post-fit residuals on (time, sv) with elevation, azimuth and screening flags."""
    shape = (obs.times.size, obs.sv.size)

    def grid(values, fill, dtype=float):
        out = np.full(shape, fill, dtype=dtype)
        out[obs.epoch, obs.sat] = values
        return out

    m = result.model
    return xr.Dataset(
        {
            "code_residual_m": (("time", "sv"), grid(result.code_residual_m, np.nan),
                                {"units": "m", "long_name": "ionosphere-free code residual "
                                 "(observed - computed)"}),
            "phase_residual_m": (("time", "sv"), grid(result.phase_residual_m, np.nan),
                                 {"units": "m", "long_name": "ionosphere-free phase residual "
                                  "(observed - computed)"}),
            "el_deg": (("time", "sv"), grid(m.el_deg, np.nan),
                       {"units": "degree", "long_name": "elevation in the antenna frame"}),
            "az_deg": (("time", "sv"), grid(m.az_deg, np.nan),
                       {"units": "degree", "long_name": "azimuth in the antenna frame "
                        "(from +X towards +Y)"}),
            "pass_index": (("time", "sv"), grid(obs.pass_index, -1, np.int32),
                           {"units": "1", "long_name": "ambiguity pass index (-1: none)"}),
            "code_rejected": (("time", "sv"), grid(result.code_rejected, 0, np.int8),
                              {"units": "1", "long_name": "code rejected as outlier"}),
            "phase_rejected": (("time", "sv"), grid(result.phase_rejected, 0, np.int8),
                               {"units": "1", "long_name": "phase rejected as outlier"}),
            "clk_rx_m": (("time",), result.clk_rx_m,
                         {"units": "m", "long_name": "receiver clock offset times c"}),
            "isb_piece": (("time",), (np.zeros(obs.times.size, np.int32)
                                      if result.isb_piece is None
                                      else result.isb_piece.astype(np.int32)),
                          {"units": "1", "long_name": "index of the inter-system-bias piece "
                           "of the epoch (parameters isb_<system>_<piece>_m)"}),
        },
        coords={"time": obs.times, "sv": obs.sv},
    )


def parameter_dataset(result: PodResult) -> xr.Dataset:
    """Estimated arc parameters with formal sigmas and covariance, and per variance group
    (system and observation type) the variance factor, its sigma, the redundancy, the
    residual RMS and the number of observations."""
    k = len(result.parameter_names)
    names = np.array(result.parameter_names)
    groups = [f"{x}_{kind}" for x in result.systems for kind in ("code", "phase")]
    g = ("group",)
    return xr.Dataset(
        {
            "estimate": (("parameter",), result.estimates,
                         {"units": "various (see unit)", "long_name": "estimated value"}),
            "sigma": (("parameter",), result.sigmas,
                      {"units": "various (see unit)",
                       "long_name": "formal standard deviation (sigma0-scaled)"}),
            "unit": (("parameter",), np.array([_unit(n) for n in names]),
                     {"units": "1", "long_name": "unit of the parameter"}),
            "covariance": (("parameter", "parameter_b"), result.covariance[:k, :k],
                           {"units": "various (products of units)",
                            "long_name": "formal covariance (sigma0-scaled)"}),
            "variance_factor": (g, result.variance_factors,
                                {"units": "1", "long_name": "variance factor of the a-priori "
                                 "variances of the group (1: not estimated)"}),
            "variance_factor_sigma": (g, result.variance_sigmas,
                                      {"units": "1", "long_name": "standard deviation of the "
                                       "variance factor (NaN: not estimated)"}),
            "redundancy": (g, result.redundancy,
                           {"units": "1", "long_name": "redundancy number of the group"}),
            "apriori_sigma_m": (g, result.apriori_sigma_m,
                                {"units": "m", "long_name": "a-priori standard deviation of "
                                 "the group above the weighting elevation (the variance "
                                 "factor scales its square)"}),
            "residual_rms_m": (g, result.group_rms_m,
                               {"units": "m", "long_name": "RMS of the post-fit residuals"}),
            "n_obs": (g, np.asarray(result.group_count, dtype=np.int32),
                      {"units": "1", "long_name": "observations used"}),
        },
        coords={"parameter": names, "parameter_b": names, "group": groups},
        attrs={"systems": " ".join(result.systems),
               "sigma0": result.sigma0, "iterations": result.iterations,
               "converged": int(result.converged), "t_ref": str(result.t_ref)},
    )


def ambiguity_dataset(result: PodResult, obs: PodObservations) -> xr.Dataset:
    """Float ambiguities per pass with their covariance."""
    k = len(result.parameter_names)
    passes = result.ambiguity_pass
    used = result.phase_used
    sv = np.empty(passes.size, dtype=object)
    start = np.empty(passes.size, dtype="datetime64[ns]")
    end = np.empty(passes.size, dtype="datetime64[ns]")
    n_obs = np.zeros(passes.size, dtype=np.int32)
    for i, p in enumerate(passes):
        sel = used & (obs.pass_index == p)
        ep = obs.epoch[sel]
        sv[i] = str(obs.sv[obs.sat[sel][0]])
        start[i], end[i] = obs.times[ep.min()], obs.times[ep.max()]
        n_obs[i] = sel.sum()
    return xr.Dataset(
        {
            "sv": (("ambiguity",), sv.astype(str),
                   {"units": "1", "long_name": "GNSS satellite"}),
            "pass_index": (("ambiguity",), passes.astype(np.int32),
                           {"units": "1", "long_name": "pass index of the arc"}),
            "start": (("ambiguity",), start, {"long_name": "first phase observation used"}),
            "end": (("ambiguity",), end, {"long_name": "last phase observation used"}),
            "n_obs": (("ambiguity",), n_obs,
                      {"units": "1", "long_name": "phase observations used"}),
            "value_m": (("ambiguity",), result.ambiguity_m,
                        {"units": "m", "long_name": "float ionosphere-free ambiguity "
                         "(with receiver and satellite phase biases)"}),
            "sigma_m": (("ambiguity",), result.ambiguity_sigma_m,
                        {"units": "m", "long_name": "formal standard deviation"}),
            "covariance_m2": (("ambiguity", "ambiguity_b"), result.covariance[k:, k:],
                              {"units": "m2", "long_name": "formal covariance"}),
        },
        attrs=({"nl_wavelength_m": obs.nl_wavelength_m}
               if np.ndim(obs.nl_wavelength_m) == 0 else
               {"nl_wavelength_m_" + str(sv)[0]: float(nl)      # per system (one per sv)
                for sv, nl in zip(obs.sv, obs.nl_wavelength_m, strict=True)}),
    )


def pod_start(parameters: xr.Dataset, ambiguities: xr.Dataset, residuals: xr.Dataset,
              obs: PodObservations) -> PodStart:
    """Warm start of a new run of an arc from the datasets of an earlier solution.

    Parameters
    ----------
    parameters, ambiguities, residuals : xarray.Dataset
        :func:`parameter_dataset`, :func:`ambiguity_dataset`, :func:`residual_dataset` of
        the earlier solution.
    obs : PodObservations
        Observations of the new run; their epochs must be those of ``residuals``.

    Returns
    -------
    PodStart
    """
    times = residuals.time.values
    if times.shape != obs.times.shape or np.any(times != obs.times):
        raise ValueError("warm start: the epochs of the earlier solution differ from those "
                         "of the observations")
    col = {sv: i for i, sv in enumerate(residuals.sv.values.astype(str))}
    if any(sv not in col for sv in obs.sv):
        raise ValueError("warm start: satellites without a column in the earlier residuals")
    sat = np.array([col[sv] for sv in obs.sv])[obs.sat]

    def flags(name):
        return residuals[name].values[obs.epoch, sat].astype(bool)

    return PodStart(parameter_names=[str(n) for n in parameters.parameter.values],
                    estimates=parameters.estimate.values,
                    ambiguity_pass=ambiguities.pass_index.values,
                    ambiguity_m=ambiguities.value_m.values,
                    clk_rx_m=residuals.clk_rx_m.values,
                    code_rejected=flags("code_rejected"),
                    phase_rejected=flags("phase_rejected"),
                    variance_factors=(parameters.variance_factor.values
                                      if "variance_factor" in parameters else None))


def output_epochs(t_start, t_end, step_s: float) -> np.ndarray:
    """Regular epochs ``[t_start, t_end]`` on the ``step_s`` grid of the day (datetime64).

    In integer nanoseconds: in float seconds 00:00:30 is 30.000000000000004 s after midnight
    and a 10-s grid started at 00:00:40 (the first epoch of the GRACE-A 2007-080 SP3).
    """
    t_start = np.datetime64(t_start, "ns")
    day = t_start.astype("datetime64[D]").astype("datetime64[ns]")
    step = int(round(step_s * 1e9))
    start = int((t_start - day).astype("int64"))
    end = int((np.datetime64(t_end, "ns") - day).astype("int64"))
    first = -(-start // step) * step
    return day + np.arange(first, end + 1, step).astype("timedelta64[ns]")


def sp3_dataset(orbit: xr.Dataset, sat_id: str, day=None) -> xr.Dataset:
    """The ITRF orbit in the :func:`leopod.io.sp3_write.write_sp3` schema (one satellite),
    with the formal ITRF sigmas (``sigma_itrf_m``, when the orbit has them) as the record
    accuracies.

    Parameters
    ----------
    orbit : xarray.Dataset
        Output of :func:`orbit_dataset`.
    sat_id : str
        Satellite id of the SP3 records (3 characters).
    day : datetime64, optional
        Keep only the epochs of this day, 00:00 to before 24:00 (a daily product that files of
        consecutive days concatenate without duplicate epochs); None: the whole arc.
    """
    if day is not None:
        start = np.datetime64(day, "D").astype("datetime64[ns]")
        t = orbit.time.values
        orbit = orbit.isel(time=(t >= start) & (t < start + np.timedelta64(1, "D")))
    variables = {"pos_m": (("time", "sv", "xyz"), orbit.pos_itrf_m.values[:, None, :]),
                 "vel_m_s": (("time", "sv", "xyz"), orbit.vel_itrf_m_s.values[:, None, :])}
    if "sigma_itrf_m" in orbit:
        variables["pos_sigma_m"] = (("time", "sv", "xyz"), orbit.sigma_itrf_m.values[:, None, :])
    return xr.Dataset(variables,
                      coords={"time": orbit.time.values, "sv": [sat_id], "xyz": _XYZ},
                      attrs={"time_system": "GPS"})
