"""BDS-2 satellite-induced code bias (SCB): the Wanninger & Beer (2015) correction model.

The codes of the BDS-2 IGSO and MEO satellites carry a delay that varies by up to about 1 m
with the direction of the signal leaving the satellite; on the BDS-3 satellites it is much
reduced (Zhang et al. 2017) and not corrected. Wanninger & Beer (2015, Table 2) give corrections per satellite type
(IGSO, MEO) and frequency (B1, B2, B3) at elevation nodes 0°, 10°, …, 90° of a receiver on
the ground, to be interpolated linearly and *added* to the observed code::

    P_corrected = P_observed + Δ(type, band, e)

The BDS SCB-AR paper (eq. 1) writes the same model as ``P = ρ + I − d(E)``: ``d`` is ``Δ``.
The SCB leaves the phases alone; in the HMW combination it adds
``(f1 d1 + f2 d2) / ((f1 + f2) λ_WL)`` cycles (BDS SCB-AR paper, eq. 5).

**Argument for a LEO receiver.** The bias is induced at the satellite (BDS SCB-AR paper:
"likely attributed to the internal satellite multipath"; Wanninger & Beer 2015 find it
independent of the receiver), so its physical argument is the direction of the signal at the
satellite: the nadir angle ``η`` between the satellite's geocentre direction and the line to
the receiver. A receiver on the ground at radius ``R`` sees the satellite (radius ``r``) at the
elevation ``e`` with ``sin η = (R / r) cos e``, a one-to-one map for ``0° ≤ e ≤ 90°``; the table
is therefore a table in ``η``. For a LEO, leopod computes ``η`` at the BDS satellite from the
LEO's position (:func:`nadir_angle_deg`) and enters the table with the ground elevation of the
same nadir angle, ``e* = arccos((r / R) sin η)`` (:func:`equivalent_elevation_deg`), with
``R`` the mean Earth radius. A LEO can be seen beyond the Earth's limb (``sin η > R / r``),
where the table has no value: there ``e* = 0°`` (the 0° node is used). This mapping is
leopod's reading of the satellite-side origin; the BDS SCB-AR paper treats ground stations
only and says nothing of LEO receivers; Jiang et al. (2017) modelled the BDS code biases seen
onboard FY-3C with their own piece-wise functions (not used here), while PRIDE PPP-AR does not
correct LEO receivers at all (its source remarks that FY-3C does not show the errors). Whether
the ground table holds onboard is therefore open: the correction can be switched off
(``code_bias.bds2_scb``).

Satellite types by PRN (BDS-2 only; GEO C01–C05 have no table): IGSO C06–C10, C13, C16;
MEO C11, C12, C14 (:data:`BDS2_ORBIT_TYPE`, the PRN assignment of the IGS MGEX BeiDou
constellation status from 2016 on). PRNs from C17 on are not BDS-2 IGSO/MEO satellites and
get no correction.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "BDS2_ORBIT_TYPE", "ELEVATION_NODES_DEG", "NOMINAL_RADIUS_M", "SCB_BANDS",
    "WANNINGER_BEER_2015_M", "bds2_scb_m", "equivalent_elevation_deg", "nadir_angle_deg",
    "scb_band", "scb_correction_m",
]

#: Elevation nodes of the table [deg] (Wanninger & Beer 2015, Table 2).
ELEVATION_NODES_DEG = np.arange(0.0, 91.0, 10.0)

#: Code corrections [m] at :data:`ELEVATION_NODES_DEG` per (satellite type, frequency), to be
#: added to the observed code: Wanninger L, Beer S (2015), BeiDou satellite-induced code
#: pseudorange variations: diagnosis and therapy, GPS Solutions 19:639-648, Table 2. The
#: numbers were checked against the tables of the open implementations RTKLIB-based GAMP and
#: PRIDE PPP-AR (identical).
WANNINGER_BEER_2015_M = {
    ("IGSO", "B1"): (-0.55, -0.40, -0.34, -0.23, -0.15, -0.04, 0.09, 0.19, 0.27, 0.35),
    ("IGSO", "B2"): (-0.71, -0.36, -0.33, -0.19, -0.14, -0.03, 0.08, 0.17, 0.24, 0.33),
    ("IGSO", "B3"): (-0.27, -0.23, -0.21, -0.15, -0.11, -0.04, 0.05, 0.14, 0.19, 0.32),
    ("MEO", "B1"): (-0.47, -0.38, -0.32, -0.23, -0.11, 0.06, 0.34, 0.69, 0.97, 1.05),
    ("MEO", "B2"): (-0.40, -0.31, -0.26, -0.18, -0.06, 0.09, 0.28, 0.48, 0.64, 0.69),
    ("MEO", "B3"): (-0.22, -0.15, -0.13, -0.10, -0.04, 0.05, 0.14, 0.27, 0.36, 0.47),
}

#: BDS-2 IGSO and MEO satellites by PRN (GEO C01-C05 and BDS-3 are not in it).
BDS2_ORBIT_TYPE = {**{f"C{p:02d}": "IGSO" for p in (6, 7, 8, 9, 10, 13, 16)},
                   **{f"C{p:02d}": "MEO" for p in (11, 12, 14)}}

#: RINEX 3 band digit of BDS -> frequency of the table: 2 = B1I (1561.098 MHz), 7 = B2I
#: (1207.14 MHz), 6 = B3I (1268.52 MHz) (RINEX 3.04, Table 9; BDS-SIS-ICD).
SCB_BANDS = {"2": "B1", "7": "B2", "6": "B3"}

#: Nominal orbit radius per type [m] (BDS-SIS-ICD-B1I-3.0, sec. 3: IGSO at 35 786 km and MEO at
#: 21 528 km altitude, plus the equatorial radius), used when the satellite's radius is not
#: given; an error of 1 % in it moves the equivalent elevation by < 1° at 10°.
NOMINAL_RADIUS_M = {"IGSO": 42_164.0e3, "MEO": 27_906.0e3}

#: Mean radius of the ground receivers of the table [m]: R1 of GRS80 (Moritz 2000).
_R_GROUND_M = 6_371_008.8


def scb_band(code: str) -> str | None:
    """Table frequency (``"B1"``, ``"B2"``, ``"B3"``) of a BDS RINEX 3 code, None if none.

    Parameters
    ----------
    code : str
        RINEX 3 code or phase name, e.g. ``"C2I"`` (B1I), ``"C7I"`` (B2I), ``"C6I"`` (B3I).
    """
    if len(code) != 3:
        raise ValueError(f"'{code}' is not a RINEX 3 observation code (e.g. C2I)")
    return SCB_BANDS.get(code[1])


def scb_correction_m(orbit_type: str, band: str, el_deg) -> np.ndarray:
    """Wanninger & Beer (2015) code correction [m] at elevations ``el_deg`` [deg].

    Linear interpolation between the 10° nodes of :data:`WANNINGER_BEER_2015_M`; elevations
    below 0° take the 0° value; NaN stays NaN.

    Parameters
    ----------
    orbit_type : {"IGSO", "MEO"}
    band : {"B1", "B2", "B3"}
    el_deg : array_like
        Ground (or equivalent ground, :func:`equivalent_elevation_deg`) elevation [deg].

    Returns
    -------
    ndarray
        Correction to be added to the observed code [m], shape of ``el_deg``.

    Raises
    ------
    ValueError
        For an unknown type or band, or an elevation above 90° or below −90°.
    """
    key = (orbit_type, band)
    if key not in WANNINGER_BEER_2015_M:
        raise ValueError(f"no SCB table for satellite type {orbit_type!r} and band {band!r} "
                         f"(known: {sorted(WANNINGER_BEER_2015_M)})")
    el = np.asarray(el_deg, dtype=float)
    finite = el[np.isfinite(el)]
    if finite.size and (finite.max() > 90.0 or finite.min() < -90.0):
        raise ValueError(f"elevation outside [-90, 90] deg: {finite.min():.3f} .. "
                         f"{finite.max():.3f}")
    values = np.interp(np.clip(el, 0.0, 90.0), ELEVATION_NODES_DEG,
                       np.asarray(WANNINGER_BEER_2015_M[key]))
    return np.where(np.isfinite(el), values, np.nan)


def nadir_angle_deg(pos_sv_m, pos_rx_m) -> np.ndarray:
    """Nadir angle at the transmitter of the line to the receiver [deg].

    The angle between ``−pos_sv`` (towards the geocentre) and ``pos_rx − pos_sv``; both in one
    geocentric frame (Earth-fixed or inertial); arrays broadcast over the leading axes.

    Parameters
    ----------
    pos_sv_m, pos_rx_m : array_like, shape (..., 3)
        Transmitter and receiver positions [m].

    Returns
    -------
    ndarray, shape (...)
        Nadir angle in [0, 180] [deg].
    """
    sv = np.asarray(pos_sv_m, dtype=float)
    line = np.asarray(pos_rx_m, dtype=float) - sv
    cos = -np.sum(sv * line, axis=-1) / (np.linalg.norm(sv, axis=-1)
                                         * np.linalg.norm(line, axis=-1))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def equivalent_elevation_deg(nadir_deg, r_sv_m) -> np.ndarray:
    """Elevation at which a ground receiver sees a satellite under the same nadir angle [deg].

    ``e* = arccos((r / R) sin η)`` from ``sin η = (R / r) cos e`` (module docstring), with
    ``R`` the mean Earth radius; ``e* = 0`` beyond the Earth's limb (``sin η > R / r``).

    Parameters
    ----------
    nadir_deg : array_like
        Nadir angle at the satellite [deg], in [0, 90].
    r_sv_m : array_like
        Geocentric radius of the satellite [m] (broadcast with ``nadir_deg``).

    Raises
    ------
    ValueError
        If a nadir angle is outside [0, 90] deg or a radius is not above the Earth's.
    """
    eta = np.asarray(nadir_deg, dtype=float)
    r = np.asarray(r_sv_m, dtype=float)
    finite = eta[np.isfinite(eta)]
    if finite.size and (finite.min() < 0.0 or finite.max() > 90.0):
        raise ValueError(f"nadir angle outside [0, 90] deg: {finite.min():.3f} .. "
                         f"{finite.max():.3f}")
    if np.any(r[np.isfinite(r)] <= _R_GROUND_M):
        raise ValueError("satellite radius must exceed the Earth's mean radius (6371 km)")
    cos_e = np.minimum(r / _R_GROUND_M * np.sin(np.radians(eta)), 1.0)
    return np.degrees(np.arccos(cos_e))


def bds2_scb_m(svs, code: str, nadir_deg, r_sv_m=None) -> np.ndarray:
    """SCB correction [m] of one code for the columns of a (time, sv) array.

    Parameters
    ----------
    svs : sequence of str, length s
        Satellite ids (``"C11"``, ``"G05"``); columns that are not BDS-2 IGSO/MEO satellites
        (:data:`BDS2_ORBIT_TYPE`) get 0.
    code : str
        RINEX 3 code; bands other than B1I/B2I/B3I (:data:`SCB_BANDS`) get 0 everywhere.
    nadir_deg : array_like, shape (n, s)
        Nadir angle at each satellite of the line to the receiver [deg]
        (:func:`nadir_angle_deg`).
    r_sv_m : array_like, shape (n, s), optional
        Satellite radii [m]; None = :data:`NOMINAL_RADIUS_M` of the type.

    Returns
    -------
    ndarray, shape (n, s)
        Correction to be *added* to the observed code [m]; NaN where a BDS-2 IGSO/MEO
        nadir angle is NaN.
    """
    nadir = np.asarray(nadir_deg, dtype=float)
    svs = [str(s) for s in svs]
    if nadir.ndim != 2 or nadir.shape[1] != len(svs):
        raise ValueError(f"nadir_deg must be a (time, sv) array with {len(svs)} columns, got "
                         f"shape {nadir.shape}")
    out = np.zeros(nadir.shape)
    band = scb_band(code)
    if band is None:
        return out
    for j, sv in enumerate(svs):
        kind = BDS2_ORBIT_TYPE.get(sv)
        if kind is None:
            continue
        r = NOMINAL_RADIUS_M[kind] if r_sv_m is None else np.asarray(r_sv_m, float)[:, j]
        out[:, j] = scb_correction_m(kind, band, equivalent_elevation_deg(nadir[:, j], r))
    return out
