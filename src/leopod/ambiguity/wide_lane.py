"""Wide-lane (WL) ambiguities from the Hatch–Melbourne–Wübbena (HMW) combination.

Model (Peng et al. 2021, eq. (3), written with the sign convention of
:mod:`leopod.simulate.biases`; ``s`` satellite, ``r`` receiver, ``λ_WL = c/(f1 − f2)``)::

    HMW / λ_WL = N_WL + w_r + w^s + noise,      N_WL = N1 − N2,
    w = β1 − β2 − (f1 d1 + f2 d2) / ((f1 + f2) λ_WL)

with ``β_i`` phase biases [cycles] and ``d_i`` code biases [m]. Peng et al. (2021) writes the
satellite biases with the opposite sign, ``λ (N + B_r − B^s)``: its ``B^s_HMW`` is our
``−w^s``.

Satellite WL bias ``w^s`` from the products at hand (conventions in the docstring of
:mod:`leopod.simulate.biases`):

* CNES/CLS ``WL`` records (:func:`leopod.io.wlbias.read_wl_bias`) hold ``μ^s = −w^s``:
  :func:`sat_wl_bias_cnes` returns ``w^s = −μ^s``;
* Bias-SINEX OSBs (:func:`leopod.io.bias_sinex.read_bias_sinex`), "corrected = observed −
  OSB", phase OSB ``p_i = λ_i β^s_i`` [m], code OSB ``d_i`` [m]: the HMW of the corrected
  observations has no satellite term when ``w^s λ_WL`` equals the HMW combination of the
  OSBs themselves, ``(f1 p1 − f2 p2)/(f1 − f2) − (f1 d1 + f2 d2)/(f1 + f2)``, which is
  ``λ_WL (β1 − β2) − (f1 d1 + f2 d2)/(f1 + f2)``: :func:`sat_wl_bias_osb`.

Single difference (Peng et al. 2021, eq. (6)): for two passes ``i`` (satellite ``s``) and ``j``
(satellite ``k``) of the same receiver the receiver term ``w_r`` cancels and::

    ΔN_WL = N_WL,i − N_WL,j = mean_t[(HMW_i(t) − HMW_j(t)) / λ_WL] − (w^s − w^k).

Choice: the single difference is formed epoch by epoch and averaged over the *common* epochs
of the two passes, rather than differencing the two pass means. Eq. (6) is an epoch-wise
single-difference observation equation fixed "with the multi-epoch data for each pass"
(Peng et al. 2021, sec. III-B); only at common epochs do time-varying receiver-side errors common to
both satellites (receiver code-bias or clock-related variations) cancel, and the 8-minute
common-time criterion of the pairs (:mod:`leopod.ambiguity.pairs`) only makes sense for this
form. Its sigma is either the empirical STD of the single-difference series over ``sqrt(n)``
(``sigma_method="white"``: epochs treated as independent, optimistic under time-correlated
multipath) or the unbiased sigma of the mean of a correlated series whose correlation is
fitted over all single differences of the call (``"autocorrelation"``,
:mod:`leopod.ambiguity.correlation`). The
per-pass means of :func:`pass_hmw` (Jiang et al. 2023: "an average value of the HMW observations for
each pass") are kept for quality reports.
"""

from __future__ import annotations

import itertools
import logging
from typing import NamedTuple

import numpy as np
import xarray as xr

from leopod.ambiguity.correlation import fit_correlation, mean_sigma, semivariogram
from leopod.gnss.combinations import melbourne_wuebbena, wide_lane_wavelength_m
from leopod.io.bias_sinex import osb
from leopod.signals import code_band, frequency_hz

__all__ = [
    "SdWideLane", "hmw_cycles", "pass_hmw", "sat_osb_m", "sat_wl_bias_cnes",
    "sat_wl_bias_osb", "sd_wide_lane",
]

logger = logging.getLogger(__name__)


def hmw_cycles(phase_1_m, phase_2_m, code_1_m, code_2_m, f1_hz: float, f2_hz: float):
    """HMW combination in wide-lane cycles (Peng et al. 2021, eq. (3)); arrays broadcast.

    Parameters
    ----------
    phase_1_m, phase_2_m : array_like
        Carrier phases on frequencies 1 and 2 [m].
    code_1_m, code_2_m : array_like
        Codes on the same frequencies [m], corrected (code-bias map, DCB) as the caller
        wishes.
    f1_hz, f2_hz : float
        Frequencies [Hz].

    Returns
    -------
    ndarray
        ``HMW / λ_WL`` [WL cycles].
    """
    return (melbourne_wuebbena(phase_1_m, phase_2_m, code_1_m, code_2_m, f1_hz, f2_hz)
            / wide_lane_wavelength_m(f1_hz, f2_hz))


