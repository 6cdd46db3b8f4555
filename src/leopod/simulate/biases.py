"""Simulated GNSS code and phase biases, and the ambiguity-resolution products made from them.

Why one module of 557 lines: the simulated biases and the products made from them (OSB, WL
records, integer-recovery clock) follow the one set of sign conventions stated below; a split
would separate the conventions from half of the code they govern.

Observation model of the simulator (metres; ``s`` satellite, ``r`` receiver, ``i`` signal,
``λ_i`` wavelength, ``I`` slant ionosphere on frequency 1, ``γ_i = (f_1/f_i)²``)::

    P_i = ρ + c (dt_r − dt^s) + γ_i I + d_r,i + d^s_i + ε
    L_i = ρ + c (dt_r − dt^s) − γ_i I + λ_i (N_i + β_r,i + β^s_i) + ε

``d`` are code biases [m], ``β`` phase biases [cycles] (any real; only their fractional part is
separable from the integer ``N_i``). Sign conventions of the products made here:

Bias-SINEX OSB (:func:`leopod.io.bias_sinex_write.write_bias_sinex`)
    "observation corrected = observation − OSB" (Bias-SINEX 1.00): code OSB = ``d^s_i``,
    phase OSB = ``λ_i β^s_i``. The satellite clock ``dt^s`` refers to the ionosphere-free
    combination of the clock-reference codes (``BiasSettings.clock_reference``; by default
    :data:`CLOCK_REFERENCE_CODES`: GPS C1W/C2W, BDS-3 C1P/C5P, Galileo C1C/C5Q), whose satellite code biases
    are therefore drawn with a zero ionosphere-free combination
    ``(f1² d1 − f2² d2)/(f1² − f2²) = 0``, as in the real CODE and WHU files (checked in
    tests/simulate/test_biases.py). The clock reference need not be simulated: BDS clocks
    referring to B1I/B3I (C2I/C6I, the convention of most analysis centres) with a B1C/B2a
    receiver give B1C/B2a code OSBs ``d^s = d^s_ref − DCB`` (reference code of the same band,
    else the nearest in frequency) whose ionosphere-free combination is not zero: the
    estimator must remove them.
Wide-lane satellite bias ``w^s`` [WL cycles] (HMW convention)
    With ``HMW = (f1 L1 − f2 L2)/(f1 − f2) − (f1 P1 + f2 P2)/(f1 + f2)`` (Peng et al. 2021, eq. (3))
    and ``λ_WL = c/(f1 − f2)``: ``HMW/λ_WL = (N1 − N2) + w_r + w^s`` with
    ``w = β1 − β2 − (f1 d1 + f2 d2)/((f1 + f2) λ_WL)`` for the satellite and the receiver
    (geometry, clocks and ionosphere cancel). The codes are the clock-reference pair.
    (Peng et al. 2021 write the satellite biases with the opposite sign, ``λ (N + B_r − B^s)``.)
CNES/CLS ``WL`` record (:func:`leopod.io.wlbias_write.write_wl_bias`)
    The file holds ``μ^s = −w^s``, i.e. ``HMW/λ_WL = N_WL + w_r − μ^s``: the sign that the
    public converter of the CNES/CLS (GRG) products (github.com/YuanxinPan/clkcomb,
    ``AnalyseCenter::read_grg_bias`` and ``utils/grg2snx.cpp``) assumes, as it negates the
    file value to obtain the satellite term of the HMW combination (method of the products:
    Laurichesse et al. 2009, NAVIGATION 56(2)). A user fixes ``N_WL = HMW/λ_WL + μ^s − w_r``.
Integer-recovery clock (:func:`integer_clock_s`)
    ``c dt^s_int = c dt^s − c (f1 β^s_1 − f2 β^s_2)/(f1² − f2²)``: the ionosphere-free phase
    with this clock has the ambiguity ``λ_NL N1 + c f2/(f1² − f2²) (N1 − N2)`` plus the
    receiver part (Peng et al. 2021, eq. (5)); its ionosphere-free code, however, keeps
    ``−c (f1 β^s_1 − f2 β^s_2)/(f1² − f2²)`` (up to ±0.43 m for GPS with ``|β| ≤ 0.5``), as
    with real "phase clocks". The ionosphere-free code with the standard clock ``dt^s`` has no satellite bias.

Biases are constant over the day, except an optional linear drift of the narrow-lane part of
the satellite phase biases: ``β^s_i(t) = β^s_i(t0) + ν^s (t − t0)`` with the same ``ν^s`` on
both frequencies, so ``w^s`` stays constant and the ionosphere-free phase bias drifts by
``λ_NL ν^s`` per second.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S, SECONDS_PER_DAY
from leopod.settings import Settings
from leopod.signals import frequency_hz

__all__ = [
    "CLOCK_REFERENCE_CODES",
    "DEFAULT_SIGNALS",
    "ArProducts",
    "BiasSettings",
    "SimulatedBiases",
    "ar_products",
    "if_phase_bias_m",
    "integer_clock_s",
    "simulate_biases",
    "truth_dataset",
    "wide_lane_bias_cyc",
]

#: Code pair of the wide-lane and integer-clock products per system, and the default clock
#: reference (Bias-SINEX SATELLITE_CLOCK_REFERENCE_OBSERVABLES; GPS as in CODE/WHU products,
#: Galileo E1/E5a C1C/C5Q as in CODE's COD0OPSFIN_20231890000_01D_01D_OSB.BIA).
CLOCK_REFERENCE_CODES = {"G": ("C1W", "C2W"), "C": ("C1P", "C5P"), "E": ("C1C", "C5Q")}

#: Simulated signals per system (GPS: C/A, P1, P2 codes and the L1C/L2W phases a RINEX 2
#: receiver reports; BDS-3: B1C and B2a pilot codes and phases; Galileo: E1 and E5a codes and
#: phases of CODE's OSBs).
DEFAULT_SIGNALS = {"G": ("C1C", "C1W", "C2W", "L1C", "L2W"), "C": ("C1P", "C5P", "L1P", "L5P"),
                   "E": ("C1C", "C5Q", "L1C", "L5Q")}

_NS_TO_M = 1e-9 * C_LIGHT_M_S


@dataclass(frozen=True)
class BiasSettings(Settings):
    """Magnitudes of the simulated biases (``simulate.biases`` of the campaign schema, which
    holds the defaults).

    Attributes
    ----------
    dcb_clock_pair_sigma_ns : dict
        Standard deviation of the satellite DCB between the two clock-reference codes per
        system [ns]. Default GPS C1W−C2W: 4 ns (std over GPS of C1W−C2W: 4.8 ns in CODE's OSB
        file COD0OPSFIN_20231890000_01D_01D_OSB.BIA, 3.0 ns in
        WHU0IGSFIN_20082790000_01D_01D_ABS); BDS-3 C1P−C5P: 4 ns, from Galileo C1C−C5Q on the
        same frequencies (3.9 ns in the CODE file; no BDS-3 file at hand); Galileo C1C−C5Q:
        4 ns (3.9 ns in the CODE file).
    dcb_other_sigma_ns : float
        Standard deviation of the DCB between any other code and the clock-reference code of
        its band [ns]. Default 1 ns (GPS P1−C1: 1.04 ns in CODE's P1C10810_RINEX.DCB, 1.02 ns
        in the 2023 OSB file).
    rx_code_sigma_ns : float
        Standard deviation of each receiver code bias [ns].
    phase_half_range_cyc : float
        Satellite and receiver phase biases are uniform in ``[−h, h)`` [cycles].
    nl_drift_sigma_cyc_per_day : float
        Standard deviation of the narrow-lane drift ``ν^s`` of the satellite phase biases
        [cycles/day] (0: constant).
    clock_reference : dict
        System -> the two codes the satellite clocks refer to (their ionosphere-free code
        OSB is zero); systems not given use :data:`CLOCK_REFERENCE_CODES`. E.g. BDS
        ``("C2I", "C6I")``: clocks of B1I/B3I, the convention of most analysis centres.
    """

    dcb_clock_pair_sigma_ns: dict
    dcb_other_sigma_ns: float
    rx_code_sigma_ns: float
    phase_half_range_cyc: float
    nl_drift_sigma_cyc_per_day: float
    clock_reference: dict

    def reference_codes(self, system: str) -> tuple[str, str]:
        """The clock-reference code pair of ``system``."""
        return tuple(self.clock_reference.get(system, CLOCK_REFERENCE_CODES[system]))


@dataclass(frozen=True)
class SimulatedBiases:
    """The true code and phase biases of one simulated day.

    Attributes
    ----------
    code_sat_m : xarray.DataArray, (sv, code_signal)
        Satellite code biases ``d^s_i`` [m]; NaN for signals of other systems.
    phase_sat_cyc : xarray.DataArray, (sv, phase_signal)
        Satellite phase biases ``β^s_i`` at ``epoch`` [cycles]; NaN for other systems.
    phase_drift_sat_cyc_s : xarray.DataArray, (sv,)
        Narrow-lane drift ``ν^s`` of both phase biases [cycles/s].
    code_rx_m : xarray.DataArray, (system, code_signal)
        Receiver code biases ``d_r,i`` [m].
    phase_rx_cyc : xarray.DataArray, (system, phase_signal)
        Receiver phase biases ``β_r,i`` [cycles].
    epoch : numpy.datetime64
        Start of the day (reference of the drift), GPS time.
    phase_pairs : dict
        System -> the two phase signals on the bands of :data:`CLOCK_REFERENCE_CODES`
        (``("L1C", "L2W")``).
    clock_reference : dict
        System -> the codes the satellite clocks refer to (default
        :data:`CLOCK_REFERENCE_CODES`).
    """

    code_sat_m: xr.DataArray
    phase_sat_cyc: xr.DataArray
    phase_drift_sat_cyc_s: xr.DataArray
    code_rx_m: xr.DataArray
    phase_rx_cyc: xr.DataArray
    epoch: np.datetime64
    phase_pairs: dict
    clock_reference: dict = field(default_factory=lambda: dict(CLOCK_REFERENCE_CODES))

    @property
    def systems(self) -> tuple[str, ...]:
        """Systems present, sorted."""
        return tuple(str(s) for s in self.code_rx_m["system"].values)

    def sat_phase_cyc_at(self, time) -> xr.DataArray:
        """Satellite phase biases ``β^s_i(t)`` [cycles] at the epochs ``time``.

        Parameters
        ----------
        time : array_like of datetime64, shape (n,)
            Epochs (GPS time).

        Returns
        -------
        xarray.DataArray, (time, sv, phase_signal)
        """
        t = np.atleast_1d(np.asarray(time, dtype="datetime64[ns]"))
        dt_s = xr.DataArray((t - self.epoch) / np.timedelta64(1, "s"), dims="time",
                            coords={"time": t})
        return (self.phase_sat_cyc + self.phase_drift_sat_cyc_s * dt_s).transpose(
            "time", "sv", "phase_signal")


def _pair_frequencies(system: str) -> tuple[float, float]:
    c1, c2 = CLOCK_REFERENCE_CODES[system]
    return frequency_hz(system, c1), frequency_hz(system, c2)


def _demeaned_normal(rng: np.random.Generator, sigma: float, n: int) -> np.ndarray:
    """Zero-mean (over the constellation, the usual DCB datum) normal draws."""
    x = rng.normal(0.0, sigma, n)
    return x - x.mean()


def _phase_pair(system: str, phases: list[str]) -> tuple[str, str]:
    pair = []
    for code in CLOCK_REFERENCE_CODES[system]:
        on_band = [p for p in phases if p[1] == code[1]]
        if len(on_band) != 1:
            raise ValueError(f"system {system}: need exactly one phase signal on band "
                             f"{code[1]} (clock code {code}), got {on_band}")
        pair.append(on_band[0])
    return pair[0], pair[1]


def _reference_of(system: str, code: str, c1: str, c2: str) -> str:
    """Clock-reference code a code's DCB refers to: the one on its band, else the nearest
    in frequency (BDS B1C -> B1I, B2a -> B3I)."""
    for ref in (c2, c1):
        if code[1] == ref[1]:
            return ref
    f = frequency_hz(system, code)
    return min((c1, c2), key=lambda ref: abs(frequency_hz(system, ref) - f))


def _sat_code_biases(system: str, codes: list[str], n: int, rng: np.random.Generator,
                     settings: BiasSettings) -> dict[str, np.ndarray]:
    """Satellite code biases [m] of one system: clock pair with zero IF, others by DCBs."""
    p1, p2 = CLOCK_REFERENCE_CODES[system]
    if p1 not in codes or p2 not in codes:
        raise ValueError(f"system {system}: the clock-reference codes {p1}/{p2} must be "
                         f"simulated, got {codes}")
    c1, c2 = settings.reference_codes(system)
    f1, f2 = frequency_hz(system, c1), frequency_hz(system, c2)
    dcb = _demeaned_normal(rng, settings.dcb_clock_pair_sigma_ns[system], n) * _NS_TO_M
    # d1 − d2 = DCB and f1² d1 − f2² d2 = 0
    ref = {c1: -dcb * f2**2 / (f1**2 - f2**2), c2: -dcb * f1**2 / (f1**2 - f2**2)}
    out = {c: v for c, v in ref.items() if c in codes}
    for code in codes:
        if code in out:
            continue
        # DCB(ref − code) = OSB(ref) − OSB(code), as P1−C1 = OSB(C1W) − OSB(C1C)
        out[code] = (ref[_reference_of(system, code, c1, c2)]
                     - _demeaned_normal(rng, settings.dcb_other_sigma_ns, n) * _NS_TO_M)
    return out


def simulate_biases(svs, signals_by_system: dict | None, rng: np.random.Generator, *,
                    epoch, settings: BiasSettings) -> SimulatedBiases:
    """Draw the satellite and receiver code and phase biases of one day.

    Parameters
    ----------
    svs : sequence of str
        Satellites (``"G01"``, ``"C19"``); systems must be in :data:`CLOCK_REFERENCE_CODES`.
    signals_by_system : dict or None
        System -> RINEX 3 codes (``C..`` code, ``L..`` phase) to simulate; None for
        :data:`DEFAULT_SIGNALS`. The clock-reference codes and one phase signal on each of
        their bands are required.
    rng : numpy.random.Generator
        Source of randomness (same generator state -> same biases).
    epoch : datetime64 or str
        Start of the day (GPS time): reference of the drift and of the products' windows.
    settings : BiasSettings
        Magnitudes.

    Returns
    -------
    SimulatedBiases

    Notes
    -----
    Satellite DCBs have zero mean over the satellites of each system (the datum of the IGS
    DCB products); with one satellite they are zero. Code and phase OSBs of the clock-
    reference pair satisfy the module's IF condition exactly.

    Raises
    ------
    ValueError
        If a system or a required signal is missing.
    """
    signals = DEFAULT_SIGNALS if signals_by_system is None else signals_by_system
    svs = sorted(str(s) for s in svs)
    systems = sorted({s[0] for s in svs})
    for system in systems:
        if system not in CLOCK_REFERENCE_CODES or system not in signals:
            raise ValueError(f"system {system}: no clock-reference codes or signals defined "
                             f"(known: {sorted(CLOCK_REFERENCE_CODES)})")
    codes = sorted({c for s in systems for c in signals[s] if c[0] == "C"})
    phases = sorted({c for s in systems for c in signals[s] if c[0] == "L"})
    code_sat = np.full((len(svs), len(codes)), np.nan)
    phase_sat = np.full((len(svs), len(phases)), np.nan)
    code_rx = np.full((len(systems), len(codes)), np.nan)
    phase_rx = np.full((len(systems), len(phases)), np.nan)
    drift = np.zeros(len(svs))
    pairs = {}
    h = settings.phase_half_range_cyc
    for k, system in enumerate(systems):
        rows = np.array([i for i, s in enumerate(svs) if s[0] == system])
        sys_codes = sorted(c for c in signals[system] if c[0] == "C")
        sys_phases = sorted(c for c in signals[system] if c[0] == "L")
        pairs[system] = _phase_pair(system, sys_phases)
        for code, value in _sat_code_biases(system, sys_codes, len(rows), rng,
                                            settings).items():
            code_sat[rows, codes.index(code)] = value
        for code in sys_phases:
            phase_sat[rows, phases.index(code)] = rng.uniform(-h, h, len(rows))
        drift[rows] = rng.normal(0.0, settings.nl_drift_sigma_cyc_per_day,
                                 len(rows)) / SECONDS_PER_DAY
        for code in sys_codes:
            code_rx[k, codes.index(code)] = rng.normal(0.0, settings.rx_code_sigma_ns) * _NS_TO_M
        for code in sys_phases:
            phase_rx[k, phases.index(code)] = rng.uniform(-h, h)
    coords = {"sv": svs, "code_signal": codes, "phase_signal": phases, "system": systems}
    return SimulatedBiases(
        code_sat_m=xr.DataArray(code_sat, dims=("sv", "code_signal"),
                                coords={k: coords[k] for k in ("sv", "code_signal")}),
        phase_sat_cyc=xr.DataArray(phase_sat, dims=("sv", "phase_signal"),
                                   coords={k: coords[k] for k in ("sv", "phase_signal")}),
        phase_drift_sat_cyc_s=xr.DataArray(drift, dims="sv", coords={"sv": svs}),
        code_rx_m=xr.DataArray(code_rx, dims=("system", "code_signal"),
                               coords={k: coords[k] for k in ("system", "code_signal")}),
        phase_rx_cyc=xr.DataArray(phase_rx, dims=("system", "phase_signal"),
                                  coords={k: coords[k] for k in ("system", "phase_signal")}),
        epoch=np.datetime64(epoch, "ns"),
        phase_pairs=pairs,
        clock_reference={s: settings.reference_codes(s) for s in systems},
    )


def wide_lane_bias_cyc(code_1_m, code_2_m, phase_1_cyc, phase_2_cyc, f1_hz: float,
                       f2_hz: float):
    """Bias term of ``HMW/λ_WL`` [WL cycles] from code and phase biases (Peng et al. 2021, eq. (3)).

    ``w = β1 − β2 − (f1 d1 + f2 d2)/((f1 + f2) λ_WL)``, ``λ_WL = c/(f1 − f2)``: the phase
    part ``(f1 λ1 β1 − f2 λ2 β2)/(f1 − f2) = λ_WL (β1 − β2)`` minus the narrow-lane code part,
    divided by ``λ_WL``. Arrays broadcast.

    Parameters
    ----------
    code_1_m, code_2_m : array_like
        Code biases ``d1``, ``d2`` [m].
    phase_1_cyc, phase_2_cyc : array_like
        Phase biases ``β1``, ``β2`` [cycles].
    f1_hz, f2_hz : float
        Frequencies [Hz].
    """
    lambda_wl = C_LIGHT_M_S / (f1_hz - f2_hz)
    code_nl = (f1_hz * np.asarray(code_1_m) + f2_hz * np.asarray(code_2_m)) / (f1_hz + f2_hz)
    return np.asarray(phase_1_cyc) - np.asarray(phase_2_cyc) - code_nl / lambda_wl


def if_phase_bias_m(phase_1_cyc, phase_2_cyc, f1_hz: float, f2_hz: float):
    """Ionosphere-free combination of phase biases ``c (f1 β1 − f2 β2)/(f1² − f2²)`` [m].

    Equals ``(f1² λ1 β1 − f2² λ2 β2)/(f1² − f2²)`` with ``λ_i = c/f_i``. Arrays broadcast.
    """
    return (C_LIGHT_M_S * (f1_hz * np.asarray(phase_1_cyc) - f2_hz * np.asarray(phase_2_cyc))
            / (f1_hz**2 - f2_hz**2))


def _system_rows(biases: SimulatedBiases, system: str) -> np.ndarray:
    """Indices along ``sv`` of the satellites of ``system``."""
    return np.array([i for i, s in enumerate(biases.code_sat_m["sv"].values) if s[0] == system])


def _sat_wide_lane(biases: SimulatedBiases) -> xr.DataArray:
    """``w^s`` (sv) [WL cycles] from the clock-reference codes and the phase pair."""
    out = np.full(biases.code_sat_m.sizes["sv"], np.nan)
    for system in biases.systems:
        rows = _system_rows(biases, system)
        c1, c2 = CLOCK_REFERENCE_CODES[system]
        l1, l2 = biases.phase_pairs[system]
        code = biases.code_sat_m.isel(sv=rows)
        phase = biases.phase_sat_cyc.isel(sv=rows)
        out[rows] = wide_lane_bias_cyc(code.sel(code_signal=c1), code.sel(code_signal=c2),
                                       phase.sel(phase_signal=l1), phase.sel(phase_signal=l2),
                                       *_pair_frequencies(system))
    return xr.DataArray(out, dims="sv", coords={"sv": biases.code_sat_m["sv"].values})


def _rx_combinations(biases: SimulatedBiases) -> dict[str, xr.DataArray]:
    """Receiver wide-lane [cycles], IF phase [m] and IF code [m] biases per system."""
    wl, if_phase, if_code = [], [], []
    for system in biases.systems:
        f1, f2 = _pair_frequencies(system)
        c1, c2 = CLOCK_REFERENCE_CODES[system]
        l1, l2 = biases.phase_pairs[system]
        d = biases.code_rx_m.sel(system=system)
        b = biases.phase_rx_cyc.sel(system=system)
        d1, d2 = float(d.sel(code_signal=c1)), float(d.sel(code_signal=c2))
        b1, b2 = float(b.sel(phase_signal=l1)), float(b.sel(phase_signal=l2))
        wl.append(float(wide_lane_bias_cyc(d1, d2, b1, b2, f1, f2)))
        if_phase.append(float(if_phase_bias_m(b1, b2, f1, f2)))
        if_code.append((f1**2 * d1 - f2**2 * d2) / (f1**2 - f2**2))
    coords = {"system": list(biases.systems)}
    return {k: xr.DataArray(v, dims="system", coords=coords)
            for k, v in (("wl", wl), ("if_phase", if_phase), ("if_code", if_code))}


def _sat_if_phase_bias_m(biases: SimulatedBiases, time) -> xr.DataArray:
    """``c (f1 β^s_1(t) − f2 β^s_2(t))/(f1² − f2²)`` [m], (time, sv)."""
    phase = biases.sat_phase_cyc_at(time)
    out = np.full((phase.sizes["time"], phase.sizes["sv"]), np.nan)
    for system in biases.systems:
        rows = _system_rows(biases, system)
        l1, l2 = biases.phase_pairs[system]
        p = phase.isel(sv=rows)
        out[:, rows] = if_phase_bias_m(p.sel(phase_signal=l1), p.sel(phase_signal=l2),
                                       *_pair_frequencies(system))
    return xr.DataArray(out, dims=("time", "sv"),
                        coords={"time": phase["time"].values, "sv": phase["sv"].values})


def integer_clock_s(clk_s: xr.DataArray, biases: SimulatedBiases) -> xr.DataArray:
    """Integer-recovery satellite clocks from the clocks ``dt^s`` of the simulation [s].

    ``dt^s_int = dt^s − (f1 β^s_1(t) − f2 β^s_2(t))/(f1² − f2²)`` (module docstring), with the
    clock-reference frequencies of each satellite's system (taken from its id, so no system
    argument is needed). Write the result with :func:`leopod.io.clock_write.write_rinex_clock`.

    Parameters
    ----------
    clk_s : xarray.DataArray, (time, sv)
        Satellite clocks ``dt^s`` [s] (e.g. ``read_rinex_clock(...)["clk_s"]``).
    biases : SimulatedBiases
        Must contain every satellite of ``clk_s``.

    Returns
    -------
    xarray.DataArray, (time, sv)
        Integer-recovery clocks [s].
    """
    offset_m = _sat_if_phase_bias_m(biases, clk_s["time"].values).sel(sv=clk_s["sv"].values)
    out = clk_s - offset_m.transpose(*clk_s.dims).values / C_LIGHT_M_S
    out.attrs = {"units": "s", "long_name": "integer-recovery satellite clock"}
    return out


def _var(data, long_name: str, units: str) -> xr.DataArray:
    da = data.copy()
    da.attrs = {"units": units, "long_name": long_name}
    return da


def truth_dataset(biases: SimulatedBiases) -> xr.Dataset:
    """All true biases and their combinations as one netCDF-ready Dataset.

    Returns
    -------
    xarray.Dataset
        ``code_bias_sat_m`` (sv, code_signal), ``phase_bias_sat_cyc`` (sv, phase_signal) at
        ``epoch``, ``phase_drift_sat_cyc_s`` (sv), ``code_bias_rx_m`` (system, code_signal),
        ``phase_bias_rx_cyc`` (system, phase_signal), ``wl_bias_sat_cyc`` (sv) = ``w^s``,
        ``if_phase_bias_sat_m`` (sv) at ``epoch`` = ``c (dt^s − dt^s_int)``,
        ``wl_bias_rx_cyc``, ``if_phase_bias_rx_m``, ``if_code_bias_rx_m`` (system); attrs
        ``epoch``, the clock-reference and phase pairs per system, and the conventions.
    """
    rx = _rx_combinations(biases)
    if_sat = _sat_if_phase_bias_m(biases, [biases.epoch]).isel(time=0, drop=True)
    ds = xr.Dataset({
        "code_bias_sat_m": _var(biases.code_sat_m, "satellite code bias d^s (= OSB)", "m"),
        "phase_bias_sat_cyc": _var(biases.phase_sat_cyc, "satellite phase bias beta^s at "
                                   "epoch", "1"),
        "phase_drift_sat_cyc_s": _var(biases.phase_drift_sat_cyc_s, "narrow-lane drift of "
                                      "both satellite phase biases", "s-1"),
        "code_bias_rx_m": _var(biases.code_rx_m, "receiver code bias d_r", "m"),
        "phase_bias_rx_cyc": _var(biases.phase_rx_cyc, "receiver phase bias beta_r", "1"),
        "wl_bias_sat_cyc": _var(_sat_wide_lane(biases), "satellite term w^s of HMW/lambda_WL "
                                "(clock-reference codes)", "1"),
        "if_phase_bias_sat_m": _var(if_sat, "ionosphere-free satellite phase bias at epoch "
                                    "= c (dt^s - dt^s_int)", "m"),
        "wl_bias_rx_cyc": _var(rx["wl"], "receiver term of HMW/lambda_WL", "1"),
        "if_phase_bias_rx_m": _var(rx["if_phase"], "ionosphere-free receiver phase bias", "m"),
        "if_code_bias_rx_m": _var(rx["if_code"], "ionosphere-free receiver code bias "
                                  "(clock-reference codes)", "m"),
    })
    ds.attrs["epoch"] = str(biases.epoch)
    ds.attrs["time_system"] = "GPS"
    for system in biases.systems:
        ds.attrs[f"clock_reference_codes_{system}"] = " ".join(biases.clock_reference[system])
        ds.attrs[f"phase_pair_{system}"] = " ".join(biases.phase_pairs[system])
    ds.attrs["conventions"] = (
        "P_i = rho + c(dt_r - dt^s) + gamma_i I + d_r,i + d^s_i; "
        "L_i = rho + c(dt_r - dt^s) - gamma_i I + lambda_i (N_i + beta_r,i + beta^s_i); "
        "HMW/lambda_WL = N1 - N2 + wl_bias_rx_cyc + wl_bias_sat_cyc; "
        "CNES WL file value = -wl_bias_sat_cyc")
    return ds


class ArProducts(NamedTuple):
    """Datasets of the simulated ambiguity-resolution products of one day."""

    osb: xr.Dataset
    """Input of :func:`leopod.io.bias_sinex_write.write_bias_sinex` (satellite OSBs)."""
    wl: xr.Dataset
    """Input of :func:`leopod.io.wlbias_write.write_wl_bias` (CNES sign, ``−w^s``)."""
    truth: xr.Dataset
    """:func:`truth_dataset`."""


def _records(values_s: xr.DataArray, signal_dim: str) -> tuple[np.ndarray, ...]:
    """Finite entries of ``values_s`` (sv, signal, time) [s] as record columns, sv-major."""
    v = values_s.transpose("sv", signal_dim, "time")
    sv, sig, start = np.meshgrid(v["sv"].values, v[signal_dim].values, v["time"].values,
                                 indexing="ij")
    keep = np.isfinite(v.values)
    return sv[keep], sig[keep], start[keep], v.values[keep]


def _osb_dataset(biases: SimulatedBiases, window_s: float, agency: str) -> xr.Dataset:
    n_win = round(SECONDS_PER_DAY / window_s)
    if not np.isclose(n_win * window_s, SECONDS_PER_DAY):
        raise ValueError(f"window_s={window_s} does not divide one day")
    win = np.timedelta64(round(window_s * 1e9), "ns")
    starts = biases.epoch + win * np.arange(n_win)
    code_s = (biases.code_sat_m / C_LIGHT_M_S).expand_dims(time=starts)
    phase = biases.sat_phase_cyc_at(starts + win // 2).assign_coords(time=starts)
    period_s = xr.DataArray(
        [[1.0 / frequency_hz(sv[0], sig) if np.isfinite(cyc) else np.nan
          for sig, cyc in zip(phase["phase_signal"].values, row)]
         for sv, row in zip(phase["sv"].values, biases.phase_sat_cyc.values)],
        dims=("sv", "phase_signal"), coords=biases.phase_sat_cyc.coords)
    columns = [np.concatenate(parts) for parts in zip(_records(code_s, "code_signal"),
                                                      _records(phase * period_s,
                                                               "phase_signal"))]
    prn, obs1, start, value_s = columns
    start = start.astype("datetime64[ns]")
    n = len(prn)
    ds = xr.Dataset(
        {"value_s": ("bias", value_s, {"units": "s", "long_name": "bias"}),
         "sigma_s": ("bias", np.zeros(n), {"units": "s", "long_name": "bias standard "
                                                                     "deviation (truth: 0)"})},
        coords={"bias_type": ("bias", ["OSB"] * n), "svn": ("bias", [""] * n),
                "prn": ("bias", prn), "station": ("bias", [""] * n),
                "obs1": ("bias", obs1), "obs2": ("bias", [""] * n),
                "unit": ("bias", ["ns"] * n), "start": ("bias", start),
                "end": ("bias", start + win)})
    ds.attrs.update(
        file_agency=agency, data_agency=agency, creation_time=str(biases.epoch),
        data_start=str(biases.epoch),
        data_end=str(biases.epoch + np.timedelta64(round(SECONDS_PER_DAY), "s")),
        bias_mode_flag="A", bias_mode="ABSOLUTE", bias_timing="window", time_system="GPS",
        time_system_code="G", determination_method="SIMULATION",
        parameter_spacing=round(window_s),
        reference_description="leopod closed-loop simulation (truth biases)",
        reference_output="simulated satellite code and phase OSBs",
        reference_software="leopod")
    for system in biases.systems:
        ds.attrs[f"satellite_clock_reference_observables_{system}"] = " ".join(
            biases.clock_reference[system])
    return ds


def _wl_dataset(biases: SimulatedBiases, wl_sat: xr.DataArray) -> xr.Dataset:
    values = -wl_sat.values[None, :]
    return xr.Dataset(
        {"wl_bias_cyc": (("time", "sv"), values,
                         {"units": "1", "long_name": "wide-lane satellite bias in wide-lane "
                                                     "cycles, CNES sign (= -w^s)"}),
         "wl_bias_sigma_cyc": (("time", "sv"), np.full(values.shape, np.nan),
                               {"units": "1", "long_name": "standard deviation of the "
                                                           "wide-lane satellite bias"})},
        coords={"time": [biases.epoch], "sv": wl_sat["sv"].values},
        attrs={"time_system": "GPS", "record_type": "WL"})


def ar_products(biases: SimulatedBiases, *, window_s: float = SECONDS_PER_DAY,
                agency: str = "LEO") -> ArProducts:
    """Build the datasets of the Bias-SINEX OSB and CNES ``WL`` products, and the truth.

    Parameters
    ----------
    biases : SimulatedBiases
        The day's biases.
    window_s : float
        Validity window of the OSB records [s] (divides one day). Code OSBs are constant;
        phase OSBs are the values at the window centres (exact when there is no drift).
    agency : str
        3-character agency code of the Bias-SINEX header.

    Returns
    -------
    ArProducts
        ``osb``: Bias-SINEX Dataset (schema of :func:`leopod.io.bias_sinex.read_bias_sinex`;
        code OSB ``d^s_i``, phase OSB ``λ_i β^s_i``, in ns); ``wl``: one ``WL`` epoch (start of
        the day) with ``μ^s = −w^s``; ``truth``: :func:`truth_dataset`. The integer-recovery
        clocks come from :func:`integer_clock_s`.
    """
    truth = truth_dataset(biases)
    return ArProducts(osb=_osb_dataset(biases, window_s, agency),
                      wl=_wl_dataset(biases, truth["wl_bias_sat_cyc"]), truth=truth)
