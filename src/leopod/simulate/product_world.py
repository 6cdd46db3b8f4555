"""A simulated world whose GNSS satellites are those of a real product set.

With ``simulate.gnss_products`` the simulator does not invent the GNSS constellation: the
satellite orbits are the real SP3 orbits, the satellite clocks the real clock product (e.g.
the WHU integer-recovery "phase" clocks) and the satellite code and phase biases the real
Bias-SINEX OSBs. The LEO observations are simulated against them, so the campaign processes
the **real product files** unchanged (reading, sign conventions, wide-lane/narrow-lane
fixing), while the truth orbit, the receiver and its biases remain simulated.

Orbits. The SP3 positions (ITRF, centre of mass) are Lagrange-interpolated in the ITRF
(:class:`leopod.gnss.products.GnssProducts`, as the POD does) and rotated to the GCRF at
the same epoch (:func:`leopod.frames.earth_rotation.itrf_to_gcrf`), the inertial frame of
:class:`leopod.simulate.observations.GnssWorld`; extrapolated by up to 1 s beyond the file's
ends (light time).

Clocks. Linear interpolation between the product samples (the POD's rule), held constant
over the < 0.1 s before the first and after the last sample (transmission times of the
day's first and last epochs); satellites without a clock sample are left out. A product set
without a clock file (``clock: null``, e.g. CODE's 2023-189 OSBs and orbits, whose clocks are
not at hand) flies with simulated clocks (``simulated_clocks`` of :func:`product_world`),
which the simulator writes as the day's RINEX clock file: they refer, as any clock of an OSB
product, to the ionosphere-free combination of the clock-reference codes, whose real OSBs
have a zero ionosphere-free part (checked for CODE 2023-189 GPS C1W/C2W and Galileo C1C/C5Q
in tests/simulate/test_product_world_galileo.py), so the OSBs of the file stay consistent
with the clocks.

Biases (:func:`osb_biases`). Bias-SINEX "observation corrected = observation − OSB"
(:mod:`leopod.simulate.biases`): satellite code bias ``d^s_i`` = code OSB, phase bias
``β^s_i`` = phase OSB / ``λ_i``. Codes without an OSB (GPS C1C in the WHU 2008 file) take
``d^s_C1C = d^s_C1W − DCB(P1−C1)`` from a CODE P1C1 file.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.gnss.products import GnssProducts
from leopod.io.bias_sinex import osb, read_bias_sinex
from leopod.io.clock import read_rinex_clock
from leopod.io.dcb import read_code_dcb
from leopod.io.netcdf import merge_days
from leopod.io.sp3 import read_sp3
from leopod.signals import frequency_hz
from leopod.simulate.biases import SimulatedBiases
from leopod.simulate.observations import GnssWorld
from leopod.simulate.product_set import ProductSet
from leopod.time.calendar import seconds_since

__all__ = ["ProductSet", "osb_biases", "product_world"]

log = logging.getLogger(__name__)

#: Extrapolation of the SP3 orbits beyond their first and last node [s]: the transmission
#: times of a day's first and last epochs (light time < 0.1 s) when the orbit file covers
#: exactly the day (e.g. CODE's 2023-189 SP3, 00:00-24:00); the POD does not extrapolate and
#: leaves those epochs out.
_LIGHT_TIME_MARGIN_S = 1.0


class _ProductOrbit:
    """One satellite of a :class:`GnssProducts` table as a GCRF orbit of world time."""

    def __init__(self, products: GnssProducts, isv: int, epoch: np.datetime64):
        self._products, self._isv, self._epoch = products, isv, epoch

    def inertial(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """GCRF position [m] and velocity [m/s] (n, 3) at world times ``t_s`` [s]."""
        t_s = np.asarray(t_s, dtype=float)
        pos, vel, _ = self._products.position(np.full(t_s.shape, self._isv), t_s)
        times = self._epoch + np.round(t_s * 1e9).astype("timedelta64[ns]")
        return itrf_to_gcrf(times, pos, vel)


class _ProductClock:
    """Linear interpolation of one satellite's clock samples (constant beyond the ends)."""

    def __init__(self, t_s: np.ndarray, clk_s: np.ndarray):
        ok = np.isfinite(clk_s)
        self._t, self._c = t_s[ok], clk_s[ok]

    def __call__(self, t_s) -> np.ndarray:
        return np.interp(np.asarray(t_s, dtype=float), self._t, self._c)