class _Passes(NamedTuple):
    """Where each pass id of a (time, sv) id map lives (ids without data: column −1)."""

    column: np.ndarray   # (n_id,) sv column of the pass
    first: np.ndarray    # (n_id,) first time index with data
    last: np.ndarray     # (n_id,) last time index with data


def _valid(hmw_cyc: np.ndarray, pass_id: np.ndarray) -> np.ndarray:
    if hmw_cyc.shape != pass_id.shape or hmw_cyc.ndim != 2:
        raise ValueError(f"hmw_cyc and pass_id must be (time, sv) arrays of one shape, got "
                         f"{hmw_cyc.shape} and {pass_id.shape}")
    return (pass_id >= 0) & np.isfinite(hmw_cyc)


def _locate_passes(pass_id: np.ndarray, valid: np.ndarray) -> _Passes:
    """Column and first/last epoch of every pass id (row-major scan: time ascending)."""
    t_idx, s_idx = np.nonzero(valid)
    ids = pass_id[valid]
    n_id = int(ids.max()) + 1 if ids.size else 0
    column = np.full(n_id, -1, dtype=np.int64)
    first = np.zeros(n_id, dtype=np.int64)
    last = np.zeros(n_id, dtype=np.int64)
    uniq, i_first = np.unique(ids, return_index=True)
    _, i_last = np.unique(ids[::-1], return_index=True)
    i_last = ids.size - 1 - i_last
    column[uniq] = s_idx[i_first]
    first[uniq] = t_idx[i_first]
    last[uniq] = t_idx[i_last]
    if np.any(column[ids] != s_idx):
        raise ValueError("a pass id occurs in more than one satellite column")
    return _Passes(column, first, last)


def _column_of(loc: _Passes, ids: np.ndarray) -> np.ndarray:
    """Satellite column of every pass id, −1 for a pass without HMW data."""
    out = np.full(ids.size, -1, dtype=np.int64)
    inside = ids < loc.column.size
    out[inside] = loc.column[ids[inside]]
    return out


def pass_hmw(hmw_cyc: xr.DataArray, pass_id: xr.DataArray) -> xr.Dataset:
    """Mean, empirical STD and formal sigma of the HMW combination of every pass.

    Parameters
    ----------
    hmw_cyc : xarray.DataArray, (time, sv)
        HMW combination [WL cycles] (:func:`hmw_cycles`, or ``mw_cyc`` of the quality step).
    pass_id : xarray.DataArray of int, (time, sv)
        Pass number, −1 where there is none (quality output ``pass_id``); a pass id belongs
        to one satellite.

    Returns
    -------
    xarray.Dataset
        Dim ``pass`` (pass ids with at least one finite HMW value, ascending): ``pass_id``,
        ``sv``, ``start``, ``end`` (first/last epoch with data), ``n_epochs``,
        ``hmw_mean_cyc`` (mean, containing ``N_WL + w_r + w^s``), ``hmw_std_cyc`` (sample
        STD, ddof = 1; NaN for one epoch), ``hmw_sigma_cyc`` (= STD/sqrt(n)).
    """
    hmw_cyc, pass_id = xr.align(hmw_cyc, pass_id, join="exact")
    h = hmw_cyc.transpose("time", "sv").values
    pid = pass_id.transpose("time", "sv").values.astype(np.int64)
    valid = _valid(h, pid)
    loc = _locate_passes(pid, valid)
    ids = pid[valid]
    n = np.bincount(ids, minlength=loc.column.size)
    mean = np.divide(np.bincount(ids, weights=h[valid], minlength=n.size), n,
                     out=np.full(n.shape, np.nan), where=n > 0)
    dev = h[valid] - mean[ids]
    ss = np.bincount(ids, weights=dev * dev, minlength=n.size)
    present = np.nonzero(n > 0)[0]
    count, mean, ss = n[present], mean[present], ss[present]
    std = np.sqrt(np.divide(ss, count - 1, out=np.full(count.shape, np.nan),
                            where=count > 1))
    times = hmw_cyc["time"].values
    svs = hmw_cyc["sv"].values.astype(str)
    return xr.Dataset(
        {
            "pass_id": ("pass", present, {"units": "1", "long_name": "pass number"}),
            "sv": ("pass", svs[loc.column[present]], {"long_name": "GNSS satellite"}),
            "start": ("pass", times[loc.first[present]], {"long_name": "first epoch with HMW"}),
            "end": ("pass", times[loc.last[present]], {"long_name": "last epoch with HMW"}),
            "n_epochs": ("pass", count, {"units": "1", "long_name": "epochs with HMW"}),
            "hmw_mean_cyc": ("pass", mean, {"units": "1", "long_name":
                                            "mean HMW combination in wide-lane cycles"}),
            "hmw_std_cyc": ("pass", std, {"units": "1", "long_name":
                                          "empirical STD of the HMW combination"}),
            "hmw_sigma_cyc": ("pass", std / np.sqrt(count), {
                "units": "1", "long_name": "formal sigma of the mean (STD/sqrt(n))"}),
        })


