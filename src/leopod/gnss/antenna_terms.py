"""Per-frequency antenna terms of onboard observations, removed before HMW and MP are formed.

The geometry-free combinations keep what differs between the two frequencies of a satellite
pair. A phase-centre offset (PCO) or variation (PCV) that differs between the bands leaves
``2 f1 f2 (a1 − a2) / (f1² − f2²)`` in the HMW combination (Peng et al. 2021, eq. (3)) and
``−2 fj² (ai − aj) / (fi² − fj²)`` in the multipath combination MP_i (Peng et al. 2021, eq. (1)),
``a_b`` being the range term of band ``b`` below. Jiang et al. (2023, on single-receiver
AR) note that "a further antenna phase center correction is required because the
antenna phase centers of the frequencies are different" (their Table 1: HY-2D L1/L2 PCOs 1.9 cm
and B1C/B2a 2.7 cm apart along Z). Left in, the term biases the wide-lane pass means (GPS L1/L2
2 cm apart along the boresight: up to 0.09 WL cycles) and the code-bias maps absorb it
(3.1 × 2 cm × sin e on C1W, 5.1 × 2 cm × sin e on C2W), to re-inject it into the codes when
the maps are applied.

Range term of band ``b`` for the line of sight ``e`` (unit vector receiver → transmitter) [m]::

    a_b = −e · (R_LEO p_LEO,b) + e · (R_sv p_sv,b) + PCV_sv,b(nadir) + PCV_LEO,b(el, az)

- ``p_LEO,b``: LEO PCO of the band in the body frame (configuration ``antenna_pco_body_m``, the
  offsets the POD combines to its ionosphere-free PCO), rotated into Earth-fixed axes with the
  satellite's attitude law ``R_LEO`` (:func:`leopod.frames.leo_attitude.leo_body_axes`: nominal
  or yaw steering; the attitude of the POD's observation model,
  :mod:`leopod.estimation.obsmodel`);
- ``p_sv,b``, ``PCV_sv,b``: the ANTEX PCO and nadir-dependent PCV of the GNSS satellite on the
  band's frequency (``sNN`` code, :mod:`leopod.io.antex`), PCO rotated with the yaw-steering
  attitude of :func:`leopod.gnss.attitude.gnss_body_axes`, or with ``gnss_attitude:
  eclipse_models`` the yaw law of the block (:func:`leopod.gnss.attitude.gnss_attitude_axes`;
  Sun of :func:`leopod.astro.sun.sun_position_ef`) — the source and attitude of the POD's satellite
  antenna model (:func:`leopod.estimation.inputs.satellite_antenna`), per frequency instead of
  ionosphere-free;
- ``PCV_LEO,b``: the LEO phase-centre variations of an ANTEX antenna (``satellites.<sat>.
  antenna``, :class:`leopod.gnss.leo_antenna.LeoAntenna`: ``p_LEO,b`` is then its ``ARP +
  R_ant PCO_b``) at the zenith and azimuth of the line of sight in its antenna frame
  (:func:`leopod.frames.attitude.antenna_el_az`), the PCV the POD combines to its
  ionosphere-free PCV; none with ``antenna_pco_body_m``.

Sign (ANTEX 1.4, sec. 3: mean phase centre = reference point + PCO; observed range = range to
the mean phase centre + PCV): the range between the phase centres of band ``b`` is the range
between the centres of mass plus ``a_b``, so the antenna-free observation is
``observation − a_b`` for the code *and* the phase of the band (both in metres). An antenna
that sits above the centre of mass (body ``z_b < 0``, Z to the geocentre) shortens the range by
``|z_b| sin e`` (e the antenna-frame elevation).

Observations of satellites of a system with an ANTEX file but no entry for the satellite (or
the band) get NaN terms: the POD does not use them either.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from leopod import signals
from leopod.constants import OMEGA_EARTH_RAD_S
from leopod.frames.attitude import antenna_el_az, body_to_ef, inertial_velocity_ef
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes, leo_body_axes_ef
from leopod.gnss.attitude import gnss_attitude_axes, gnss_body_axes, satellite_families
from leopod.gnss.leo_antenna import LeoAntenna

__all__ = ["VARIABLE", "antenna_attrs", "antenna_range_m", "antenna_terms",
           "remove_antenna_terms"]

#: Name of the range term of RINEX band digit ``{band}`` in datasets (e.g. ``antenna_range_1_m``).
VARIABLE = "antenna_range_{band}_m"


def _unit(vec: np.ndarray) -> np.ndarray:
    return vec / np.linalg.norm(vec, axis=-1, keepdims=True)


def antenna_range_m(leo_pos_m: np.ndarray, leo_vel_m_s: np.ndarray, sv_pos_m: np.ndarray,
                    sun_m: np.ndarray, leo_pco_body_m, *, sat_pco_body_m=None,
                    sat_pcv_m: Callable | None = None,
                    leo_pcv_m: Callable | None = None, leo_antenna_frame=None,
                    sat_family=None,
                    sv_vel_m_s: np.ndarray | None = None,
                    leo_attitude: LeoAttitude | None = None, times=None) -> np.ndarray:
    """Range term ``a_b`` of one band for (epoch, satellite) pairs (module docstring) [m].

    Parameters
    ----------
    leo_pos_m, leo_vel_m_s : ndarray, shape (n, 3)
        Earth-fixed LEO centre of mass [m] and velocity [m/s].
    sv_pos_m : ndarray, shape (n, s, 3)
        Earth-fixed GNSS centres of mass [m].
    sun_m : ndarray, shape (n, 3)
        Earth-fixed Sun position [m].
    leo_pco_body_m : array_like, shape (3,)
        LEO PCO of the band in the body frame (X flight, Z to the geocentre) [m].
    sat_pco_body_m : ndarray, shape (s, 3), optional
        GNSS PCO of the band in the satellite body frame [m] (NaN rows: unknown).
    sat_pcv_m : callable, optional
        ``sat_pcv_m(column (k,), nadir_deg (k,)) -> (k,)`` [m]: GNSS PCV of the band.
    leo_pcv_m : callable, optional
        ``leo_pcv_m(el_deg (n, s), az_deg (n, s)) -> (n, s)`` [m]: LEO PCV of the band in the
        antenna frame of :func:`leopod.frames.attitude.antenna_el_az`.
    leo_antenna_frame : ndarray, shape (3, 3), optional
        Rows north, east, up of the LEO antenna frame in the body frame (the angles of
        ``leo_pcv_m``); None: north +X, up -Z.
    sat_family : ndarray of str, shape (s,), optional
        GNSS attitude family per satellite (:func:`leopod.gnss.attitude.satellite_families`);
        None: nominal yaw steering.
    sv_vel_m_s : ndarray, shape (n, s, 3), optional
        Inertial GNSS velocities in Earth-fixed axes [m/s] (with ``sat_family``).
    leo_attitude : LeoAttitude, optional
        Attitude law of the LEO; None: nominal.
    times : array_like of datetime64, shape (n,), optional
        Epochs (GPS time): needed by the ``file`` attitude law (its quaternions are inertial,
        rotated to the Earth-fixed frame at the epochs).

    Returns
    -------
    ndarray, shape (n, s)
        ``a_b`` [m]; NaN where a position is missing or a GNSS PCO is unknown.
    """
    if times is not None:
        rot = leo_body_axes_ef(leo_attitude, times, leo_pos_m, leo_vel_m_s, sun_m=sun_m)
    else:
        rot = leo_body_axes(leo_attitude, leo_pos_m,
                            inertial_velocity_ef(leo_pos_m, leo_vel_m_s), sun_m)  # (n, 3, 3)
    los = _unit(sv_pos_m - leo_pos_m[:, None, :])                           # (n, s, 3)
    pco_ef = body_to_ef(rot, np.asarray(leo_pco_body_m, dtype=float))       # (n, 3)
    term = -np.einsum("nsi,ni->ns", los, pco_ef)
    if sat_pco_body_m is not None or sat_pcv_m is not None:
        if sat_family is None:
            axes = gnss_body_axes(sv_pos_m, sun_m[:, None, :])              # (n, s, 3, 3)
        else:
            axes = gnss_attitude_axes(sv_pos_m, sv_vel_m_s, sun_m[:, None, :],
                                      np.broadcast_to(np.asarray(sat_family, dtype=object),
                                                      sv_pos_m.shape[:2]))
    if sat_pco_body_m is not None:
        pco_sv = np.einsum("nsij,si->nsj", axes, np.asarray(sat_pco_body_m, dtype=float))
        term = term + np.einsum("nsi,nsi->ns", los, pco_sv)
    if sat_pcv_m is not None:
        nadir = np.degrees(np.arccos(np.clip(-np.einsum("nsi,nsi->ns", los, axes[..., 2, :]),
                                             -1.0, 1.0)))
        ok = np.isfinite(nadir)
        cols = np.broadcast_to(np.arange(nadir.shape[1]), nadir.shape)
        pcv = np.full(nadir.shape, np.nan)
        pcv[ok] = sat_pcv_m(cols[ok], nadir[ok])
        term = term + pcv
    if leo_pcv_m is not None:
        el, az = antenna_el_az(np.einsum("nij,nsj->nsi", rot, los), leo_antenna_frame)
        term = term + leo_pcv_m(el, az)
    return term


def _satellite_band(antex, svs: Sequence[str], system: str, band: str, epoch):
    """ANTEX PCO (s, 3) and PCV function of one band of the satellites of one system."""
    freq = f"{system}{int(band):02d}"
    pco = np.full((len(svs), 3), np.nan)
    patterns = {}
    for j, sv in enumerate(svs):
        try:
            pattern = antex.satellite(str(sv), epoch)
            pco[j] = pattern.pco_m(freq)
        except KeyError:
            continue
        patterns[j] = pattern

    def pcv(col: np.ndarray, nadir_deg: np.ndarray) -> np.ndarray:
        out = np.full(nadir_deg.shape, np.nan)
        for j, pattern in patterns.items():
            sel = col == j
            if sel.any():
                out[sel] = pattern.pcv_m(freq, nadir_deg[sel], outside="nearest")
        return out

    return pco, pcv


def antenna_terms(times: np.ndarray, svs: Sequence[str], leo_pos_m: np.ndarray,
                  leo_vel_m_s: np.ndarray, sv_pos_m: np.ndarray, sun_m: np.ndarray,
                  bands: Mapping[str, Sequence[str]], leo_pco_body_m: Mapping | None, *,
                  antex=None, leo_pcv_m: Mapping[str, Callable] | None = None,
                  gnss_attitude: str = "nominal",
                  leo_attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Range terms of every band of every system for the (epoch, satellite) grid of a day.

    Parameters
    ----------
    times : ndarray of datetime64, shape (n,)
        Epochs (GPS time); the first selects the ANTEX entries.
    svs : sequence of str, shape (s,)
        Satellite ids (``"G05"``).
    leo_pos_m, leo_vel_m_s : ndarray, shape (n, 3)
        Earth-fixed LEO centre of mass [m] and velocity [m/s].
    sv_pos_m : ndarray, shape (n, s, 3)
        Earth-fixed GNSS centres of mass [m].
    sun_m : ndarray, shape (n, 3)
        Earth-fixed Sun position [m].
    bands : mapping
        System letter -> RINEX band digits whose terms are wanted (``{"G": ["1", "2"]}``).
    leo_pco_body_m : mapping or LeoAntenna or None
        LEO PCO per band name (``"L1"``, ``"B2a"``) in the body frame [m] (configuration
        ``satellites.<sat>.antenna_pco_body_m``), or an ANTEX antenna (its phase centres, and
        its PCV unless ``leo_pcv_m`` is given); None or empty: no LEO PCO.
    antex : leopod.io.antex.AntexFile, optional
        GNSS satellite antennas (PCO and PCV per frequency); None: centre of mass, as the POD.
    leo_pcv_m : mapping, optional
        Band name -> LEO PCV callable (see :func:`antenna_range_m`).
    gnss_attitude : str
        ``eclipse_models``: GNSS antennas oriented by the yaw law of each block (ANTEX type,
        :mod:`leopod.gnss.attitude`; velocities from the positions by central differences);
        ``nominal``: yaw steering (setting ``pod.gnss_attitude``, as the POD).
    leo_attitude : LeoAttitude, optional
        Attitude law of the LEO (``satellites.<sat>``); None: nominal.

    Returns
    -------
    xarray.Dataset
        ``antenna_range_<digit>_m`` (time, sv) [m], NaN for satellites of other systems; the
        attributes of :func:`antenna_attrs`.

    Raises
    ------
    ValueError
        If ``leo_pco_body_m`` is given but has no offset for a band (naming the field).
    """
    svs = [str(s) for s in svs]
    system_of = np.array([s[0] for s in svs])
    leo_pco = dict(leo_pco_body_m or {})
    frame = None
    if isinstance(leo_pco_body_m, LeoAntenna):
        frame = leo_pco_body_m.frame
        if leo_pcv_m is None and leo_pco_body_m.has_pcv:
            leo_pcv_m = {b: leo_pco_body_m.pcv_el_az(b) for b in leo_pco_body_m}
    epoch = np.datetime64(times[0], "ns")
    family = sv_vel = None
    if gnss_attitude == "eclipse_models" and antex is not None and len(times) > 1:
        family = satellite_families(antex, svs, epoch)
        t_s = (np.asarray(times, "datetime64[ns]") - epoch) / np.timedelta64(1, "s")
        sv_vel = (np.gradient(sv_pos_m, t_s, axis=0)
                  + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], sv_pos_m))
    out = {}
    for system, digits in bands.items():
        cols = np.flatnonzero(system_of == system)
        for digit in digits:
            name = signals.band(system, digit).name
            if leo_pco and name not in leo_pco:
                where = (f"LEO antenna {leo_pco_body_m.source}"
                         if isinstance(leo_pco_body_m, LeoAntenna) else "antenna_pco_body_m")
                raise ValueError(f"{where} has no offset for band {name} of "
                                 f"system {system} (it has {sorted(leo_pco)})")
            pco = leo_pco.get(name, (0.0, 0.0, 0.0))
            sat_pco = sat_pcv = None
            if antex is not None:
                sat_pco, sat_pcv = _satellite_band(antex, [svs[c] for c in cols], system,
                                                   digit, epoch)
            term = antenna_range_m(leo_pos_m, leo_vel_m_s, sv_pos_m[:, cols], sun_m, pco,
                                   sat_pco_body_m=sat_pco, sat_pcv_m=sat_pcv,
                                   leo_pcv_m=(leo_pcv_m or {}).get(name),
                                   leo_antenna_frame=frame,
                                   sat_family=None if family is None else family[cols],
                                   sv_vel_m_s=None if sv_vel is None else sv_vel[:, cols],
                                   leo_attitude=leo_attitude, times=times)
            key = VARIABLE.format(band=digit)
            if key not in out:
                out[key] = np.full((len(times), len(svs)), np.nan)
            out[key][:, cols] = term
    ds = xr.Dataset({k: (("time", "sv"), v, {
        "units": "m", "long_name": f"antenna range term of band {k.split('_')[2]}: range "
        "between the phase centres minus range between the centres of mass"})
        for k, v in out.items()}, coords={"time": times, "sv": svs})
    ds.attrs.update(antenna_attrs(leo_pco, antex, bands, leo_pcv=bool(leo_pcv_m)))
    if isinstance(leo_pco_body_m, LeoAntenna):
        ds.attrs["antenna_leo_antex"] = leo_pco_body_m.describe()
    ds.attrs["antenna_gnss_attitude"] = "nominal" if family is None else gnss_attitude
    if leo_attitude is not None:
        ds.attrs["antenna_leo_attitude"] = leo_attitude.describe()
    return ds


