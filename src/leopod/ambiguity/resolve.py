"""Single-receiver WL/NL ambiguity resolution of one float POD arc (rule ``ambiguity``).

Steps (Peng et al. 2021, sec. III-B; Jiang et al. 2023):

1. single differences between the passes (float ambiguities) of different satellites with at
   least ``min_common_s`` of common observation time (:func:`~leopod.ambiguity.pairs.sd_pairs`);
2. wide lane: HMW of the (optionally map-corrected) codes and the phases at the POD epochs,
   each signal without the antenna range term of its frequency when the quality step gives
   them (LEO PCO per band, GNSS PCO/PCV per frequency: :mod:`leopod.gnss.antenna_terms`;
   the table's ``antenna_*`` attributes say which), single-differenced over the common
   epochs and corrected by the satellite WL biases of the campaign's product
   (:mod:`~leopod.ambiguity.wide_lane`), then the fixing decision;
3. narrow lane: from the float ionosphere-free single difference and the fixed WL, with its
   sigma from the float covariance (:mod:`~leopod.ambiguity.narrow_lane`), then the decision;
4. a maximal linearly independent set of the fixed single differences, best-determined first
   (:mod:`~leopod.ambiguity.independent`), mapped to constraints ``B_i − B_j = value`` on the
   undifferenced float ambiguities for the fixed POD.

Decisions: ``"rounding"`` — fractional part and sigma below their bounds (Peng et al. 2021: WL 0.24,
NL 0.12 cycles) — or ``"dong_bock"`` — the probability test of the BDS SCB-AR paper eq. 9
(α = 0.1 %), with the same sigma bounds. The WL sigma (``wl_sigma``, :func:`wl_sigma_method`)
is ``STD/sqrt(n)`` (by default with rounding, whose bounds were set for it) or the sigma of the
mean of a time-correlated series (:mod:`~leopod.ambiguity.correlation`; by default with the
probability test, whose α needs it; the test then widens it for its Satterthwaite degrees of
freedom). Options: the WL
candidate check of Peng et al. (2021) and integer least squares of the NL set
(:mod:`~leopod.ambiguity.alternatives`). Every candidate keeps its float value, sigma, integer,
decision and the reason of a rejection. Fixing rates follow Jiang et al. (2023): fixed independent /
all independent.

A combined POD of several systems (:func:`resolve_systems`) resolves the ambiguities of each
system with its own signal pair (WL and NL wavelengths, HMW, AR product) and single differences
only between satellites of that system (the receiver biases of different signals do not
cancel between systems; :func:`~leopod.ambiguity.pairs.sd_pairs`), and hands the constraints
of all systems to the one fixed solution.

Before anything is fixed, the product guard (:mod:`~leopod.ambiguity.consistency`) tests that the
WL and NL fractional parts cluster at zero; a refused product fixes nothing, and the table's
``product_guard*`` attributes say why. Fixed NL whose integer lies more than
``nl_max_shift_sigma`` formal sigmas from the float value are not fixed. The integer
convention is in the table's ``convention_*`` attributes (:mod:`~leopod.ambiguity.convention`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.ambiguity.alternatives import ils_nl_decision, wl_candidate_check
from leopod.ambiguity.consistency import float_consistent, product_verdict
from leopod.ambiguity.convention import integer_convention_attrs
from leopod.ambiguity.correlation import student_t_factor
from leopod.ambiguity.decision import FixDecision, dong_bock_decision, rounding_decision
from leopod.ambiguity.independent import constraint_rows, fixing_rate, independent_edges
from leopod.ambiguity.narrow_lane import fixed_sd_if_m, sd_covariance_m2, sd_narrow_lane
from leopod.ambiguity.pairs import sd_pairs
from leopod.ambiguity.wide_lane import hmw_cycles, sd_wide_lane
from leopod.gnss.antenna_terms import remove_antenna_terms
from leopod.gnss.combinations import narrow_lane_wavelength_m
from leopod.settings import Settings
from leopod.signals import frequency_hz

__all__ = ["ArSettings", "Resolution", "arc_hmw", "decide", "require_common_data", "resolve_arc",
           "resolve_systems", "wl_sigma_method"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ArSettings(Settings):
    """Tunables of the ambiguity resolution (config ``ambiguity``; units in the names)."""

    SCHEMA_DEF = "ambiguity"

    min_common_s: float
    decision: str
    wl_max_dev_cyc: float
    wl_max_sigma_cyc: float
    nl_max_dev_cyc: float
    nl_max_sigma_cyc: float
    alpha: float
    constraint_sigma_m: float
    max_residual_ratio: float
    max_rejection_rounds: int
    product_guard: bool
    guard_alpha: float
    guard_min_satellite_pairs: int
    nl_max_shift_sigma: float
    wl_sigma: str
    wl_candidate_check: bool
    nl_method: str
    ils_min_ratio: float
    ils_min_success_rate: float


@dataclass
class Resolution:
    """Result of :func:`resolve_arc`.

    Attributes
    ----------
    table : xarray.Dataset
        One row per single-difference candidate (dim ``pair``) with float values, sigmas,
        integers, decisions, reasons and the independent/constrained flags; attributes hold
        the fixing rates.
    constraints : tuple of ndarray
        ``(pass_i, pass_j, value_m, sigma_m)`` for
        :func:`leopod.estimation.float_pod.float_pod` (empty arrays if nothing is fixed).
    """

    table: xr.Dataset
    constraints: tuple


def wl_sigma_method(settings: ArSettings) -> str:
    """The WL sigma of :func:`~leopod.ambiguity.wide_lane.sd_wide_lane` (``sigma_method``):
    ``wl_sigma``, where ``"auto"`` is ``"autocorrelation"`` for the Dong–Bock test (its α holds
    only with the sigma of a time-correlated mean, benchmarks/wl_statistics.py) and
    ``"white"`` for rounding (Peng et al. 2021 bound STD/√n)."""
    if settings.wl_sigma != "auto":
        return settings.wl_sigma
    return "autocorrelation" if settings.decision == "dong_bock" else "white"


def decide(value, sigma, max_dev, max_sigma, settings: ArSettings, dof=None) -> FixDecision:
    """The campaign's fixing decision of float ambiguities (module docstring).

    Parameters
    ----------
    value, sigma : array_like, shape (m,)
        Float ambiguities and their sigmas [cycles].
    max_dev, max_sigma : float
        Bounds of the fractional part (rounding only) and of the sigma [cycles].
    settings : ArSettings
        ``decision`` (``"rounding"`` or ``"dong_bock"``) and ``alpha``.
    dof : array_like, shape (m,), optional
        Degrees of freedom of the sigmas: the Dong–Bock test widens them by the Student-t
        factor (:func:`~leopod.ambiguity.correlation.student_t_factor`).

    Returns
    -------
    FixDecision
    """
    if settings.decision == "dong_bock":
        widen = 1.0 if dof is None else student_t_factor(dof, settings.alpha)
        d = dong_bock_decision(value, np.asarray(sigma) * widen, alpha=settings.alpha)
        big = ~(np.asarray(sigma) <= max_sigma)
        reason = np.where(big & d.fixed, f"sigma > {max_sigma}", d.reason)
        return FixDecision(d.integer, d.fraction_cyc, d.fixed & ~big, reason)
    if settings.decision == "rounding":
        return rounding_decision(value, sigma, max_dev_cyc=max_dev, max_sigma_cyc=max_sigma)
    raise ValueError(f"unknown ambiguity decision {settings.decision!r} "
                     "(rounding or dong_bock)")


def require_common_data(decision: FixDecision, n_common, times, min_common_s: float
                         ) -> FixDecision:
    """No WL fix from less than ``min_common_s`` of common HMW data.

    The pairs are formed from the passes' spans (:func:`~leopod.ambiguity.pairs.sd_pairs`);
    inside a common span, epochs without both HMW values (gaps, codes dropped by a code-bias
    map) leave fewer epochs. Peng et al. (2021, sec. IV-B) ignore SDs observed together for
    less than 8 min; with a handful of epochs the empirical STD of the series, and so the
    sigma, can be small by chance (a wrong WL fix from 2 epochs with STD 0.05 cycles was seen
    in config/hy2d-sim-gc.yaml).

    Parameters
    ----------
    decision : FixDecision
        WL decision of every single difference.
    n_common : ndarray of int, shape (n_pair,)
        Common epochs with both HMW values.
    times : ndarray of datetime64, shape (n_time,)
        Epochs of the POD grid (their spacing is the sampling).
    min_common_s : float
        Least common data [s].
    """
    step_s = float(np.median(np.diff(times)) / np.timedelta64(1, "s")) if times.size > 1 else 0.0
    short = np.asarray(n_common) * step_s < min_common_s
    if not short.any():
        return decision
    reason = np.where(short, f"common HMW data < {min_common_s:g} s",
                      np.asarray(decision.reason, dtype=object))
    return decision._replace(fixed=decision.fixed & ~short, reason=reason)


def arc_hmw(obs: xr.Dataset, pass_index: xr.DataArray, system: str, phases, codes,
            antenna: xr.Dataset | None = None) -> xr.DataArray:
    """HMW combination [WL cycles] of the observations at the POD epochs (module docstring).

    Parameters
    ----------
    obs : xarray.Dataset
        Observations (codes corrected as the campaign wishes).
    pass_index : xarray.DataArray of int, (time, sv)
        Pass of every POD observation (float residuals); its grid is the output's.
    system : str
        GNSS letter.
    phases, codes : sequence of two str
        Phase and code signals of the pair.
    antenna : xarray.Dataset, optional
        Antenna range terms per band (:func:`resolve_arc`), subtracted from every signal.

    Returns
    -------
    xarray.DataArray, (time, sv)
        ``HMW/λ_WL`` on the grid of ``pass_index``, NaN where a signal is missing.
    """
    f1, f2 = frequency_hz(system, phases[0]), frequency_hz(system, phases[1])
    o = obs.reindex(time=pass_index.time, sv=pass_index.sv)
    if antenna is not None:
        o = remove_antenna_terms(o, antenna, [*phases, *codes])
    return xr.DataArray(hmw_cycles(o[phases[0]].values, o[phases[1]].values,
                                   o[codes[0]].values, o[codes[1]].values, f1, f2),
                        coords=pass_index.coords, dims=pass_index.dims)


def resolve_arc(amb: xr.Dataset, residuals: xr.Dataset, obs: xr.Dataset, system: str,
                phases, codes, wl_sat_cyc: xr.DataArray | None,
                settings: ArSettings, *, sat_if_bias_m=None,
                antenna: xr.Dataset | None = None) -> Resolution:
    """Resolve the single-difference ambiguities of one float arc (module docstring).

    Parameters
    ----------
    amb : xarray.Dataset
        Float ambiguities (:func:`leopod.estimation.outputs.ambiguity_dataset`).
    residuals : xarray.Dataset
        Float residuals with ``pass_index`` on (time, sv) (which pass each POD observation
        belongs to).
    obs : xarray.Dataset
        Observations of the arc (codes already corrected as the campaign wishes).
    system : str
        GNSS letter.
    phases, codes : sequence of two str
        Phase and code signals of the ionosphere-free pair (e.g. L1C L2W, C1W C2W).
    wl_sat_cyc : xarray.DataArray or None
        Satellite WL biases ``w^s`` [WL cycles] on ``sv``; None: no AR product, nothing is
        fixed (the table says why).
    settings : ArSettings
    sat_if_bias_m : array_like, shape (n_ambiguities,), optional
        Satellite ionosphere-free phase bias per float ambiguity [m] (OSB products with
        ordinary clocks); None with integer-recovery clocks.
    antenna : xarray.Dataset, optional
        Antenna range terms per band on (time, sv) (``antenna_range_<digit>_m`` of the quality
        output, :func:`leopod.gnss.antenna_terms.antenna_terms`), subtracted from each phase
        and code of the HMW combination (its own frequency's term); its ``antenna_*``
        attributes are copied to the table. None: raw observations (the HMW then keeps
        ``2 f1 f2 (a1 − a2)/(f1² − f2²)``).

    Returns
    -------
    Resolution
    """
    f1, f2 = frequency_hz(system, phases[0]), frequency_hz(system, phases[1])
    pairs = sd_pairs(amb.sv.values, amb.start.values, amb.end.values,
                     min_common_s=settings.min_common_s)
    i, j = pairs.i, pairs.j
    n_pair = i.size
    pid = residuals.pass_index
    hmw = arc_hmw(obs, pid, system, phases, codes, antenna)
    pass_of = amb.pass_index.values
    empty = np.zeros(0)
    if wl_sat_cyc is None or n_pair == 0:
        why = "no wide-lane satellite bias product" if wl_sat_cyc is None else "no pairs"
        log.warning("ambiguity resolution skipped: %s", why)
        wl = sd_wide_lane(hmw, pid, pass_of[i], pass_of[j], None)
        wl_dec = FixDecision(np.round(wl.value_cyc), wl.value_cyc - np.round(wl.value_cyc),
                             np.zeros(n_pair, bool), np.full(n_pair, why))
    else:
        wl = sd_wide_lane(hmw, pid, pass_of[i], pass_of[j], wl_sat_cyc,
                          sigma_method=wl_sigma_method(settings))
        wl_dec = require_common_data(
            decide(wl.value_cyc, wl.sigma_cyc, settings.wl_max_dev_cyc,
                    settings.wl_max_sigma_cyc, settings, dof=wl.dof),
            wl.n_common, pid.time.values, settings.min_common_s)
    n_wl = np.where(wl_dec.fixed, wl_dec.integer, 0).astype(np.int64)
    nl = sd_narrow_lane(amb.value_m.values, amb.covariance_m2.values, i, j, n_wl, f1, f2,
                        sat_bias_m=sat_if_bias_m)
    nl_dec = decide(nl.value_cyc, nl.sigma_cyc, settings.nl_max_dev_cyc,
                     settings.nl_max_sigma_cyc, settings)
    guard = None
    if settings.product_guard and wl_sat_cyc is not None and n_pair:
        guard = product_verdict(
            amb.sv.values[i], amb.sv.values[j], wl.value_cyc,
            wl.sigma_cyc <= settings.wl_max_sigma_cyc, nl.value_cyc,
            wl_dec.fixed & (nl.sigma_cyc <= settings.nl_max_sigma_cyc),
            alpha=settings.guard_alpha, min_pairs=settings.guard_min_satellite_pairs)
        if not guard.accepted:
            log.warning("nothing is fixed: %s", guard.reason)
            wl_dec = wl_dec._replace(fixed=np.zeros(n_pair, bool),
                                     reason=np.full(n_pair, guard.reason, dtype=object))
    refused = guard is not None and not guard.accepted
    if settings.wl_candidate_check and wl_sat_cyc is not None and not refused:
        wl_dec, nl_value, nl_dec = wl_candidate_check(
            wl.value_cyc, wl_dec, nl.value_cyc, nl_dec, nl.sigma_cyc, f2 / (f1 - f2),
            lambda v, s: decide(v, s, settings.nl_max_dev_cyc, settings.nl_max_sigma_cyc,
                                 settings))
        nl = nl._replace(value_cyc=nl_value)
        n_wl = np.where(wl_dec.fixed, wl_dec.integer, 0).astype(np.int64)
    if settings.nl_method == "ils":
        nl_dec = ils_nl_decision(
            nl.value_cyc, sd_covariance_m2(amb.covariance_m2.values, i, j)
            / narrow_lane_wavelength_m(f1, f2) ** 2, i, j, wl_dec.fixed,
            min_ratio=settings.ils_min_ratio, min_success_rate=settings.ils_min_success_rate)
    shift_ok, shift_reason = float_consistent(nl_dec.fraction_cyc, nl.sigma_cyc,
                                              settings.nl_max_shift_sigma)
    nl_fixed = nl_dec.fixed & wl_dec.fixed & shift_ok
    nl_reason = np.where(wl_dec.fixed, np.where(nl_dec.fixed, shift_reason, nl_dec.reason),
                         wl_dec.reason if refused else "wide lane not fixed")
    if (nl_dec.fixed & wl_dec.fixed & ~shift_ok).any():
        log.warning("%d NL fixes dropped: the integer lies more than %g sigma from the float "
                    "value", int((nl_dec.fixed & wl_dec.fixed & ~shift_ok).sum()),
                    settings.nl_max_shift_sigma)
    independent = independent_edges(i, j, key=nl.sigma_cyc)
    chosen = independent_edges(i[nl_fixed], j[nl_fixed], key=nl.sigma_cyc[nl_fixed])
    constrained = np.zeros(n_pair, bool)
    constrained[np.flatnonzero(nl_fixed)[chosen]] = True
    bias_sd = 0.0
    if sat_if_bias_m is not None:
        b = np.asarray(sat_if_bias_m, dtype=float)
        bias_sd = b[i] - b[j]
    value_if = fixed_sd_if_m(n_wl, np.where(nl_fixed, nl_dec.integer, 0), f1, f2,
                             sat_bias_sd_m=bias_sd)
    if constrained.any():
        rows = constraint_rows(i[constrained], j[constrained], value_if[constrained],
                               sigma_m=settings.constraint_sigma_m)
        constraints = (pass_of[rows.index_i], pass_of[rows.index_j], rows.value_m,
                       np.broadcast_to(rows.sigma_m, rows.value_m.shape).astype(float))
    else:
        constraints = (empty.astype(np.int64), empty.astype(np.int64), empty, empty)
    wl_rate = fixing_rate(i, j, wl_dec.fixed) if n_pair else np.nan
    nl_rate = fixing_rate(i, j, nl_fixed) if n_pair else np.nan
    log.info("ambiguities: %d passes, %d single differences (%d independent); WL fixed %d, "
             "NL fixed %d; fixing rates WL %.1f %%, NL %.1f %%; %d constraints",
             pass_of.size, n_pair, int(independent.sum()), int(wl_dec.fixed.sum()),
             int(nl_fixed.sum()), 100 * wl_rate, 100 * nl_rate, int(constrained.sum()))
    d = ("pair",)
    table = xr.Dataset(
        {
            "amb_i": (d, i.astype(np.int32), {"units": "1", "long_name": "first ambiguity"}),
            "amb_j": (d, j.astype(np.int32), {"units": "1", "long_name": "second ambiguity"}),
            "sv_i": (d, amb.sv.values[i].astype(str), {"units": "1", "long_name": "satellite i"}),
            "sv_j": (d, amb.sv.values[j].astype(str), {"units": "1", "long_name": "satellite j"}),
            "pass_i": (d, pass_of[i].astype(np.int32), {"units": "1", "long_name": "pass i"}),
            "pass_j": (d, pass_of[j].astype(np.int32), {"units": "1", "long_name": "pass j"}),
            "common_start": (d, pairs.common_start, {"long_name": "start of common time"}),
            "common_end": (d, pairs.common_end, {"long_name": "end of common time"}),
            "wl_float_cyc": (d, wl.value_cyc, {"units": "1", "long_name": "float SD WL"}),
            "wl_sigma_cyc": (d, wl.sigma_cyc, {"units": "1", "long_name": "sigma of SD WL"}),
            "wl_std_cyc": (d, wl.std_cyc, {"units": "1", "long_name": "STD of SD HMW"}),
            "wl_n_common": (d, wl.n_common, {"units": "1", "long_name": "common epochs"}),
            "wl_n_eff": (d, wl.n_common if wl.n_eff is None else wl.n_eff, {
                "units": "1", "long_name": "effective number of independent HMW epochs"}),
            "wl_integer": (d, wl_dec.integer.astype(np.int64),
                           {"units": "1", "long_name": "nearest integer SD WL"}),
            "wl_fraction_cyc": (d, wl_dec.fraction_cyc,
                                {"units": "1", "long_name": "float minus nearest integer"}),
            "wl_fixed": (d, wl_dec.fixed.astype(np.int8), {"units": "1", "long_name": "WL fixed"}),
            "wl_reason": (d, np.asarray(wl_dec.reason).astype(str),
                          {"units": "1", "long_name": "why the WL is not fixed"}),
            "nl_float_cyc": (d, nl.value_cyc, {"units": "1", "long_name": "float SD NL"}),
            "nl_sigma_cyc": (d, nl.sigma_cyc, {"units": "1", "long_name": "sigma of SD NL"}),
            "nl_integer": (d, nl_dec.integer.astype(np.int64),
                           {"units": "1", "long_name": "nearest integer SD NL"}),
            "nl_fraction_cyc": (d, nl_dec.fraction_cyc,
                                {"units": "1", "long_name": "float minus nearest integer"}),
            "nl_fixed": (d, nl_fixed.astype(np.int8), {"units": "1", "long_name": "NL fixed"}),
            "nl_reason": (d, np.asarray(nl_reason).astype(str),
                          {"units": "1", "long_name": "why the NL is not fixed"}),
            "independent": (d, independent.astype(np.int8),
                            {"units": "1", "long_name": "in the maximal independent set"}),
            "constrained": (d, constrained.astype(np.int8),
                            {"units": "1", "long_name": "constrained in the fixed POD"}),
            "fixed_if_m": (d, np.where(constrained, value_if, np.nan),
                           {"units": "m", "long_name": "fixed SD ionosphere-free ambiguity"}),
        },
        attrs={"wl_fixing_rate": wl_rate, "nl_fixing_rate": nl_rate,
               "n_passes": int(pass_of.size), "n_independent": int(independent.sum()),
               "decision": settings.decision, "min_common_s": settings.min_common_s,
               "wl_sigma": wl_sigma_method(settings), "nl_method": settings.nl_method,
               "wl_candidate_check": int(settings.wl_candidate_check),
               "ar_product": "none" if wl_sat_cyc is None else "wide-lane satellite biases",
               "nl_max_shift_sigma": settings.nl_max_shift_sigma,
               **integer_convention_attrs(phases),
               **({k: v for k, v in antenna.attrs.items() if k.startswith("antenna_")}
                  if antenna is not None else {"antenna_terms": "not removed (raw HMW)"})},
    )
    if guard is not None:
        table.attrs.update(guard.attrs(settings.guard_alpha, settings.guard_min_satellite_pairs))
    else:
        table.attrs.update(product_guard="not tested", product_guard_reason=(
            "guard disabled" if not settings.product_guard else "no AR product or no pairs"))
    return Resolution(table=table, constraints=constraints)


def resolve_systems(amb: xr.Dataset, residuals: xr.Dataset, obs: xr.Dataset, signals,
                    wl_sat_cyc, settings: ArSettings, *, sat_if_bias_m=None,
                    antenna: xr.Dataset | None = None) -> Resolution:
    """:func:`resolve_arc` of each system of a combined float arc, joined (module docstring).

    Parameters
    ----------
    amb, residuals, obs, settings, antenna
        As for :func:`resolve_arc` (all systems of the arc).
    signals : mapping of str to leopod.signals.SystemSignals
        Signals (``phase`` and ``pod_code`` pairs) per system letter, in the order of the POD.
    wl_sat_cyc : mapping of str to (xarray.DataArray or None)
        Satellite WL biases per system (:func:`resolve_arc`).
    sat_if_bias_m : mapping of str to array_like, optional
        Satellite IF phase bias per float ambiguity of each system's ambiguities (in the
        order of ``amb`` restricted to the system).

    Returns
    -------
    Resolution
        The tables of the systems concatenated along ``pair`` with a ``system`` variable;
        ``amb_i``/``amb_j`` index ``amb``; attributes ``<system>_<attribute>`` of each
        system's table, and the fixing rates of all systems together
        (:func:`leopod.ambiguity.independent.fixing_rate` of all pairs).
    """
    sv = amb.sv.values.astype(str)
    tables, parts, used = [], [], []
    for x, sig in signals.items():
        index = np.flatnonzero(np.char.startswith(sv, x))
        if not index.size:
            continue
        used.append(x)
        sub = amb.isel(ambiguity=index, ambiguity_b=index)
        columns = [s for s in residuals.sv.values if str(s)[0] == x]
        res = resolve_arc(sub, residuals.sel(sv=columns), obs, x, sig.phase, sig.pod_code,
                          wl_sat_cyc.get(x), settings,
                          sat_if_bias_m=None if sat_if_bias_m is None else sat_if_bias_m.get(x),
                          antenna=antenna)
        table = res.table
        table["amb_i"] = table.amb_i.copy(data=index[table.amb_i.values].astype(np.int32))
        table["amb_j"] = table.amb_j.copy(data=index[table.amb_j.values].astype(np.int32))
        table["system"] = (("pair",), np.full(table.sizes["pair"], x),
                           {"units": "1", "long_name": "GNSS of the single difference"})
        tables.append(table)
        parts.append(res.constraints)
    if not tables:
        raise ValueError("no float ambiguity of the systems " + " ".join(signals))
    joined = xr.concat([t.drop_attrs(deep=False) for t in tables], dim="pair")
    for x, t in zip(used, tables, strict=True):
        joined.attrs.update({f"{x}_{k}": v for k, v in t.attrs.items()})
    i, j = joined.amb_i.values, joined.amb_j.values
    joined.attrs["systems"] = " ".join(used)
    joined.attrs["wl_fixing_rate"] = (fixing_rate(i, j, joined.wl_fixed.values == 1)
                                      if i.size else np.nan)
    joined.attrs["nl_fixing_rate"] = (fixing_rate(i, j, joined.nl_fixed.values == 1)
                                      if i.size else np.nan)
    joined.attrs["ar_product"] = "; ".join(f"{x}: {t.attrs.get('ar_product')}"
                                           for x, t in zip(used, tables, strict=True))
    constraints = tuple(np.concatenate([c[k] for c in parts]) for k in range(4))
    log.info("combined AR: %d single differences of %s, fixing rates WL %.1f %%, NL %.1f %%, "
             "%d constraints", i.size, joined.attrs["systems"],
             100 * joined.attrs["wl_fixing_rate"], 100 * joined.attrs["nl_fixing_rate"],
             constraints[0].size)
    return Resolution(table=joined, constraints=constraints)