class SdWideLane(NamedTuple):
    """Single-difference float WL ambiguities ``i − j`` over the common epochs.

    Attributes
    ----------
    value_cyc : ndarray, shape (m,)
        ``mean_t[h_i − h_j] − (w^s_i − w^s_j)``, ``h = HMW/λ_WL`` [WL cycles] (float
        ``ΔN_WL``);
        NaN without common epochs or satellite bias.
    std_cyc : ndarray, shape (m,)
        Empirical STD of the single-difference series [WL cycles] (ddof = 1).
    sigma_cyc : ndarray, shape (m,)
        Formal sigma of the mean, ``std_cyc / sqrt(n_common)`` [WL cycles].
    n_common : ndarray of int64, shape (m,)
        Number of common epochs used.
    n_eff : ndarray, shape (m,) or None
        Effective number of independent epochs (``"autocorrelation"`` only).
    dof : ndarray, shape (m,) or None
        Satterthwaite degrees of freedom of the sigma (``"autocorrelation"`` only).
    """

    value_cyc: np.ndarray
    std_cyc: np.ndarray
    sigma_cyc: np.ndarray
    n_common: np.ndarray
    n_eff: np.ndarray | None = None
    dof: np.ndarray | None = None


def sd_wide_lane(hmw_cyc: xr.DataArray, pass_id: xr.DataArray, id_i, id_j,
                 wl_sat_cyc: xr.DataArray | None = None, *,
                 sigma_method: str = "white") -> SdWideLane:
    """Single-difference WL float ambiguities averaged over the common epochs (Peng et al. 2021,
    eq. 6).

    Parameters
    ----------
    hmw_cyc : xarray.DataArray, (time, sv)
        HMW combination [WL cycles].
    pass_id : xarray.DataArray of int, (time, sv)
        Id of the undifferenced ambiguity of each observation (−1: none), e.g. the quality
        ``pass_id`` or the float-POD residual ``pass_index``.
    id_i, id_j : array_like of int, shape (m,)
        Ids (values of ``pass_id``) of the two passes of each pair.
    wl_sat_cyc : xarray.DataArray, (sv), optional
        Satellite WL biases ``w^s`` [WL cycles] (:func:`sat_wl_bias_cnes`,
        :func:`sat_wl_bias_osb`); None when the HMW is already corrected (OSBs subtracted
        from the observations). Satellites missing from it give NaN.
    sigma_method : {"white", "autocorrelation"}
        Sigma of the mean: ``STD/sqrt(n)``, or from the correlation fitted to all the
        single-difference series (module docstring; falls back to "white" with a warning when
        there are too few data for the fit).

    Returns
    -------
    SdWideLane
        Float ``ΔN_WL = N_WL,i − N_WL,j`` with STD and sigma; the receiver bias cancels.

    Raises
    ------
    ValueError
        If an id is not in ``pass_id``, a pass id occurs in two satellite columns or the
        sigma method is unknown. A pass without any valid HMW epoch gives its pairs no common
        epoch (NaN value and sigma: not fixed).
    """
    if sigma_method not in ("white", "autocorrelation"):
        raise ValueError(f"unknown WL sigma method {sigma_method!r} (white or autocorrelation)")
    hmw_cyc, pass_id = xr.align(hmw_cyc, pass_id, join="exact")
    h = hmw_cyc.transpose("time", "sv").values
    pid = pass_id.transpose("time", "sv").values.astype(np.int64)
    loc = _locate_passes(pid, _valid(h, pid))
    id_i = np.asarray(id_i, dtype=np.int64)
    id_j = np.asarray(id_j, dtype=np.int64)
    if id_i.shape != id_j.shape or id_i.ndim != 1:
        raise ValueError(f"id_i and id_j must be 1-d of equal length, got {id_i.shape} and "
                         f"{id_j.shape}")
    known = np.unique(pid[pid >= 0])
    for ids in (id_i, id_j):
        bad = ~np.isin(ids, known)
        if bad.any():
            raise ValueError(f"pass ids {np.unique(ids[bad]).tolist()} are not in pass_id")
    # a pass without any HMW value (e.g. its codes dropped by a code-bias map) has no
    # common epochs: its single differences get n_common 0 and a NaN value
    col_i, col_j = _column_of(loc, id_i), _column_of(loc, id_j)
    has_data = (col_i >= 0) & (col_j >= 0)
    lo = np.zeros(id_i.size, dtype=np.int64)
    length = np.zeros(id_i.size, dtype=np.int64)
    k, ki, kj = np.flatnonzero(has_data), id_i[has_data], id_j[has_data]
    lo[k] = np.maximum(loc.first[ki], loc.first[kj])
    length[k] = np.maximum(np.minimum(loc.last[ki], loc.last[kj]) - lo[k] + 1, 0)
    # all candidate epochs of all pairs, flattened: pair label and time index
    label = np.repeat(np.arange(id_i.size), length)
    offset = np.cumsum(length) - length
    t = lo[label] + np.arange(label.size) - offset[label]
    hi, hj = h[t, col_i[label]], h[t, col_j[label]]
    ok = ((pid[t, col_i[label]] == id_i[label]) & (pid[t, col_j[label]] == id_j[label])
          & np.isfinite(hi) & np.isfinite(hj))
    label, diff = label[ok], (hi - hj)[ok]
    n = np.bincount(label, minlength=id_i.size)
    mean = np.divide(np.bincount(label, weights=diff, minlength=n.size), n,
                     out=np.full(n.shape, np.nan), where=n > 0)
    dev = diff - mean[label]
    ss = np.bincount(label, weights=dev * dev, minlength=n.size)
    std = np.sqrt(np.divide(ss, n - 1, out=np.full(n.shape, np.nan), where=n > 1))
    sigma = np.divide(std, np.sqrt(n), out=np.full(n.shape, np.nan), where=n > 0)
    n_eff = dof = None
    if sigma_method == "autocorrelation":
        times_s = (hmw_cyc["time"].values - hmw_cyc["time"].values[0]) / np.timedelta64(1, "s")
        correlated = _correlated_sigma(times_s, t[ok], label, diff, n)
        if correlated is not None:
            sigma, n_eff, dof = correlated
    if wl_sat_cyc is not None:
        svs = hmw_cyc["sv"].values.astype(str)
        w = wl_sat_cyc.reindex(sv=svs).values
        mean = mean - (w[col_i] - w[col_j])
    logger.debug("%d single-difference WL ambiguities, %d without common epochs",
                 n.size, int((n == 0).sum()))
    return SdWideLane(value_cyc=mean, std_cyc=std, sigma_cyc=sigma, n_common=n, n_eff=n_eff,
                      dof=dof)


