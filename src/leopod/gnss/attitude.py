"""Nominal attitude of GNSS satellites and their antenna phase-centre offsets.

Yaw-steering attitude (IGS convention, Montenbruck et al. 2015, Adv. Space Res. 56:1015):
+Z points to the geocentre, +Y = Z × e_sun (along the solar-panel axis), +X = Y × Z completes
the frame so that +X points to the Sun-lit hemisphere. The antenna phase centre is
``r_com + x e_X + y e_Y + z e_Z`` with the ANTEX offset (x, y, z).

The Sun direction comes from the low-precision series of :mod:`leopod.astro.sun`.
"""

from __future__ import annotations

import numpy as np

from leopod.gnss.combinations import ionosphere_free

__all__ = ["gnss_body_axes", "satellite_pco_if"]


def gnss_body_axes(pos_m: np.ndarray, sun_m: np.ndarray) -> np.ndarray:
    """Yaw-steering body axes (rows X, Y, Z), shape (..., 3, 3), in the frame of the inputs.

    Parameters
    ----------
    pos_m : ndarray, shape (..., 3)
        Satellite positions [m].
    sun_m : ndarray, shape (..., 3)
        Sun positions in the same frame [m] (broadcast against ``pos_m``).
    """
    ez = -pos_m / np.linalg.norm(pos_m, axis=-1, keepdims=True)
    to_sun = sun_m - pos_m
    ey = np.cross(ez, to_sun)
    ey /= np.linalg.norm(ey, axis=-1, keepdims=True)
    ex = np.cross(ey, ez)
    return np.stack([ex, ey, ez], axis=-2)


def satellite_pco_if(antex, sv, epoch, system: str, bands: tuple[str, str],
                     f1_hz: float, f2_hz: float) -> np.ndarray:
    """Ionosphere-free phase-centre offsets of satellites in their body frame [m].

    Parameters
    ----------
    antex : leopod.io.antex.AntexFile
    sv : sequence of str, shape (s,)
        Satellite ids (``"G05"``).
    epoch : datetime64
        Epoch that selects the antenna entry valid for each PRN.
    system : str
        GNSS letter.
    bands : (str, str)
        RINEX band digits of the two frequencies (``("1", "2")``).
    f1_hz, f2_hz : float

    Returns
    -------
    ndarray, shape (s, 3)
        Body-frame offsets (x, y, z) [m]; NaN rows for satellites without an entry.
    """
    out = np.full((len(sv), 3), np.nan)
    for j, prn in enumerate(sv):
        try:
            pattern = antex.satellite(str(prn), epoch)
            p1 = pattern.pco_m(f"{system}{int(bands[0]):02d}")
            p2 = pattern.pco_m(f"{system}{int(bands[1]):02d}")
        except KeyError:
            continue
        out[j] = ionosphere_free(p1, p2, f1_hz, f2_hz)
    return out
