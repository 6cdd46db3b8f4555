"""Orbit comparison in the radial, along-track and cross-track frame.

Used for orbit overlaps of consecutive arcs (Jiang et al. 2023, "Internal consistency validation";
:mod:`.overlap`) and for comparisons with external orbits (Wang et al. 2024, sec. 3.4.2 and Table 4,
Jiang et al. 2023, Figs. 17, 18: the precise science orbits / DORIS orbits of CNES).

External-orbit comparison (:func:`compare_orbits`)
    1. The reference's time labels are converted to GPS time (:func:`to_gps_time`: TAI = GPST
       + 19 s and TT = GPST + 51.184 s exactly, UTC with the leap seconds; Wang et al. 2024 converts
       the TAI-labelled CNES orbits to GPST the same way), plus an optional extra offset.
    2. The reference is interpolated onto the orbit's epochs (:func:`interpolate_orbit`,
       Lagrange, Montenbruck & Gill 2000 sec. 4.1) without crossing data gaps.
    3. Optionally a 3-, 6- or 7-parameter Helmert transformation from the reference to the
       orbit is estimated and removed (:func:`leopod.validation.helmert.fit_helmert`, IERS
       Conventions 2010 eq. 4.4).
    4. The differences ``orbit − reference`` are rotated into the RTN axes (radial,
       along-track, cross-track) of the reference's *inertial* state (:func:`rtn_axes`): the
       along-track axis follows the inertial velocity, i.e. the orbital motion, as in
       Wang et al. (2024) sec. 3.4.3 (RTN built in the J2000 frame). Earth-fixed velocities would
       tilt the T/N axes by up to ``ω r / v`` ≈ 3.7° for a LEO.
    5. :func:`leopod.validation.orbit_statistics.orbit_statistics` gives mean, STD and RMS of
       R, T, N and 3D per GPS day and in total (Wang et al. 2024, Table 4; Jiang et al. 2023,
       Fig. 18); :func:`leopod.validation.orbit_statistics.statistics_table` flattens them
       for CSV.

:func:`difference_rtn` and :func:`rms_rtn` are the simple forms used by the workflow tests:
common epochs only, RTN axes of the reference in the frame of the compared variables.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from leopod.constants import OMEGA_EARTH_RAD_S
from leopod.frames.rtn import rtn_axes, rtn_matrix
from leopod.numerics.interpolate import interpolate_table
from leopod.time import scales
from leopod.time.calendar import seconds_since
from leopod.validation.helmert import (
    _HELMERT_UNITS,
    HELMERT_PARAMETERS,
    fit_helmert,
    helmert_displacement,
)

__all__ = [
    "compare_orbits",
    "difference_rtn",
    "fit_time_offset",
    "interpolate_orbit",
    "orbit_from_sp3",
    "rms_rtn",
    "to_gps_time",
]

_FRAME_VARIABLES = {"itrf": ("pos_itrf_m", "vel_itrf_m_s"), "gcrf": ("pos_gcrf_m", "vel_gcrf_m_s")}
#: Default largest node spacing inside an interpolation window, in median node spacings
#: (one missing node is bridged, two are not).
_GAP_FACTOR = 2.0
_NS_PER_S = 1_000_000_000
#: Convergence threshold of the time-offset iteration [s].
_TIME_OFFSET_TOL_S = 1e-9
_RTN_ATTRS = {"units": "m", "long_name": "orbit minus reference in radial, along-track, "
              "cross-track"}


# --------------------------------------------------------------------------- simple forms
def difference_rtn(orbit: xr.Dataset, reference: xr.Dataset, *, pos: str = "pos_itrf_m",
                   vel: str = "vel_itrf_m_s", start=None, end=None) -> xr.Dataset:
    """Position differences ``orbit − reference`` in the reference's RTN axes.

    The axes are built from ``pos``/``vel``; for ITRF variables (names containing ``itrf``)
    the velocity is made inertial in direction by adding ``ω × r`` (Earth rotation about
    the ITRF Z axis; the neglected polar motion and precession tilt the axes by < 1e-5 rad),
    so T and N are the along-track and cross-track of the orbit plane as in
    :func:`compare_orbits`, which also interpolates.

    Parameters
    ----------
    orbit, reference : xarray.Dataset
        Orbits with ``time`` and ``pos``/``vel`` (time, xyz) in the same frame [m, m/s].
    pos, vel : str
        Variable names.
    start, end : datetime64, optional
        Restrict to this window (inclusive).

    Returns
    -------
    xarray.Dataset
        ``diff_rtn_m`` (time, rtn) at the common epochs [m].
    """
    common = np.intersect1d(orbit.time.values, reference.time.values)
    if start is not None:
        common = common[common >= np.datetime64(start, "ns")]
    if end is not None:
        common = common[common <= np.datetime64(end, "ns")]
    if common.size == 0:
        raise ValueError("the orbits have no common epochs in the window")
    a = orbit[pos].sel(time=common).values
    ref = reference.sel(time=common)
    ref_pos, ref_vel = ref[pos].values, ref[vel].values
    if "itrf" in pos:
        ref_vel = ref_vel + np.cross([0.0, 0.0, OMEGA_EARTH_RAD_S], ref_pos)
    rtn = rtn_matrix(ref_pos, ref_vel)
    diff = np.einsum("nij,nj->ni", rtn, a - ref_pos)
    return xr.Dataset({"diff_rtn_m": (("time", "rtn"), diff, dict(_RTN_ATTRS))},
                      coords={"time": common, "rtn": ["R", "T", "N"]})


def rms_rtn(diff: xr.Dataset) -> dict[str, float]:
    """RMS of R, T, N and 3D [m] of a :func:`difference_rtn` result (finite rows)."""
    d = diff.diff_rtn_m.values
    d = d[np.isfinite(d).all(axis=1)]
    r = np.sqrt(np.mean(d**2, axis=0))
    return {"R": float(r[0]), "T": float(r[1]), "N": float(r[2]),
            "3D": float(np.sqrt(np.sum(r**2)))}


def orbit_from_sp3(sp3: xr.Dataset, sv: str) -> xr.Dataset:
    """One satellite of a :func:`leopod.io.sp3.read_sp3` Dataset in the orbit schema.

    Parameters
    ----------
    sp3 : xarray.Dataset
        ``pos_m`` (and ``vel_m_s`` for SP3 with V records) (time, sv, xyz) [m, m/s],
        Earth-fixed.
    sv : str
        Satellite id, e.g. ``"L47"``.

    Returns
    -------
    xarray.Dataset
        ``pos_itrf_m`` (and ``vel_itrf_m_s``) (time, xyz); attrs ``time_system`` of the file.
    """
    data = {"pos_itrf_m": (("time", "xyz"), sp3.pos_m.sel(sv=sv).transpose("time", "xyz").values,
                           {"units": "m", "long_name": "position"})}
    if "vel_m_s" in sp3:
        data["vel_itrf_m_s"] = (("time", "xyz"),
                                sp3.vel_m_s.sel(sv=sv).transpose("time", "xyz").values,
                                {"units": "m s-1", "long_name": "Earth-fixed velocity"})
    return xr.Dataset(data, coords={"time": sp3.time.values, "xyz": ["x", "y", "z"]},
                      attrs={"time_system": str(sp3.attrs.get("time_system", "GPS")),
                             "reference_frame": str(sp3.attrs.get("coordinate_system", ""))})


# --------------------------------------------------------------------------- time and epochs
def to_gps_time(times, time_system: str = "GPS", *, offset_s: float = 0.0) -> np.ndarray:
    """GPS-time labels of epochs labelled in another time system, plus an extra offset.

    ``GPS = TAI − 19 s`` and ``GPS = TT − 51.184 s`` exactly (IERS Conventions 2010, ch. 10;
    IS-GPS-200); UTC labels use the leap seconds of :func:`leopod.time.scales.utc_to_gps`.

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        Labels in ``time_system``.
    time_system : {"GPS", "TAI", "TT", "UTC", "BDT", "GAL"}
        Time system of the labels (case-insensitive; :func:`leopod.time.scales.to_gps_time`,
        which also gives BDT = GPST - 14 s and GST = GPST).
    offset_s : float
        Added after the conversion [s] (e.g. an estimated timing offset, :func:`fit_time_offset`).

    Returns
    -------
    ndarray of datetime64[ns], shape (n,)
    """
    t = scales.to_gps_time(times, time_system)
    return t + np.timedelta64(round(offset_s * _NS_PER_S), "ns")


def interpolate_orbit(orbit: xr.Dataset, times, *, pos: str = "pos_itrf_m",
                      vel: str = "vel_itrf_m_s", order: int = 10,
                      max_gap_s: float | None = None) -> xr.Dataset:
    """Positions and velocities of a tabulated orbit at other epochs (Lagrange).

    Each query uses the ``order + 1`` nearest valid nodes (:func:`interpolate_table`,
    Montenbruck & Gill 2000 sec. 4.1); at a node the tabulated value is returned exactly.
    Nodes with non-finite positions are dropped first, so they act as gaps.

    Parameters
    ----------
    orbit : xarray.Dataset
        ``time`` and ``pos`` (time, xyz) [m]; ``vel`` (time, xyz) [m/s] is interpolated too when
        present, otherwise the velocity is the derivative of the position polynomial.
    times : array_like of datetime64, shape (m,)
        Query epochs, same time system as ``orbit.time``.
    pos, vel : str
        Variable names.
    order : int
        Polynomial degree (default 10: 11 nodes).
    max_gap_s : float, optional
        Queries whose window spans a node spacing larger than this are NaN [s]. Default:
        twice the median node spacing (bridges one missing node). Queries outside the
        table are NaN (no extrapolation).

    Returns
    -------
    xarray.Dataset
        ``pos`` and ``vel`` (time, xyz) at ``times`` (NaN where not interpolable).
    """
    times = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
    p = orbit[pos].transpose("time", "xyz").values
    has_vel = vel in orbit
    values = np.concatenate([p, orbit[vel].transpose("time", "xyz").values], axis=1) \
        if has_vel else p
    ok = np.isfinite(values).all(axis=1)
    if ok.sum() < order + 1:
        raise ValueError(f"the orbit has {ok.sum()} valid epochs; interpolation of order "
                         f"{order} needs {order + 1}")
    t0 = orbit.time.values[ok][0]
    t_nodes = seconds_since(orbit.time.values[ok], t0)
    if max_gap_s is None:
        max_gap_s = _GAP_FACTOR * float(np.median(np.diff(t_nodes))) * (1.0 + 1e-9)
    val, rate = interpolate_table(t_nodes, values[ok], seconds_since(times, t0), order,
                                  max_gap_s=max_gap_s)
    pos_q, vel_q = (val[:, :3], val[:, 3:]) if has_vel else (val, rate)
    frame = {k: v for k, v in orbit[pos].attrs.items() if k == "reference_frame"}
    return xr.Dataset(
        {pos: (("time", "xyz"), pos_q, {"units": "m", "long_name": "interpolated position",
                                         **frame}),
         vel: (("time", "xyz"), vel_q, {"units": "m s-1", "long_name": "interpolated velocity",
                                         **frame})},
        coords={"time": times, "xyz": ["x", "y", "z"]},
        attrs={"interpolation_order": order, "max_gap_s": max_gap_s,
               "velocity_source": "tabulated" if has_vel else "position polynomial"})


# --------------------------------------------------------------------------- comparison
def _window(times: np.ndarray, start, end) -> np.ndarray:
    keep = np.ones(times.size, dtype=bool)
    if start is not None:
        keep &= times >= np.datetime64(start, "ns")
    if end is not None:
        keep &= times <= np.datetime64(end, "ns")
    if not keep.any():
        raise ValueError("the orbit has no epochs in the window")
    return keep


def _reference_in_gps(reference: xr.Dataset, time_system: str | None,
                      time_offset_s: float) -> tuple[xr.Dataset, str]:
    system = time_system or str(reference.attrs.get("time_system", "GPS"))
    return reference.assign_coords(time=to_gps_time(reference.time.values, system,
                                                    offset_s=time_offset_s)), system


def _variables(frame: str) -> tuple[str, str]:
    try:
        return _FRAME_VARIABLES[frame]
    except KeyError:
        raise ValueError(f"frame must be one of {sorted(_FRAME_VARIABLES)}, not {frame!r}") \
            from None


def fit_time_offset(orbit: xr.Dataset, reference: xr.Dataset, *, frame: str = "itrf",
                    reference_time_system: str | None = None, order: int = 10,
                    max_gap_s: float | None = None, start=None, end=None,
                    max_iterations: int = 10) -> float:
    """Timing offset of a reference orbit by least squares along its velocity.

    Finds the ``offset_s`` for which ``to_gps_time(labels, system, offset_s=offset_s)`` makes
    the reference coincide best with the orbit: with ``d = orbit(t) − ref(t − δ)`` and
    ``∂ref(t − δ)/∂δ = −v``, each Gauss–Newton step is ``Δδ = −Σ v·d / Σ v·v``, repeated with
    re-interpolation until ``|Δδ| < 1 ns``.

    Parameters
    ----------
    orbit, reference : xarray.Dataset
        As for :func:`compare_orbits`.
    frame, reference_time_system, order, max_gap_s, start, end
        As for :func:`compare_orbits`.
    max_iterations : int
        Upper limit of Gauss–Newton steps.

    Returns
    -------
    float
        Offset [s] to pass as ``time_offset_s`` to :func:`compare_orbits`.
    """
    pos, vel = _variables(frame)
    keep = _window(orbit.time.values, start, end)
    times = orbit.time.values[keep]
    p = orbit[pos].transpose("time", "xyz").values[keep]
    offset = 0.0
    for _ in range(max_iterations):
        ref, _ = _reference_in_gps(reference, reference_time_system, offset)
        r = interpolate_orbit(ref, times, pos=pos, vel=vel, order=order, max_gap_s=max_gap_s)
        d = p - r[pos].values
        v = r[vel].values
        ok = np.isfinite(d).all(axis=1) & np.isfinite(v).all(axis=1)
        if not ok.any():
            raise ValueError("the orbit and the reference have no common span")
        step = -float(np.sum(v[ok] * d[ok]) / np.sum(v[ok] * v[ok]))
        offset += step
        if abs(step) < _TIME_OFFSET_TOL_S:
            break
    return offset


def compare_orbits(orbit: xr.Dataset, reference: xr.Dataset, *, frame: str = "itrf",
                   reference_time_system: str | None = None, time_offset_s: float = 0.0,
                   order: int = 10, max_gap_s: float | None = None, helmert: int | None = None,
                   start=None, end=None, eop=None) -> xr.Dataset:
    """Differences ``orbit − reference`` in inertial RTN axes at the orbit's epochs.

    Parameters
    ----------
    orbit : xarray.Dataset
        Orbit to validate: ``time`` (GPS) and ``pos_<frame>_m``, ``vel_<frame>_m_s``
        (time, xyz) [m, m/s] (the POD orbit schema of :mod:`leopod.estimation.outputs`).
    reference : xarray.Dataset
        Reference orbit in the same schema (velocity optional); e.g. :func:`leopod.io.sp3.read_sp3`
        output turned into it with ``pos_itrf_m=sp3.pos_m.sel(sv=...)``.
    frame : {"itrf", "gcrf"}
        Frame of the compared variables (and of the Helmert transformation).
    reference_time_system : {"GPS", "TAI", "TT", "UTC"}, optional
        Time system of the reference's labels; default ``reference.attrs["time_system"]``,
        else GPS.
    time_offset_s : float
        Extra offset added to the reference's GPS-converted labels [s] (see
        :func:`fit_time_offset`).
    order : int
        Lagrange degree of the interpolation of the reference (default 10).
    max_gap_s : float, optional
        Largest node spacing inside an interpolation window [s]; default twice the median
        spacing of the reference.
    helmert : {None, 3, 6, 7}
        Estimate and remove a Helmert transformation reference → orbit with this many
        parameters (translations; + rotations; + scale).
    start, end : datetime64, optional
        Window of orbit epochs (inclusive).
    eop : EarthOrientation, optional
        EOP source of the ITRF → GCRF rotation of the RTN axes.

    Returns
    -------
    xarray.Dataset
        ``diff_rtn_m`` (time, rtn) [m] and ``diff_3d_m`` (time) [m] at the orbit's epochs in the
        window (NaN where the reference is not available); with ``helmert``:
        ``helmert_estimate`` and ``helmert_sigma`` (helmert_parameter), units per parameter in
        the ``helmert_unit`` coordinate. Attributes record the reference time system, offset,
        interpolation, frame and the number of epochs without reference.
    """
    pos, vel = _variables(frame)
    keep = _window(orbit.time.values, start, end)
    times = orbit.time.values[keep]
    ref, system = _reference_in_gps(reference, reference_time_system, time_offset_s)
    r = interpolate_orbit(ref, times, pos=pos, vel=vel, order=order, max_gap_s=max_gap_s)
    p = orbit[pos].transpose("time", "xyz").values[keep]
    ref_p, ref_v = r[pos].values, r[vel].values
    diff = p - ref_p
    ok = np.isfinite(diff).all(axis=1) & np.isfinite(ref_v).all(axis=1)
    if not ok.any():
        raise ValueError("the orbit and the reference have no common span")
    data = {}
    coords = {"time": times, "rtn": ["R", "T", "N"]}
    if helmert is not None:
        estimate, sigma = fit_helmert(p[ok], ref_p[ok], helmert)
        diff[ok] -= helmert_displacement(estimate, ref_p[ok])
        data["helmert_estimate"] = ("helmert_parameter", estimate, {
            "units": "1", "long_name": "Helmert transformation reference to orbit, IERS "
            "Conventions 2010 eq. 4.4 (unit per parameter in helmert_unit)"})
        data["helmert_sigma"] = ("helmert_parameter", sigma, {
            "units": "1", "long_name": "formal standard deviation of the Helmert parameters"})
        coords["helmert_parameter"] = list(HELMERT_PARAMETERS)
        coords["helmert_unit"] = ("helmert_parameter", list(_HELMERT_UNITS))
    diff_rtn = np.full_like(diff, np.nan)
    axes = rtn_axes(times[ok], ref_p[ok], ref_v[ok], frame=frame, eop=eop)
    diff_rtn[ok] = np.einsum("nij,nj->ni", axes, diff[ok])
    data["diff_rtn_m"] = (("time", "rtn"), diff_rtn, dict(_RTN_ATTRS))
    data["diff_3d_m"] = ("time", np.linalg.norm(diff_rtn, axis=1),
                         {"units": "m", "long_name": "3D distance orbit to reference"})
    return xr.Dataset(data, coords=coords, attrs={
        "difference": "orbit - reference", "frame": frame,
        "rtn_axes": "inertial RTN of the reference",
        "reference_time_system": system, "time_offset_s": float(time_offset_s),
        "interpolation_order": order, "max_gap_s": float(r.attrs["max_gap_s"]),
        "helmert_parameters": int(helmert or 0), "n_epochs_without_reference": int((~ok).sum())})
