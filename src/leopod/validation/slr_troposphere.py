"""Tropospheric delay of laser ranging: Mendes–Pavlis zenith delay and FCULa mapping function.

IERS Conventions 2010, sec. 9.2.1 (Mendes & Pavlis 2004; Mendes et al. 2002), at optical
wavelengths, from the surface pressure, temperature and relative humidity; the water vapour
pressure follows Giacomo (1982) with the CIPM-81/91 constants (Davis 1992). Used by
:func:`leopod.validation.slr_model.slr_range`.

References
----------
1. Petit, G. & Luzum, B. (eds.) (2010). IERS Conventions (2010), IERS Technical Note 36.
2. Mendes, V.B. & Pavlis, E.C. (2004). High-accuracy zenith delay prediction at optical
   wavelengths. Geophys. Res. Lett. 31, L14602, doi:10.1029/2004GL020308.
3. Mendes, V.B., Prates, G., Pavlis, E.C., Pavlis, D.E. & Langley, R.B. (2002). Improved
   mapping functions for atmospheric refraction correction in SLR. Geophys. Res. Lett. 29(10),
   1414, doi:10.1029/2001GL014394.
4. Giacomo, P. (1982). Equation for the determination of the density of moist air (1981).
   Metrologia 18, 33–40; Davis, R.S. (1992), Metrologia 29, 67–70 (CIPM-81/91 constants).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "fcula_mapping",
    "mendes_pavlis_delay_m",
    "saturation_vapour_pressure_hpa",
    "water_vapour_pressure_hpa",
    "zenith_delay_m",
]

#: Dispersion constants of the hydrostatic refractivity [µm⁻²] (k0, k1*, k2, k3*), Mendes &
#: Pavlis (2004) eq. (20) (Ciddor 1996); IERS Conventions 2010, sec. 9.2.1.
_MP_K_UM2 = (238.0185, 19990.975, 57.362, 579.55174)
#: Dispersion constants of the non-hydrostatic refractivity (ω0..ω3 [µm^0, ^-2, ^-4, ^-6]),
#: Mendes & Pavlis (2004) eq. (32).
_MP_W = (295.235, 2.6422, -0.032380, 0.004028)
#: CO2 content [ppm] (IAG 1999 recommendation) and its correction factor 1 + 0.534e-6 (x_c − 450),
#: Mendes & Pavlis (2004), sec. 2.
_MP_CO2_PPM = 375.0
_MP_CO2_FACTOR = 1.0 + 0.534e-6 * (_MP_CO2_PPM - 450.0)
#: Zenith hydrostatic delay per hPa [m/hPa], Mendes & Pavlis (2004) eq. (26).
_MP_ZHD_M_HPA = 2.416579e-3
#: Zenith non-hydrostatic delay coefficients [m/hPa] of f_nh and f_h, eq. (38).
_MP_ZWD_NH_M_HPA = 5.316e-4
_MP_ZWD_H_M_HPA = 3.759e-4
#: Site function f_s(φ, H) = 1 − 0.00266 cos 2φ − 0.28e-6 H[m], Mendes & Pavlis (2004) eq. (24).
_MP_SITE_COS2PHI = 0.00266
_MP_SITE_PER_M = 0.28e-6
#: FCULa coefficients a_i = a_i0 + a_i1 t[°C] + a_i2 cos φ + a_i3 H[m], rows i = 1, 2, 3
#: (Mendes et al. 2002; IERS Conventions 2010, Table 9.1 and software FCUL_A.F).
_FCULA = np.array([
    [0.121008e-02, 0.17295e-05, 0.3191e-04, -0.18478e-07],
    [0.304965e-02, 0.2346e-05, -0.1035e-03, -0.1856e-07],
    [0.68777e-01, 0.1972e-04, -0.3458e-02, 0.1060e-06],
])
#: Saturation vapour pressure over water, exp(A T² + B T + C + D/T) [Pa] with T [K]
#: (Giacomo 1982 with the CIPM-81/91 constants of Davis 1992).
_SVP_A, _SVP_B, _SVP_C, _SVP_D = 1.2378847e-5, -1.9121316e-2, 33.93711047, -6.3431645e3
#: Enhancement factor f_w = α + β P + γ t², P [hPa], t [°C] (Giacomo 1982; β = 3.14e-8 /Pa).
_ENH_ALPHA, _ENH_BETA_HPA, _ENH_GAMMA = 1.00062, 3.14e-6, 5.6e-7
_KELVIN_0C = 273.15
_PA_PER_HPA = 100.0



def saturation_vapour_pressure_hpa(temperature_k):
    """Saturation water vapour pressure over a plane water surface [hPa].

    ``e_sat = exp(A T² + B T + C + D / T)`` [Pa] (Giacomo 1982, constants of Davis 1992).

    Parameters
    ----------
    temperature_k : array_like
        Air temperature [K].
    """
    t = np.asarray(temperature_k, dtype=float)
    return np.exp(_SVP_A * t**2 + _SVP_B * t + _SVP_C + _SVP_D / t) / _PA_PER_HPA


def water_vapour_pressure_hpa(temperature_k, humidity_pct, pressure_hpa):
    """Partial water vapour pressure from relative humidity [hPa].

    ``e = (RH / 100) f_w e_sat`` with the enhancement factor
    ``f_w = 1.00062 + 3.14e-6 P + 5.6e-7 (T − 273.15)²`` (Giacomo 1982; the conversion used
    with the Mendes–Pavlis model, IERS Conventions 2010, sec. 9.2.1).

    Parameters
    ----------
    temperature_k : array_like
        Air temperature [K].
    humidity_pct : array_like
        Relative humidity [%].
    pressure_hpa : array_like
        Total surface pressure [hPa].
    """
    t_c = np.asarray(temperature_k, dtype=float) - _KELVIN_0C
    f_w = _ENH_ALPHA + _ENH_BETA_HPA * np.asarray(pressure_hpa, dtype=float) + _ENH_GAMMA * t_c**2
    return np.asarray(humidity_pct, dtype=float) / 100.0 * f_w * saturation_vapour_pressure_hpa(
        temperature_k)


def _site_function(lat_rad, height_m):
    """f_s(φ, H) of Mendes & Pavlis (2004) eq. (24) (IERS Conventions 2010, sec. 9.2.1)."""
    return (1.0 - _MP_SITE_COS2PHI * np.cos(2.0 * np.asarray(lat_rad, dtype=float))
            - _MP_SITE_PER_M * np.asarray(height_m, dtype=float))


def _dispersion(wavelength_um):
    """Hydrostatic and non-hydrostatic dispersion f_h(λ), f_nh(λ), MP 2004 eqs. (20), (32)."""
    s2 = (1.0 / np.asarray(wavelength_um, dtype=float)) ** 2
    k0, k1, k2, k3 = _MP_K_UM2
    f_h = 0.01 * _MP_CO2_FACTOR * (k1 * (k0 + s2) / (k0 - s2) ** 2 + k3 * (k2 + s2) / (k2 - s2) ** 2)
    w0, w1, w2, w3 = _MP_W
    f_nh = 0.003101 * (w0 + 3.0 * w1 * s2 + 5.0 * w2 * s2**2 + 7.0 * w3 * s2**3)
    return f_h, f_nh


def zenith_delay_m(lat_rad, height_m, pressure_hpa, wvp_hpa, wavelength_um):
    """Mendes–Pavlis zenith hydrostatic and non-hydrostatic delays at optical wavelengths.

    ``d_h = 0.002416579 f_h(λ) P / f_s(φ, H)`` and
    ``d_nh = 1e-4 (5.316 f_nh(λ) − 3.759 f_h(λ)) e / f_s(φ, H)``
    (Mendes & Pavlis 2004, eqs. 20–38; IERS Conventions 2010, sec. 9.2.1). Valid for
    wavelengths 0.355–1.064 µm.

    Parameters
    ----------
    lat_rad : array_like
        Geodetic latitude [rad].
    height_m : array_like
        Height above the ellipsoid [m].
    pressure_hpa : array_like
        Surface pressure [hPa].
    wvp_hpa : array_like
        Surface water vapour pressure [hPa] (:func:`water_vapour_pressure_hpa`).
    wavelength_um : array_like
        Laser wavelength [µm].

    Returns
    -------
    zhd_m, zwd_m : ndarray
        Zenith hydrostatic and non-hydrostatic delays [m] (one way); their sum is the zenith
        total delay.
    """
    f_s = _site_function(lat_rad, height_m)
    f_h, f_nh = _dispersion(wavelength_um)
    zhd = _MP_ZHD_M_HPA * f_h * np.asarray(pressure_hpa, dtype=float) / f_s
    zwd = (_MP_ZWD_NH_M_HPA * f_nh - _MP_ZWD_H_M_HPA * f_h) * np.asarray(wvp_hpa, dtype=float) / f_s
    return zhd, zwd


def fcula_mapping(el_rad, lat_rad, height_m, temperature_k):
    """FCULa mapping function of the total zenith delay (Mendes et al. 2002).

    ``m(ε) = (1 + a1/(1 + a2/(1 + a3))) / (sin ε + a1/(sin ε + a2/(sin ε + a3)))`` with
    ``a_i = a_i0 + a_i1 t + a_i2 cos φ + a_i3 H`` (t in °C, H in m) (IERS Conventions 2010,
    sec. 9.2.1 and Table 9.1). ``m(90°) = 1``; valid down to ~3° elevation.

    Parameters
    ----------
    el_rad : array_like
        Geometric (vacuum) elevation of the target [rad].
    lat_rad : array_like
        Geodetic latitude [rad].
    height_m : array_like
        Station height [m].
    temperature_k : array_like
        Surface temperature [K].

    Returns
    -------
    ndarray
        Mapping factor (dimensionless).
    """
    t_c = np.asarray(temperature_k, dtype=float) - _KELVIN_0C
    cos_lat = np.cos(np.asarray(lat_rad, dtype=float))
    h = np.asarray(height_m, dtype=float)
    a1, a2, a3 = (c[0] + c[1] * t_c + c[2] * cos_lat + c[3] * h for c in _FCULA)
    s = np.sin(np.asarray(el_rad, dtype=float))
    return (1.0 + a1 / (1.0 + a2 / (1.0 + a3))) / (s + a1 / (s + a2 / (s + a3)))


def mendes_pavlis_delay_m(el_rad, lat_rad, height_m, pressure_hpa, temperature_k, humidity_pct,
                          wavelength_um):
    """One-way tropospheric delay of a laser range: Mendes–Pavlis zenith delay × FCULa.

    ``d = (d_h + d_nh) · m_FCULa(ε)`` (IERS Conventions 2010, sec. 9.2.1), the water vapour
    pressure from relative humidity by :func:`water_vapour_pressure_hpa`.

    Parameters
    ----------
    el_rad : array_like
        Geometric elevation [rad].
    lat_rad : array_like
        Geodetic latitude [rad].
    height_m : array_like
        Height above the ellipsoid [m].
    pressure_hpa, temperature_k, humidity_pct : array_like
        Surface pressure [hPa], temperature [K] and relative humidity [%] at the station.
    wavelength_um : array_like
        Laser wavelength [µm].

    Returns
    -------
    ndarray
        Delay [m] (one way), broadcast shape of the inputs.
    """
    wvp = water_vapour_pressure_hpa(temperature_k, humidity_pct, pressure_hpa)
    zhd, zwd = zenith_delay_m(lat_rad, height_m, pressure_hpa, wvp, wavelength_um)
    return (zhd + zwd) * fcula_mapping(el_rad, lat_rad, height_m, temperature_k)
