"""Onboard GNSS code and phase of a simulated LEO, with their truth (closed-loop simulator).

Why one module of 536 lines: one public function, simulate_observations, with its two input
types (ObservationSettings, GnssWorld) and the private geometry only it uses (light time,
antenna angles, patterns); a split would only export private helpers.

For every receiver epoch (clock reading ``t_read``, GPS-time label) and GNSS satellite
``s`` the generator works in the GCRF (the inertial frame of
:meth:`leopod.simulate.world.CircularOrbit.inertial` *is* the GCRF of this world):

* true reception time ``t = t_read − dt_rx`` (receiver clock, a random walk at the µs level);
* LEO centre of mass at ``t`` from the truth orbit (GCRF, 10th-order Lagrange interpolation
  of position and velocity, :func:`leopod.numerics.interpolate.interpolate_table`); antenna
  phase centre of band ``b`` = centre of mass + the body-frame PCO of the band rotated with the
  satellite's attitude law (nominal or yaw steering, :func:`leopod.frames.leo_attitude.
  leo_body_axes` with the Sun in the GCRF), the law the estimator uses; with an ANTEX
  antenna (:class:`leopod.gnss.leo_antenna.LeoAntenna`) the PCO of the band is ``ARP +
  R_ant PCO_b(N, E, U)`` and its PCV at the antenna-frame zenith and azimuth is added to the
  range of the band (codes and phases; ANTEX 1.4, sec. 3);
* transmission time ``t − τ`` by light-time iteration on the exact analytic GNSS orbit in the
  GCRF (no Sagnac term is needed in an inertial frame); transmitter phase centre = centre of
  mass + ANTEX PCO of the band (yaw-steering attitude, or the published eclipse/turn laws of
  the block with ``gnss_attitude: eclipse_models``,
  :func:`leopod.gnss.attitude.gnss_attitude_axes`, with the Sun of
  :func:`~leopod.astro.sun.sun_position_ef` rotated to the GCRF) — zero, i.e. the
  SP3 centre of mass, unless an ANTEX file is given; then also the nadir-dependent PCV;
* satellite clock ``dt^s = dt^s_product(t − τ) + Δt_rel`` with the periodic relativistic term
  ``Δt_rel = −2 r·v/c²`` (IS-GPS-200 20.3.3.3.3.1, :func:`leopod.gnss.corrections.
  relativistic_clock_s`): the clock *products* exclude it, as IGS products do;
* Shapiro delay (IERS Conventions 2010 eq. 11.17) on code and phase;
* phase wind-up (Wu et al. 1993; Kouba 2009 sec. 5.3) in cycles, equal on both frequencies,
  with receiver dipole axes ``x = body X``, ``y = −body Y`` and the transmitter's yaw-steering
  X/Y axes — the arguments the estimator uses (module docstring of
  :mod:`leopod.estimation.obsmodel`), made continuous along each track;
* first-order ionosphere ``I_b = 40.3·10¹⁶ STEC / f_b²`` [m] (STEC in TECU) from a thin shell
  ``shell_height_m`` above the LEO: ``STEC = VTEC / cos z'`` with ``sin z' = r/(r + h)
  cos e`` (e the local elevation at the LEO) and a day/night VTEC
  ``V_night + (V_day − V_night) max(0, r̂·ŝ)`` (ŝ the Sun direction), a smooth function of
  the receiver position and the line of sight, nearly common to two receivers a few km apart
  (:mod:`leopod.simulate.ionosphere`);
* code and phase biases of :mod:`leopod.simulate.biases` and integer ambiguities per pass;
* optionally (``bds2_scb``) the BDS-2 satellite-induced code bias ``s_i = −Δ(type, band, e*)``
  on the B1I/B2I/B3I codes of BDS-2 IGSO/MEO satellites: the Wanninger & Beer (2015) table
  (:mod:`leopod.gnss.scb`, whose correction ``Δ`` is *added* to observed codes) at the ground
  elevation ``e*`` equivalent to the nadir angle at the transmitter of the line to the LEO
  (transmitter at the transmission time, LEO at the reception time, exact radius).

Observation equations (metres; ``λ_b`` wavelength, ``ρ_b`` geometric range between the phase
centres of band ``b``, ``w`` wind-up [cycles], ``m_i`` the antenna-frame code-bias map of
signal ``i`` (:class:`leopod.simulate.code_bias_map.CodeBiasMap`), ``ε`` noise)::

    P_i = ρ_b + c (dt_rx − dt^s) + δ_shapiro + I_b + d_r,i + d^s_i + m_i(az, el) + s_i + ε_P
    L_i = ρ_b + c (dt_rx − dt^s) + δ_shapiro − I_b + λ_b (N_i + β_r,i + β^s_i + w) + ε_L

Receiver (:mod:`leopod.simulate.tracking`): a sticky channel allocation per system (at most
``channels`` satellites, tracked from acquisition above the antenna-frame elevation mask until
they set or a gap breaks the lock; free channels go to the highest untracked satellites);
random short gaps; cycle slips (integer jumps of the phases, LLI set with probability
``lli_detected``); a new pass with new random integer ambiguities at each acquisition (LLI
set); white noise with the elevation-dependent standard deviation ``σ(e) = σ_30 (1 + k exp(−e/10°)) / (1 + k exp(−3))``.

The default code noise levels ``σ_30`` (``simulate.observations.noise_m`` in the campaign
schema) are the typical 2-min STDs of epoch-differenced code minus carrier of Peng et al.
(2021) (C1 0.46, P1 0.09, P2 0.02 m, sec. II-B) divided by √2 (the epoch difference doubles the
variance); BDS-3 B1C/B2a (0.20 and 0.15 m before the √2) are assumed values (Jiang et al. 2023
gives no numbers); phases 1.5 mm. A key names a code of every system that has it (``C1C``), or
of one system (``E:C1C``, which wins): Galileo E1 C1C is a pilot signal on the frequency of
BDS-3 B1C, not the GPS C/A code of the same RINEX name, and takes B1C's assumed level; Galileo
E5a C5Q that of BDS-3 B2a (same frequency, pilot).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod import signals
from leopod.astro.sun import sun_position_ef
from leopod.constants import C_LIGHT_M_S
from leopod.frames.attitude import antenna_el_az
from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.leo_attitude import LeoAttitude, below_flip, leo_body_axes
from leopod.frames.yaw import orbit_angles
from leopod.gnss.attitude import gnss_attitude_axes, satellite_families
from leopod.gnss.corrections import (
    relativistic_clock_s,
    shapiro_delay_m,
    unwrap_windup,
    windup_cycles,
)
from leopod.gnss.leo_antenna import LeoAntenna
from leopod.gnss.scb import bds2_scb_m, nadir_angle_deg
from leopod.numerics.interpolate import interpolate_table
from leopod.settings import Settings
from leopod.simulate.biases import SimulatedBiases
from leopod.simulate.code_bias_map import CodeBiasMap
from leopod.simulate.ionosphere import thin_shell_stec_tecu
from leopod.simulate.tracking import passes, track
from leopod.simulate.world import CircularOrbit, KeplerOrbit, RandomWalkClock
from leopod.time.calendar import seconds_since

__all__ = ["GnssWorld", "ObservationSettings", "simulate_observations"]

#: First-order ionospheric delay factor: ``I = 40.3 STEC / f²`` with STEC in electrons/m²,
#: i.e. 40.3e16 m Hz² per TECU (Hofmann-Wellenhof et al., GNSS, 2008, eq. 5.75).
_IONO_M_HZ2_PER_TECU = 40.3e16
#: Light-time iterations (each reduces the error by v/c ~ 1e-5: 0.07 s -> < 1e-15 s).
_LIGHT_TIME_ITERATIONS = 4
#: Reference elevation of the noise levels and e-folding elevation of their growth [deg].
_NOISE_REF_EL_DEG, _NOISE_SCALE_EL_DEG = 30.0, 10.0


@dataclass(frozen=True)
class ObservationSettings(Settings):
    """Receiver, signal-noise and tracking settings of the simulated observations
    (``simulate.observations`` of the campaign schema, which holds the defaults).

    Attributes
    ----------
    noise_m : dict
        White-noise STD at 30° antenna elevation per RINEX 3 code (``C1C``) or per system and
        code (``E:C1C``, preferred where both exist) [m] (defaults: module docstring).
    low_elevation_factor : float
        ``k`` of the elevation dependence (module docstring) [1].
    channels : int
        Tracking channels per system (HY-2B: 12 for GPS).
    elevation_mask_deg : float
        Antenna-frame elevation below which nothing is tracked [deg].
    vtec_tecu : tuple of float
        Night and day vertical TEC of the thin shell above the LEO [TECU].
    shell_height_m : float
        Height of the thin shell above the LEO [m].
    slip_rate_per_h : float
        Expected cycle slips per hour of tracking of one satellite.
    slip_max_cyc : int
        Largest slip per frequency [cycles] (jumps uniform in ±this, not both zero).
    lli_detected : float
        Probability that the receiver flags a slip with the LLI.
    gap_rate_per_h : float
        Expected short tracking gaps per hour and satellite.
    gap_max_epochs : int
        Longest gap [epochs] (uniform 1..this).
    ambiguity_max_cyc : int
        Ambiguities at acquisition are uniform in ±this [cycles].
    bds2_scb : bool
        Add the BDS-2 satellite-induced code bias to the B1I/B2I/B3I codes of the BDS-2 IGSO
        and MEO satellites (module docstring).
    gnss_attitude : str
        ``eclipse_models``: the GNSS satellites follow the published yaw laws of their ANTEX
        block type (noon/midnight turns, shadow crossings, orbit-normal modes,
        :mod:`leopod.gnss.attitude`) for their antenna offsets and the wind-up; ``nominal``:
        yaw steering.
    """

    noise_m: dict
    low_elevation_factor: float
    channels: int
    elevation_mask_deg: float
    vtec_tecu: tuple[float, float]
    shell_height_m: float
    slip_rate_per_h: float
    slip_max_cyc: int
    lli_detected: float
    gap_rate_per_h: float
    gap_max_epochs: int
    ambiguity_max_cyc: int
    bds2_scb: bool
    gnss_attitude: str

    def sigma_m(self, code: str, el_deg: np.ndarray,
                systems: Sequence[str] | None = None) -> np.ndarray:
        """Noise STD [m] of ``code`` at antenna elevations ``el_deg`` [deg], shape (..., s)
        with ``systems`` (s,) the system of each satellite column (its ``<system>:<code>``
        level where given); without ``systems`` the level of the bare code."""
        level = np.array([self.noise_m.get(f"{x}:{code}", self.noise_m.get(code, np.nan))
                          for x in systems] if systems is not None
                         else self.noise_m.get(code, np.nan))
        if np.isnan(level).any():
            raise ValueError(f"no noise level for signal {code} (known: "
                             f"{', '.join(sorted(self.noise_m))})")
        k = self.low_elevation_factor
        scale = ((1.0 + k * np.exp(-np.clip(el_deg, 0.0, 90.0) / _NOISE_SCALE_EL_DEG))
                 / (1.0 + k * np.exp(-_NOISE_REF_EL_DEG / _NOISE_SCALE_EL_DEG)))
        return level * scale


@dataclass(frozen=True)
class GnssWorld:
    """The simulated GNSS constellations and their product clocks.

    Attributes
    ----------
    epoch : numpy.datetime64
        World epoch (GPS time): ``t = 0`` of the orbits and clocks.
    orbits : dict of str to CircularOrbit or KeplerOrbit
        Analytic orbits by satellite id; their inertial frame is the GCRF.
    clocks : dict of str to RandomWalkClock
        Satellite clocks as in the clock products (without the periodic relativistic term) [s].
    """

    epoch: np.datetime64
    orbits: dict[str, CircularOrbit | KeplerOrbit]
    clocks: dict[str, RandomWalkClock]

    @property
    def svs(self) -> list[str]:
        """Satellite ids, sorted."""
        return sorted(self.orbits)

    def state_gcrf(self, svs: Sequence[str], t_s: np.ndarray):
        """GCRF position [m] and velocity [m/s], shape (n, s, 3), at world times (n, s) [s]."""
        pos = np.empty(t_s.shape + (3,))
        vel = np.empty(t_s.shape + (3,))
        for j, sv in enumerate(svs):
            pos[:, j], vel[:, j] = self.orbits[sv].inertial(t_s[:, j])
        return pos, vel

    def clock_s(self, svs: Sequence[str], t_s: np.ndarray) -> np.ndarray:
        """Product clocks [s], shape (n, s), at world times (n, s) [s]."""
        return np.stack([self.clocks[sv](t_s[:, j]) for j, sv in enumerate(svs)], axis=1)


# ------------------------------------------------------------------------------ geometry


def _leo_at(truth: xr.Dataset, epoch: np.datetime64, t_s: np.ndarray):
    """Truth GCRF position and velocity of the LEO (n, 3) at world times ``t_s``."""
    nodes = seconds_since(truth["time"].values, epoch)
    pos, _ = interpolate_table(nodes, truth["pos_gcrf_m"].values, t_s)
    vel, _ = interpolate_table(nodes, truth["vel_gcrf_m_s"].values, t_s)
    if not np.isfinite(pos).all():
        raise ValueError(f"the truth orbit ({truth['time'].values[0]} to "
                         f"{truth['time'].values[-1]}) does not cover the reception times")
    return pos, vel


def _light_time(world: GnssWorld, svs, t_rx_s: np.ndarray, rx_m: np.ndarray):
    """Transmission times (n, s) [world s] and transmitter states at them (GCRF)."""
    n, s = t_rx_s.size, len(svs)
    tau = np.full((n, s), 0.075)
    for _ in range(_LIGHT_TIME_ITERATIONS):
        pos, _ = world.state_gcrf(svs, t_rx_s[:, None] - tau)
        tau = np.linalg.norm(pos - rx_m[:, None, :], axis=-1) / C_LIGHT_M_S
    t_tx = t_rx_s[:, None] - tau
    pos, vel = world.state_gcrf(svs, t_tx)
    return t_tx, pos, vel


def _antenna_angles(axes: np.ndarray, los: np.ndarray, frame: np.ndarray | None = None):
    """Antenna-frame elevation and azimuth [deg] (n, s) of unit lines of sight (n, s, 3)
    (:func:`leopod.frames.attitude.antenna_el_az`; ``frame``: that of the LEO antenna)."""
    return antenna_el_az(np.einsum("nij,nsj->nsi", axes, los), frame)


def _sat_antenna(antex, svs, epoch, bands_by_sv) -> tuple[dict, dict]:
    """Per (sv, band): body-frame PCO (3,) [m] and a PCV function of nadir [deg] -> m."""
    pco, pcv = {}, {}
    if antex is None:
        return pco, pcv
    for sv in svs:
        try:
            pattern = antex.satellite(sv, epoch)
        except KeyError:
            continue
        for band in bands_by_sv[sv]:
            freq = f"{sv[0]}{int(band):02d}"
            try:
                pco[sv, band] = np.asarray(pattern.pco_m(freq), dtype=float)
            except KeyError:
                continue
            pcv[sv, band] = (lambda nadir, p=pattern, f=freq:
                             p.pcv_m(f, nadir, outside="nearest"))
    return pco, pcv


@dataclass
class _Geometry:
    """Geometry of all (epoch, satellite) pairs of one day."""

    range_m: dict               # (system, band digit) -> (n, s) [m] incl. GNSS PCV; NaN for
                                # satellites of other systems
    el_deg: np.ndarray          # (n, s) antenna frame
    az_deg: np.ndarray
    local_el_deg: np.ndarray    # (n, s) above the LEO's local horizontal
    sv_clock_s: np.ndarray      # (n, s) true satellite clock (product + relativity)
    shapiro_m: np.ndarray       # (n, s)
    windup_cyc: np.ndarray      # (n, s) wrapped
    nadir_deg: np.ndarray       # (n, s) nadir angle at the transmitter (from its geocentre line)
    r_sv_m: np.ndarray          # (n, s) geocentric radius of the transmitter at transmission
    sun_cos: np.ndarray         # (n,) cosine of the Sun's zenith angle at the sub-LEO point
    below_flip: np.ndarray | None  # (n,) beta below the yaw-steering flip threshold; None for
                                   # a satellite without that law


def _geometry(world: GnssWorld, svs, t_rx_s, times_rx, leo_pos, leo_vel, pco_body_m,
              bands_by_sv, antex, eop, gnss_attitude: str = "nominal",
              leo_attitude: LeoAttitude | None = None) -> _Geometry:
    """Light time, ranges per band, angles, clocks, Shapiro and wind-up (module docstring)."""
    sun_gcrf, _ = itrf_to_gcrf(times_rx, sun_position_ef(times_rx), eop=eop)
    axes = leo_body_axes(leo_attitude, leo_pos, leo_vel, sun_gcrf,
                         times=times_rx)                                  # (n, 3, 3) rows
    names = _band_names(bands_by_sv)
    missing = sorted({name for name in names.values() if name not in pco_body_m})
    if missing:
        raise ValueError(f"no LEO antenna offset for the bands {missing} (pco_body_m has "
                         f"{sorted(pco_body_m)})")
    rx = {key: leo_pos + np.einsum("nij,i->nj", axes, np.asarray(pco_body_m[name], float))
          for key, name in names.items()}
    # light time to the centre of mass: for the phase centres (< 0.5 m away) the transmission
    # time would differ by < 2 ns, i.e. < 8 µm of satellite motion
    t_tx, sv_pos, sv_vel = _light_time(world, svs, t_rx_s, leo_pos)
    families = None
    if gnss_attitude == "eclipse_models" and antex is not None:
        families = np.broadcast_to(satellite_families(antex, svs, times_rx[0]), t_tx.shape)
    sv_axes = gnss_attitude_axes(sv_pos, sv_vel, sun_gcrf[:, None, :], families)  # (n, s, 3, 3)
    sat_pco, sat_pcv = _sat_antenna(antex, svs, times_rx[0], bands_by_sv)
    los = sv_pos - leo_pos[:, None, :]
    los /= np.linalg.norm(los, axis=-1, keepdims=True)
    nadir = np.degrees(np.arccos(np.clip(-np.sum(los * sv_axes[..., 2, :], axis=-1), -1.0,
                                         1.0)))
    system_of = np.array([sv[0] for sv in svs])
    frame = pco_body_m.frame if isinstance(pco_body_m, LeoAntenna) else None
    el, az = _antenna_angles(axes, los, frame)
    leo_pcv = isinstance(pco_body_m, LeoAntenna) and pco_body_m.has_pcv
    ranges = {}
    for key in rx:
        cols = np.flatnonzero(system_of == key[0])
        tx = sv_pos.copy()
        for j in cols:
            if (svs[j], key[1]) in sat_pco:
                tx[:, j] += np.einsum("nij,i->nj", sv_axes[:, j], sat_pco[svs[j], key[1]])
        rho = np.full(los.shape[:2], np.nan)
        rho[:, cols] = np.linalg.norm(tx[:, cols] - rx[key][:, None, :], axis=-1)
        for j in cols:
            if (svs[j], key[1]) in sat_pcv:
                rho[:, j] += sat_pcv[svs[j], key[1]](nadir[:, j])
        if leo_pcv:     # ANTEX 1.4 sec. 3: observed range = range to the phase centre + PCV
            rho[:, cols] += pco_body_m.pcv_m(names[key], 90.0 - el[:, cols], az[:, cols])
        ranges[key] = rho
    up = leo_pos / np.linalg.norm(leo_pos, axis=-1, keepdims=True)
    local_el = np.degrees(np.arcsin(np.clip(np.einsum("nsi,ni->ns", los, up), -1.0, 1.0)))
    clock = world.clock_s(svs, t_tx) + relativistic_clock_s(sv_pos, sv_vel)
    shapiro = shapiro_delay_m(sv_pos, leo_pos[:, None, :])
    n, s = t_tx.shape
    wind = windup_cycles(-los.reshape(-1, 3), np.repeat(axes[:, 0], s, axis=0),
                         np.repeat(-axes[:, 1], s, axis=0), sv_axes[..., 0, :].reshape(-1, 3),
                         sv_axes[..., 1, :].reshape(-1, 3)).reshape(n, s)
    sun_dir = sun_gcrf / np.linalg.norm(sun_gcrf, axis=-1, keepdims=True)
    below = None
    if leo_attitude is not None and leo_attitude.attitude == "yaw_steering":
        below = below_flip(orbit_angles(leo_pos, leo_vel, sun_gcrf)[0], leo_attitude.yaw_steering)
    return _Geometry(range_m=ranges, el_deg=el, az_deg=az, local_el_deg=local_el,
                     sv_clock_s=clock, shapiro_m=shapiro, windup_cyc=wind,
                     nadir_deg=nadir_angle_deg(sv_pos, leo_pos[:, None, :]),
                     r_sv_m=np.linalg.norm(sv_pos, axis=-1),
                     sun_cos=np.sum(up * sun_dir, axis=-1), below_flip=below)


def _band_names(bands_by_sv) -> dict[tuple[str, str], str]:
    """(system, band digit) -> band name (``L1``, ``B1C``) of every simulated band."""
    keys = sorted({(sv[0], b) for sv, bands in bands_by_sv.items() for b in bands})
    return {k: signals.band(*k).name for k in keys}


# ----------------------------------------------------------------------------- assemble


def _signals_by_sv(svs, signal_codes: Mapping[str, Sequence[str]]):
    """Per satellite: its codes (C..), its phases (L..) and the band digits of both."""
    codes, phases, bands = {}, {}, {}
    for sv in svs:
        sig = list(signal_codes[sv[0]])
        codes[sv] = [c for c in sig if c[0] == "C"]
        phases[sv] = [c for c in sig if c[0] == "L"]
        bands[sv] = sorted({c[1] for c in sig if c[0] in "CL"})
    return codes, phases, bands


def _stec_tecu(geo: _Geometry, leo_pos: np.ndarray, settings: ObservationSettings):
    """Slant TEC of the thin shell above the LEO [TECU], (n, s)
    (:mod:`leopod.simulate.ionosphere`)."""
    return thin_shell_stec_tecu(np.linalg.norm(leo_pos, axis=-1)[:, None], geo.local_el_deg,
                                geo.sun_cos, settings.vtec_tecu, settings.shell_height_m)


def _var(values, units: str, long_name: str, dims=("time", "sv")):
    return dims, values, {"units": units, "long_name": long_name}


def simulate_observations(times: np.ndarray, truth: xr.Dataset, world: GnssWorld,
                          rx_clock: RandomWalkClock, biases: SimulatedBiases,
                          signal_codes: Mapping[str, Sequence[str]],
                          pco_body_m: Mapping[str, Sequence[float]],
                          code_bias_maps: Sequence[CodeBiasMap],
                          settings: ObservationSettings, rng: np.random.Generator, *,
                          antex=None, eop=None,
                          leo_attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Simulate the onboard code and phase of a LEO at the receiver epochs ``times``.

    Parameters
    ----------
    times : ndarray of datetime64, shape (n,)
        Receiver epochs (clock readings, GPS-time labels), equally spaced.
    truth : xarray.Dataset
        Truth orbit of :func:`leopod.simulate.truth_orbit.simulate_truth_orbit` (``time``,
        ``pos_gcrf_m``, ``vel_gcrf_m_s``) covering the reception times.
    world : GnssWorld
        Constellations and product clocks.
    rx_clock : RandomWalkClock
        Receiver clock offset [s] as a function of world time.
    biases : SimulatedBiases
        True code and phase biases (satellites of ``world`` and the receiver).
    signal_codes : mapping
        System -> RINEX 3 codes to simulate (e.g. ``{"G": ["C1C", "C1W", "C2W", "L1C",
        "L2W"]}``); satellites of other systems are left out.
    pco_body_m : mapping or LeoAntenna
        LEO antenna PCO per band name (``"L1"``, ``"B2a"``) in the body frame [m]; a
        :class:`leopod.gnss.leo_antenna.LeoAntenna` also adds its PCV to the range of each
        band (codes and phases) at the antenna-frame angles, which are then those of its
        frame (``el_deg``, ``az_deg``).
    code_bias_maps : sequence of CodeBiasMap
        Antenna-frame code-bias maps, each added to its ``signal`` (a map with a
        ``yaw_branch`` only on the epochs of that branch of the yaw-steering law).
    settings : ObservationSettings
    rng : numpy.random.Generator
        Source of the gaps, slips, ambiguities and noise.
    antex : leopod.io.antex.AntexFile, optional
        GNSS satellite antenna offsets and nadir variations (default none: centre of mass).
    eop : EarthOrientation, optional
        For the Sun direction in the GCRF.
    leo_attitude : LeoAttitude, optional
        Attitude law of the LEO (``satellites.<sat>``); None: nominal.

    Returns
    -------
    xarray.Dataset
        Dims (time, sv). Observations in the schema of
        :func:`leopod.io.rinex_obs.read_rinex_obs`: one variable per RINEX 3 code (code [m],
        phase [cycles]) and ``<phase>_lli`` (int8, -1 where absent). Truth: ``pass_true``
        (int32, -1 where not tracked), ``amb_<phase>_cyc`` (integers), ``range_<phase>_m``
        (geometric range of the band's phase centres), ``range_if_m`` (ionosphere-free
        combination of the two ranges of the system), ``el_deg`` / ``az_deg`` (antenna
        frame), ``windup_cyc``, ``stec_tecu``, ``shapiro_m``, ``clk_sv_true_s`` (product clock
        plus relativity), ``code_bias_map_<code>_m``, ``scb_<code>_m`` (BDS-2 SCB added, codes
        that have one), all NaN where not tracked, and
        ``clk_rx_true_s`` (time).
    """
    times = np.asarray(times, dtype="datetime64[ns]")
    svs = [sv for sv in world.svs if sv[0] in signal_codes]
    if not svs:
        raise ValueError(f"no simulated satellite of the systems {sorted(signal_codes)}")
    n, s = times.size, len(svs)
    dt_s = float((times[1] - times[0]) / np.timedelta64(1, "s")) if n > 1 else 30.0
    t_read_s = seconds_since(times, world.epoch)
    clk_rx = rx_clock(t_read_s)
    t_rx_s = t_read_s - clk_rx
    times_rx = times - np.round(clk_rx * 1e9).astype("timedelta64[ns]")
    leo_pos, leo_vel = _leo_at(truth, world.epoch, t_rx_s)
    codes, phases, bands = _signals_by_sv(svs, signal_codes)
    geo = _geometry(world, svs, t_rx_s, times_rx, leo_pos, leo_vel, pco_body_m, bands, antex,
                    eop, settings.gnss_attitude, leo_attitude)
    system_of = np.array([sv[0] for sv in svs])
    tracked = track(geo.el_deg, system_of, settings, dt_s, rng)
    phase_codes = {sys: [c for c in signal_codes[sys] if c[0] == "L"] for sys in signal_codes}
    pas = passes(tracked, system_of, phase_codes, settings, dt_s, rng)
    # unwrap the wind-up along each tracked satellite (the ambiguity takes the integer part)
    ep, col = np.nonzero(tracked)
    windup = np.full((n, s), np.nan)
    windup[ep, col] = unwrap_windup(geo.windup_cyc[ep, col], col, ep)
    stec = _stec_tecu(geo, leo_pos, settings)
    common = C_LIGHT_M_S * (clk_rx[:, None] - geo.sv_clock_s) + geo.shapiro_m
    data = {}
    all_codes = sorted({c for sv in svs for c in codes[sv] + phases[sv]})
    maps: dict[str, list[CodeBiasMap]] = {}
    for m in code_bias_maps:
        maps.setdefault(m.signal, []).append(m)
    unknown = sorted(set(maps) - {c for c in all_codes if c[0] == "C"})
    if unknown:
        raise ValueError(f"code-bias maps for signals that are not simulated: {unknown} "
                         f"(simulated codes: {[c for c in all_codes if c[0] == 'C']})")
    phase_time = biases.sat_phase_cyc_at(times)
    for code in all_codes:
        cols = np.array([code in codes[sv] + phases[sv] for sv in svs])
        sys_of = system_of[cols]
        f = np.array([signals.frequency_hz(sys, code) for sys in sys_of])
        band = np.stack([geo.range_m[(sys, code[1])][:, j]
                         for sys, j in zip(sys_of, np.flatnonzero(cols))], axis=1)
        iono = _IONO_M_HZ2_PER_TECU * stec[:, cols] / f**2
        noise = (rng.normal(0.0, 1.0, (n, s))[:, cols]
                 * settings.sigma_m(code, geo.el_deg[:, cols], sys_of))
        rx_bias = np.array([_rx_bias(biases, sys, code) for sys in sys_of])
        value = np.full((n, s), np.nan)
        if code[0] == "C":
            sat_bias = biases.code_sat_m.sel(sv=np.array(svs)[cols], code_signal=code).values
            val = band + common[:, cols] + iono + rx_bias + sat_bias + noise
            if settings.bds2_scb:
                scb = -bds2_scb_m(np.array(svs)[cols], code, geo.nadir_deg[:, cols],
                                  geo.r_sv_m[:, cols])
                if np.any(scb != 0.0):
                    val = val + scb
                    data[f"scb_{code}_m"] = _var(
                        _masked(_scatter(scb, cols, n, s), tracked), "m",
                        f"BDS-2 satellite-induced code bias added to {code} (truth)")
            if code in maps:
                m = sum(np.where(np.reshape(cbm.applies(geo.below_flip), (-1, 1)),
                                 cbm(geo.az_deg[:, cols], geo.el_deg[:, cols]), 0.0)
                        for cbm in maps[code])
                val = val + m
                data[f"code_bias_map_{code}_m"] = _var(
                    _masked(_scatter(m, cols, n, s), tracked), "m",
                    f"code-bias map value added to {code} (truth)")
        else:
            lam = C_LIGHT_M_S / f
            sat_bias = phase_time.sel(sv=np.array(svs)[cols], phase_signal=code).values
            amb = pas.ambiguity_cyc[code][:, cols]
            val = ((band + common[:, cols] - iono + noise) / lam + amb + rx_bias + sat_bias
                   + windup[:, cols])
            data[f"{code}_lli"] = (("time", "sv"), np.where(cols[None, :], pas.lli, -1)
                                   .astype(np.int8),
                                   {"units": "1", "long_name": f"loss-of-lock indicator {code}"})
            data[f"amb_{code}_cyc"] = _var(_masked(_scatter(amb, cols, n, s), tracked), "1",
                                           f"true integer ambiguity of {code} [cycles]")
            data[f"range_{code}_m"] = _var(_masked(_scatter(band, cols, n, s), tracked), "m",
                                           f"geometric range between the {code} phase "
                                           "centres (truth)")
        value[:, cols] = val
        kind = "pseudorange" if code[0] == "C" else "carrier phase [cycles]"
        data[code] = _var(_masked(value, tracked), "m" if code[0] == "C" else "1",
                          f"{kind} {code}")
    data["range_if_m"] = _var(_masked(_range_if(geo, svs, phase_codes), tracked), "m",
                              "ionosphere-free combination of the geometric ranges (truth)")
    truth_vars = {
        "el_deg": (geo.el_deg, "degree", "antenna-frame elevation (truth)"),
        "az_deg": (geo.az_deg, "degree", ("antenna-frame azimuth from north (default +X) towards east "
                                         "(+Y) (truth)")),
        "windup_cyc": (windup, "1", "phase wind-up added to every phase [cycles] (truth)"),
        "stec_tecu": (stec, "TECU", "slant TEC of the thin-shell ionosphere (truth)"),
        "shapiro_m": (geo.shapiro_m, "m", "Shapiro delay (truth)"),
        "clk_sv_true_s": (geo.sv_clock_s, "s", ("satellite clock at transmission: product "
                                                 "clock plus periodic relativity (truth)")),
    }
    for name, (values, units, long_name) in truth_vars.items():
        data[name] = _var(_masked(values, tracked), units, long_name)
    data["pass_true"] = (("time", "sv"), pas.pass_id.astype(np.int32),
                         {"units": "1", "long_name": "true pass number (new at each "
                                                     "acquisition and slip; -1: not tracked)"})
    data["clk_rx_true_s"] = (("time",), clk_rx, {"units": "s", "long_name": "true receiver "
                                                                           "clock offset"})
    ds = xr.Dataset(data, coords={"time": times, "sv": svs})
    ds.attrs.update({"n_slips": pas.n_slips,
                     "n_passes": int(pas.pass_id.max(initial=-1)) + 1,
                     "interval_s": dt_s, "time_system": "GPS"})
    return ds