def _correlated_sigma(times_s, t_idx, label, diff, n):
    """Sigma of the mean, n_eff and dof of every series (:mod:`leopod.ambiguity.correlation`);
    None when the correlation model cannot be fitted."""
    step_s = float(np.median(np.diff(times_s))) if times_s.size > 1 else np.nan
    bounds = np.concatenate([[0], np.cumsum(n)])     # label is sorted: series are contiguous
    series_t = [times_s[t_idx[a:b]] for a, b in itertools.pairwise(bounds)]
    series_x = [diff[a:b] for a, b in itertools.pairwise(bounds)]
    try:
        model = fit_correlation(*semivariogram(series_t, series_x, step_s), step_s)
    except ValueError as err:
        logger.warning("WL sigma from STD/sqrt(n): %s", err)
        return None
    logger.info("HMW single-difference correlation: white %.3f cyc, Gauss-Markov %.3f cyc, "
                "tau %.0f s", np.sqrt(model.white_var), np.sqrt(model.markov_var), model.tau_s)
    out = np.array([mean_sigma(ts, xs, model) for ts, xs in zip(series_t, series_x,
                                                                 strict=True)]).reshape(-1, 3)
    return out[:, 0], out[:, 1], out[:, 2]


def sat_wl_bias_cnes(wl: xr.Dataset, epoch) -> xr.DataArray:
    """Satellite WL bias ``w^s`` [WL cycles] from CNES/CLS ``WL`` records.

    The records hold ``μ^s = −w^s`` (sign established in :mod:`leopod.io.wlbias` and
    :mod:`leopod.simulate.biases` from the public GRG converter), so ``w^s = −μ^s``. The
    record used is the latest one at or before ``epoch`` (daily products: the day's value).

    Parameters
    ----------
    wl : xarray.Dataset
        Output of :func:`leopod.io.wlbias.read_wl_bias` (``wl_bias_cyc`` (time, sv)).
    epoch : datetime64 or str
        Epoch (GPS time) at which the bias is wanted.

    Returns
    -------
    xarray.DataArray, (sv)
        ``w^s`` [WL cycles]; NaN where the record has no value.

    Raises
    ------
    KeyError
        If every record is later than ``epoch``.
    """
    t = np.datetime64(epoch, "ns")
    times = wl["time"].values
    k = int(np.searchsorted(times, t, side="right")) - 1
    if k < 0:
        raise KeyError(f"no WL record at or before {t} (first record {times[0]})")
    out = -wl["wl_bias_cyc"].isel(time=k, drop=True)
    out.attrs = {"units": "1", "long_name": "satellite term w^s of HMW/lambda_WL"}
    return out


