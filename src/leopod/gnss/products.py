"""GNSS satellite orbits and clocks from precise products, evaluated at arbitrary epochs.

Orbits (SP3, typically 5-15 min) are interpolated with 10th-order Lagrange polynomials;
clocks (RINEX clock, typically 30 s) are interpolated linearly between neighbouring samples
only, and never across a missing sample, so no clock value is invented beyond what the
product supports (a 30-s clock product gives exact values at its own epochs).

Orbit records that their producer marks as unusable are missing records here
(:func:`usable_positions`): those with the SP3 manoeuvre flag, those whose own standard
deviation (accuracy exponent) or whose satellite's header accuracy exceeds
:data:`MAX_ORBIT_SIGMA_M`; the "bad or absent" values 0.000000 and 999999.999999 are NaN
already (:func:`leopod.io.sp3.read_sp3`). The observations of such a satellite are then not
used near those records (the POD logs how many).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import xarray as xr

from leopod.numerics.interpolate import lagrange_weights
from leopod.time.calendar import seconds_since

__all__ = ["MAX_ORBIT_SIGMA_M", "GnssProducts", "usable_positions"]

log = logging.getLogger(__name__)

#: An orbit record (or a satellite's header accuracy) with a standard deviation above this
#: [m] is not used: IGS final and rapid orbits are accurate to a few cm, ultra-rapid
#: predictions to ~5 cm (IGS product table, igs.org/products), so an accuracy code of metres
#: marks a satellite its producer does not vouch for.
MAX_ORBIT_SIGMA_M = 1.0


def usable_positions(orbit: xr.Dataset) -> np.ndarray:
    """Positions ``pos_m`` (time, sv, xyz) [m] of an SP3 dataset (:func:`leopod.io.sp3.
    read_sp3`) with the records its producer marks as unusable set to NaN (module docstring);
    their number is logged."""
    pos = orbit.pos_m.transpose("time", "sv", "xyz").values.copy()
    bad = np.zeros(pos.shape[:2], dtype=bool)
    if "manoeuvre_flag" in orbit:
        bad |= orbit.manoeuvre_flag.transpose("time", "sv").values == 1
    if "pos_sigma_m" in orbit:
        bad |= (orbit.pos_sigma_m.transpose("time", "sv", "xyz").values
                > MAX_ORBIT_SIGMA_M).any(axis=2)
    if "orbit_accuracy_m" in orbit:
        bad |= (orbit.orbit_accuracy_m.values > MAX_ORBIT_SIGMA_M)[None, :]
    bad &= np.isfinite(pos).all(axis=2)
    if bad.any():
        svs, counts = np.unique(orbit.sv.values[np.nonzero(bad)[1]], return_counts=True)
        log.warning("GNSS orbits: %d records flagged (manoeuvre, or accuracy worse than "
                    "%g m) not used: %s", int(bad.sum()), MAX_ORBIT_SIGMA_M,
                    ", ".join(f"{sv} {n}" for sv, n in zip(svs, counts, strict=True)))
        pos[bad] = np.nan
    return pos


@dataclass
class GnssProducts:
    """Tabulated GNSS orbits and clocks on a common satellite axis.

    Attributes
    ----------
    ref : numpy.datetime64
        Reference epoch of all times below (GPS time).
    sv : ndarray of str, shape (s,)
        Satellite ids (``"G05"``).
    t_orbit_s : ndarray, shape (n,)
        Orbit table times [s since ref].
    pos_m : ndarray, shape (n, s, 3)
        Earth-fixed positions of the centres of mass [m] (NaN where missing).
    t_clock_s : ndarray, shape (k,)
        Clock table times [s since ref].
    clk_s : ndarray, shape (k, s)
        Satellite clock offsets [s] (NaN where missing).
    order : int
        Degree of the Lagrange polynomial of the orbit interpolation.
    max_extrapolation_s : float
        How far beyond the orbit table the edge polynomial may be used [s].
    attitude : ndarray of str, shape (s,), optional
        Attitude family per satellite (:func:`leopod.gnss.attitude.satellite_families`) for
        the eclipse/turn yaw laws; None: nominal yaw steering (``gnss_attitude: nominal``).
    """

    ref: np.datetime64
    sv: np.ndarray
    t_orbit_s: np.ndarray
    pos_m: np.ndarray
    t_clock_s: np.ndarray
    clk_s: np.ndarray
    order: int = 10
    max_extrapolation_s: float = 0.0
    attitude: np.ndarray | None = None

    @classmethod
    def from_datasets(cls, orbit: xr.Dataset, clock: xr.Dataset, ref, *, systems=None,
                      order: int = 10, max_extrapolation_s: float = 0.0) -> "GnssProducts":
        """Combine an SP3 Dataset (``pos_m``) and a clock Dataset (``clk_s``).

        Satellites present in the orbit file define the axis; clocks missing for a satellite
        are NaN. ``systems`` restricts to satellites whose id starts with one of the letters.
        Flagged orbit records are missing (:func:`usable_positions`).
        """
        sv = np.array(sorted(str(s) for s in orbit.sv.values
                             if systems is None or str(s)[0] in systems))
        pos = usable_positions(orbit.sel(sv=sv))
        clk = clock.clk_s.reindex(sv=sv).transpose("time", "sv").values
        return cls(ref=np.datetime64(ref, "ns"), sv=sv,
                   t_orbit_s=seconds_since(orbit.time.values, ref), pos_m=pos,
                   t_clock_s=seconds_since(clock.time.values, ref), clk_s=clk,
                   order=order, max_extrapolation_s=max_extrapolation_s)

    def sv_index(self, ids) -> np.ndarray:
        """Indices into :attr:`sv` of satellite ids (-1 where unknown)."""
        lookup = {s: k for k, s in enumerate(self.sv)}
        return np.array([lookup.get(str(s), -1) for s in np.atleast_1d(ids)], dtype=int)

    def position(self, isv: np.ndarray, t_s: np.ndarray):
        """Position and velocity of satellites at epochs.

        Parameters
        ----------
        isv : ndarray of int, shape (p,)
            Satellite indices (from :meth:`sv_index`).
        t_s : ndarray, shape (p,)
            Epochs [s since ref].

        Returns
        -------
        pos_m, vel_m_s : ndarray, shape (p, 3)
            Earth-fixed position [m] and its time derivative [m/s]; NaN outside the table
            (beyond ``max_extrapolation_s``) or where a node of the window is missing.
        extrapolated : ndarray of bool, shape (p,)
            True where the value is extrapolated beyond the table.
        """
        isv = np.asarray(isv, dtype=int)
        t_s = np.asarray(t_s, dtype=float)
        idx, w, dw = lagrange_weights(self.t_orbit_s, t_s, self.order)
        nodes = self.pos_m[idx, isv[:, None], :]                       # (p, k, 3)
        pos = np.einsum("pk,pkc->pc", w, nodes)
        vel = np.einsum("pk,pkc->pc", dw, nodes)
        t0, t1 = self.t_orbit_s[0], self.t_orbit_s[-1]
        extrapolated = (t_s < t0) | (t_s > t1)
        bad = ((t_s < t0 - self.max_extrapolation_s) | (t_s > t1 + self.max_extrapolation_s)
               | (isv < 0))
        pos[bad] = np.nan
        vel[bad] = np.nan
        return pos, vel, extrapolated

    def clock(self, isv: np.ndarray, t_s: np.ndarray) -> np.ndarray:
        """Satellite clock offsets [s] by linear interpolation between adjacent samples.

        NaN where the epoch is outside the table, a neighbour is missing, or the two
        neighbours are more than 1.5 nominal sampling intervals apart.
        """
        isv = np.asarray(isv, dtype=int)
        t_s = np.asarray(t_s, dtype=float)
        tc = self.t_clock_s
        step = np.median(np.diff(tc)) if len(tc) > 1 else np.inf
        j = np.clip(np.searchsorted(tc, t_s, side="right") - 1, 0, len(tc) - 2)
        t_a, t_b = tc[j], tc[j + 1]
        c_a, c_b = self.clk_s[j, isv], self.clk_s[j + 1, isv]
        frac = (t_s - t_a) / (t_b - t_a)
        out = c_a + frac * (c_b - c_a)
        exact_b = np.isclose(t_s, t_b, atol=1e-9)
        out = np.where(exact_b, c_b, out)
        exact_a = np.isclose(t_s, t_a, atol=1e-9)
        out = np.where(exact_a, c_a, out)
        bad = (t_s < tc[0] - 1e-9) | (t_s > tc[-1] + 1e-9) | (t_b - t_a > 1.5 * step) | (isv < 0)
        out[bad] = np.nan
        return out

    def clock_at_samples(self, t_s: np.ndarray) -> np.ndarray:
        """Clock table resampled to epochs: exact product values, NaN between samples.

        Returns
        -------
        ndarray, shape (m, s)
            ``clk_s`` at each epoch that coincides (within 1 µs) with a product epoch.
        """
        t_s = np.asarray(t_s, dtype=float)
        j = np.searchsorted(self.t_clock_s, t_s)
        j = np.clip(j, 0, len(self.t_clock_s) - 1)
        hit = np.abs(self.t_clock_s[j] - t_s) < 1e-6
        out = np.full((len(t_s), len(self.sv)), np.nan)
        out[hit] = self.clk_s[j[hit]]
        return out