def _rx_bias(biases: SimulatedBiases, system: str, code: str) -> float:
    """Receiver code bias [m] or phase bias [cycles] of ``code``."""
    if code[0] == "C":
        return float(biases.code_rx_m.sel(system=system, code_signal=code))
    return float(biases.phase_rx_cyc.sel(system=system, phase_signal=code))


def _scatter(values: np.ndarray, cols: np.ndarray, n: int, s: int) -> np.ndarray:
    out = np.full((n, s), np.nan)
    out[:, cols] = values
    return out


def _masked(values: np.ndarray, tracked: np.ndarray) -> np.ndarray:
    return np.where(tracked, values, np.nan)


def _range_if(geo: _Geometry, svs, phase_codes) -> np.ndarray:
    """Ionosphere-free combination of the two phase-band ranges of each satellite."""
    n = geo.el_deg.shape[0]
    out = np.full((n, len(svs)), np.nan)
    for j, sv in enumerate(svs):
        p1, p2 = phase_codes[sv[0]][:2]
        f1, f2 = signals.frequency_hz(sv[0], p1), signals.frequency_hz(sv[0], p2)
        r1, r2 = geo.range_m[(sv[0], p1[1])][:, j], geo.range_m[(sv[0], p2[1])][:, j]
        out[:, j] = (f1**2 * r1 - f2**2 * r2) / (f1**2 - f2**2)
    return out