def sat_osb_m(ds: xr.Dataset, svs, codes, epoch) -> xr.DataArray:
    """Satellite OSBs [m] of several signals at one epoch, NaN where the product has none.

    Parameters
    ----------
    ds : xarray.Dataset
        Output of :func:`leopod.io.bias_sinex.read_bias_sinex`.
    svs : sequence of str, shape (s,)
        Satellites.
    codes : sequence of str, shape (k,)
        RINEX 3 codes (``"C1W"``, ``"L2W"``).
    epoch : datetime64 or str
        Epoch (file time system).

    Returns
    -------
    xarray.DataArray, (sv, signal)
        OSB [m] (:func:`leopod.io.bias_sinex.osb`), to be subtracted from the observations.
    """
    svs = [str(s) for s in svs]
    codes = [str(c) for c in codes]
    values = np.full((len(svs), len(codes)), np.nan)
    for a, sv in enumerate(svs):
        for b, code in enumerate(codes):
            try:
                values[a, b] = osb(ds, sv, code, epoch)
            except KeyError:
                pass   # satellite or signal not in the product: NaN
    return xr.DataArray(values, dims=("sv", "signal"), coords={"sv": svs, "signal": codes},
                        attrs={"units": "m", "long_name": "observable-specific bias"})


def _pair_frequencies(system: str, phase, code) -> tuple[float, float]:
    """Frequencies of a phase pair [Hz], checking that the codes are on the same bands."""
    if [code_band(c) for c in code] != [code_band(p) for p in phase]:
        raise ValueError(f"codes {tuple(code)} are not on the bands of phases {tuple(phase)}")
    return frequency_hz(system, phase[0]), frequency_hz(system, phase[1])


def sat_wl_bias_osb(ds: xr.Dataset, svs, epoch, *, phase=("L1C", "L2W"),
                    code=("C1W", "C2W")) -> xr.DataArray:
    """Satellite WL bias ``w^s`` [WL cycles] from Bias-SINEX code and phase OSBs.

    ``w^s λ_WL = (f1 p1 − f2 p2)/(f1 − f2) − (f1 d1 + f2 d2)/(f1 + f2)`` (module
    docstring), i.e. ``w^s = β1 − β2 − (f1 d1 + f2 d2)/((f1 + f2) λ_WL)`` with phase OSB
    ``p_i = λ_i β_i`` and code OSB ``d_i`` ("corrected = observed − OSB", Bias-SINEX 1.00).

    Parameters
    ----------
    ds : xarray.Dataset
        Output of :func:`leopod.io.bias_sinex.read_bias_sinex`.
    svs : sequence of str
        Satellites (systems from the first letter).
    epoch : datetime64 or str
        Epoch (file time system).
    phase, code : tuple of str
        Phase and code signals of the HMW combination (same two bands, in the same order).

    Returns
    -------
    xarray.DataArray, (sv)
        ``w^s`` [WL cycles]; NaN where an OSB is missing.

    Raises
    ------
    ValueError
        If the codes are not on the bands of the phases.
    """
    table = sat_osb_m(ds, svs, [*phase, *code], epoch)
    out = np.full(table.sizes["sv"], np.nan)
    for system in sorted({str(s)[0] for s in table["sv"].values}):
        rows = np.array([str(s)[0] == system for s in table["sv"].values])
        f1, f2 = _pair_frequencies(system, phase, code)
        v = table.values[rows]
        out[rows] = (melbourne_wuebbena(v[:, 0], v[:, 1], v[:, 2], v[:, 3], f1, f2)
                     / wide_lane_wavelength_m(f1, f2))
    return xr.DataArray(out, dims="sv", coords={"sv": table["sv"].values},
                        attrs={"units": "1", "long_name": "satellite term w^s of HMW/lambda_WL"})