def product_world(files: ProductSet, epoch, systems: Sequence[str] = ("G",),
                  simulated_clocks: Callable[[list[str]], Mapping] | None = None) -> GnssWorld:
    """The GNSS world of a real product set.

    Parameters
    ----------
    files : ProductSet
    epoch : datetime64
        World epoch (GPS time): ``t = 0`` of the orbits and clocks.
    systems : sequence of str
        Systems to keep.
    simulated_clocks : callable, optional
        ``svs -> {sv: clock}`` (a clock maps world times [s] to offsets [s]); required, and
        used, when the set has no clock file.

    Returns
    -------
    GnssWorld
        Satellites present in the orbit and OSB files (and in the clock file, if any).

    Raises
    ------
    ValueError
        If the set has no clock file and no ``simulated_clocks`` is given.
    """
    epoch = np.datetime64(epoch, "ns")
    orbit = merge_days([read_sp3(p) for p in files.orbit])
    biases = read_bias_sinex(files.osb)
    svs = sorted(set(map(str, orbit.sv.values)) & set(map(str, biases.prn.values)))
    svs = [s for s in svs if s[0] in systems]
    if files.clock:
        clock = merge_days([read_rinex_clock(p) for p in files.clock])
        svs = [s for s in svs if s in set(map(str, clock.sv.values))
               and np.isfinite(clock.clk_s.sel(sv=s).values).any()]
        t_clk = seconds_since(clock.time.values, epoch)
        clocks = {sv: _ProductClock(t_clk, clock.clk_s.sel(sv=sv).values) for sv in svs}
        clock_span = f"clocks {clock.time.values[0]} to {clock.time.values[-1]}"
    elif simulated_clocks is None:
        raise ValueError(f"product set {' '.join(files.orbit)}: no clock file and no "
                         "simulated clocks")
    else:
        clocks = dict(simulated_clocks(svs))
        clock_span = "simulated clocks"
    # only the positions of the table are used (the SP3 clock records stand in for clocks)
    products = GnssProducts.from_datasets(orbit.sel(sv=svs), orbit[["clk_s"]], epoch,
                                          max_extrapolation_s=_LIGHT_TIME_MARGIN_S)
    world = GnssWorld(
        epoch=epoch,
        orbits={sv: _ProductOrbit(products, int(products.sv_index([sv])[0]), epoch)
                for sv in svs},
        clocks=clocks)
    log.info("GNSS world from real products: %d satellites (%s), orbits %s to %s, %s",
             len(svs), " ".join(files.orbit + files.clock), orbit.time.values[0],
             orbit.time.values[-1], clock_span)
    return world


def _osb_m(biases: xr.Dataset, sv: str, signal: str, epoch) -> float:
    """OSB [m] of ``sv``/``signal`` at ``epoch`` (:func:`leopod.io.bias_sinex.osb`); NaN if
    the file has none."""
    try:
        return osb(biases, sv, signal, epoch)
    except KeyError:
        return np.nan


def osb_biases(files: ProductSet, template: SimulatedBiases, epoch) -> SimulatedBiases:
    """Satellite biases of ``template`` replaced by those of the product set's OSBs.

    Parameters
    ----------
    files : ProductSet
    template : SimulatedBiases
        Simulated biases (satellite axis and signals; receiver part kept).
    epoch : datetime64
        Epoch at which the OSB windows are read (GPS time).

    Returns
    -------
    SimulatedBiases
        Without drift (the OSB values are taken as constant over the campaign).

    Raises
    ------
    ValueError
        If a simulated signal of a satellite has neither an OSB nor (C1C) a P1−C1 DCB.
    """
    epoch = np.datetime64(epoch, "ns")
    biases = read_bias_sinex(files.osb)
    dcb = read_code_dcb(files.dcb_p1c1) if files.dcb_p1c1 else None
    code = template.code_sat_m.copy()
    phase = template.phase_sat_cyc.copy()
    for sv in code.sv.values:
        for sig in code.code_signal.values:
            if np.isnan(code.sel(sv=sv, code_signal=sig)):
                continue
            value = _osb_m(biases, sv, sig, epoch)
            if np.isnan(value) and sig == "C1C" and dcb is not None:
                value = _osb_m(biases, sv, "C1W", epoch) - _p1c1_m(dcb, sv, files)
            if np.isnan(value):
                raise ValueError(f"{files.osb}: no OSB for {sv} {sig} at {epoch} (and no "
                                 "P1-C1 DCB for C1C)")
            code.loc[{"sv": sv, "code_signal": sig}] = value
        for sig in phase.phase_signal.values:
            if np.isnan(phase.sel(sv=sv, phase_signal=sig)):
                continue
            value = _osb_m(biases, sv, sig, epoch)
            if np.isnan(value):
                raise ValueError(f"{files.osb}: no phase OSB for {sv} {sig} at {epoch}")
            phase.loc[{"sv": sv, "phase_signal": sig}] = value * frequency_hz(
                sv[0], sig) / C_LIGHT_M_S
    return SimulatedBiases(code_sat_m=code, phase_sat_cyc=phase,
                           phase_drift_sat_cyc_s=xr.zeros_like(template.phase_drift_sat_cyc_s),
                           code_rx_m=template.code_rx_m, phase_rx_cyc=template.phase_rx_cyc,
                           epoch=template.epoch, phase_pairs=template.phase_pairs)


def _p1c1_m(dcb: xr.Dataset, sv: str, files: ProductSet) -> float:
    """P1 − C1 satellite DCB [m] of ``sv`` (= OSB(C1W) − OSB(C1C), :mod:`leopod.io.dcb`)."""
    if sv not in dcb.sv.values or not np.isfinite(dcb.dcb_s.sel(sv=sv)):
        raise ValueError(f"{files.dcb_p1c1}: no P1-C1 DCB for {sv}")
    return float(dcb.dcb_s.sel(sv=sv)) * C_LIGHT_M_S
