"""Linear combinations of dual-frequency code and phase, for any frequency pair.

All inputs and outputs are in metres (phase already multiplied by its wavelength); the
frequencies come from :mod:`leopod.signals`. Arrays broadcast in the numpy way.

References
----------
Peng et al. (2021), eq. (1) (MP), eqs. (3)/(6) (HMW); Wang et al. (2024), eqs. (14)-(15)
(ionospheric delay and its rate); Teunissen & Montenbruck (eds.), Springer Handbook of GNSS (2017),
ch. 20.
"""

from __future__ import annotations

import numpy as np

from leopod.constants import C_LIGHT_M_S

__all__ = [
    "ionosphere_free", "geometry_free", "melbourne_wuebbena", "multipath",
    "wide_lane_wavelength_m", "narrow_lane_wavelength_m", "ionosphere_l1_m",
]


def ionosphere_free(obs_1, obs_2, f1_hz: float, f2_hz: float):
    """Ionosphere-free combination ``(f1² o1 − f2² o2) / (f1² − f2²)`` [m].

    Parameters
    ----------
    obs_1, obs_2 : array_like
        Code or phase observations on frequency 1 and 2 [m].
    f1_hz, f2_hz : float
        Carrier frequencies [Hz].
    """
    g = (f1_hz / f2_hz) ** 2
    return (g * np.asarray(obs_1) - np.asarray(obs_2)) / (g - 1.0)


def geometry_free(obs_1, obs_2):
    """Geometry-free combination ``o1 − o2`` [m] (phase: ionosphere + ambiguities)."""
    return np.asarray(obs_1) - np.asarray(obs_2)


def melbourne_wuebbena(phase_1, phase_2, code_1, code_2, f1_hz: float, f2_hz: float):
    """Hatch–Melbourne–Wübbena combination [m]: wide-lane phase minus narrow-lane code.

    ``(f1 L1 − f2 L2)/(f1 − f2) − (f1 P1 + f2 P2)/(f1 + f2)``; free of geometry, clocks and
    first-order ionosphere. Divide by :func:`wide_lane_wavelength_m` for cycles.
    """
    wl = (f1_hz * np.asarray(phase_1) - f2_hz * np.asarray(phase_2)) / (f1_hz - f2_hz)
    nl = (f1_hz * np.asarray(code_1) + f2_hz * np.asarray(code_2)) / (f1_hz + f2_hz)
    return wl - nl


def multipath(code_i, phase_i, phase_j, fi_hz: float, fj_hz: float):
    """Code multipath combination MP_i [m] of Peng et al. (2021) eq. (1).

    ``MP_i = P_i − (fi² + fj²)/(fi² − fj²) Φ_i + 2 fj²/(fi² − fj²) Φ_j``.
    Free of geometry, clocks and first-order ionosphere; contains code multipath and noise
    plus a constant (ambiguities and phase biases) per continuous pass, which the caller
    removes by subtracting the pass mean.

    Parameters
    ----------
    code_i : array_like
        Code on frequency i [m].
    phase_i, phase_j : array_like
        Phase on frequencies i and j [m].
    fi_hz, fj_hz : float
        Frequencies of i and j [Hz].
    """
    d = fi_hz**2 - fj_hz**2
    return (np.asarray(code_i) - (fi_hz**2 + fj_hz**2) / d * np.asarray(phase_i)
            + 2.0 * fj_hz**2 / d * np.asarray(phase_j))


def ionosphere_l1_m(phase_1, phase_2, f1_hz: float, f2_hz: float):
    """First-order ionospheric delay on frequency 1 from phase [m] (Wang et al. 2024, eq. 14).

    Phase is advanced by the ionosphere (``Φ_k = ρ − I_k + ...`` with ``I_2 = (f1/f2)² I_1``),
    so ``Φ1 − Φ2 = I1 (f1² − f2²)/f2²`` and ``I1 = f2²/(f1² − f2²) (Φ1 − Φ2)``. The result
    contains a constant ambiguity term per pass, so only its time variation (IOD, Wang et al. 2024
    eq. 15) is meaningful without levelling.
    """
    return f2_hz**2 / (f1_hz**2 - f2_hz**2) * (np.asarray(phase_1) - np.asarray(phase_2))


def wide_lane_wavelength_m(f1_hz: float, f2_hz: float) -> float:
    """Wide-lane wavelength ``c/(f1 − f2)`` [m] (GPS L1/L2: 0.862 m)."""
    return C_LIGHT_M_S / (f1_hz - f2_hz)


def narrow_lane_wavelength_m(f1_hz: float, f2_hz: float) -> float:
    """Narrow-lane wavelength ``c/(f1 + f2)`` [m] (GPS L1/L2: 0.107 m)."""
    return C_LIGHT_M_S / (f1_hz + f2_hz)