def antenna_attrs(leo_pco_body_m: Mapping | None, antex, bands: Mapping[str, Sequence[str]],
                  *, leo_pcv: bool = False) -> dict:
    """Attributes that say which antenna terms were removed, per frequency, with the sign."""
    leo = "; ".join(f"{k} {list(map(float, v))}" for k, v in sorted((leo_pco_body_m or
                                                                        {}).items()))
    source = "none (centre of mass)"
    if antex is not None:
        source = f"ANTEX {getattr(antex, 'path', '')}".strip()
    return {
        "antenna_terms": "removed per frequency from codes and phases before the HMW and MP "
                         "combinations: a_b = -e.(R_leo PCO_leo,b) + e.(R_sv PCO_sv,b) "
                         "+ PCV_sv,b(nadir)" + (" + PCV_leo,b(el, az)" if leo_pcv else "")
                         + "; observation - a_b",
        "antenna_bands": " ".join(f"{s}:{','.join(d)}" for s, d in sorted(bands.items())),
        "antenna_leo_pco_body_m": leo or "none",
        "antenna_leo_attitude": "nominal (Z to the geocentre, X along the inertial velocity)",
        "antenna_gnss": source,
        "antenna_leo_pcv": "given" if leo_pcv else "none",
    }


def remove_antenna_terms(obs: xr.Dataset, terms: xr.Dataset, names: Sequence[str]
                         ) -> xr.Dataset:
    """Observations minus the antenna range term of their band.

    Parameters
    ----------
    obs : xarray.Dataset
        Codes and phases in metres on (time, sv), named by RINEX 3 codes.
    terms : xarray.Dataset
        ``antenna_range_<digit>_m`` on (time, sv) (:func:`antenna_terms`, or the quality
        output that stores them); aligned to ``obs`` by label (missing: NaN).
    names : sequence of str
        Observation variables to correct (e.g. the phases and codes of HMW).

    Returns
    -------
    xarray.Dataset
        A copy of ``obs`` with ``names`` corrected; other variables unchanged.

    Raises
    ------
    KeyError
        If ``terms`` has no term for the band of one of ``names`` (naming both).
    """
    out = obs.copy()
    for name in dict.fromkeys(names):
        key = VARIABLE.format(band=signals.code_band(name))
        if key not in terms:
            raise KeyError(f"{terms.attrs.get('title', 'antenna terms')}: no {key} for "
                           f"{name} (has {sorted(v for v in terms.data_vars if 'antenna' in v)})")
        term = terms[key].reindex(time=obs.time, sv=obs.sv)
        out[name] = obs[name] - term.values
    return out
