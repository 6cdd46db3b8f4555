"""GNSS systems, frequency bands and observation codes, as data.

Every combination in leopod takes its frequencies from this table, so a new signal pair
(GPS L1/L5, BDS-3 B1C/B2a, BDS-2 B1I/B3I, ...) needs a table row, not a code path.

Observation codes follow RINEX 3 (``<type><band><attribute>``, e.g. ``C1W``): the band digit
and the system fix the carrier frequency; the attribute names the tracking mode.
RINEX 2 names (``C1 P1 P2 L1 L2 ...``) are mapped onto RINEX 3 codes by
:data:`RINEX2_TO_RINEX3`, which follows the mapping conventional for GPS receivers
(RINEX 3.04, section 5.3 and Table A2: P-code on L1/L2 = ``W``, C/A on L1 = ``C``).

Sources of the frequencies: IS-GPS-200/705 (GPS), BDS-SIS-ICD B1I 3.0, B1C 1.0, B2a 1.0,
B3I 1.0 (BeiDou), Galileo OS SIS ICD 2.0; all in the RINEX 3.04/4.00 frequency tables.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from leopod.constants import C_LIGHT_M_S
from leopod.settings import Settings

__all__ = [
    "Band", "BANDS", "SYSTEMS", "band", "frequency_hz", "wavelength_m", "rinex3_code",
    "RINEX2_TO_RINEX3", "obs_type", "code_band", "SystemSignals", "signal_settings",
    "GEO_SATELLITES", "is_geo", "system_of",
]

#: One-letter RINEX system identifiers leopod knows, with their names.
SYSTEMS = {"G": "GPS", "C": "BeiDou", "E": "Galileo"}


@dataclass(frozen=True)
class Band:
    """One carrier frequency band of one GNSS.

    Attributes
    ----------
    system : str
        RINEX system letter (``"G"``, ``"C"``, ``"E"``).
    band : str
        RINEX 3 band digit (``"1"``, ``"2"``, ``"5"``, ...).
    name : str
        Usual name of the band/signal (``"L1"``, ``"B1C"``, ``"B2a"``).
    frequency_hz : float
        Carrier frequency [Hz].
    """

    system: str
    band: str
    name: str
    frequency_hz: float

    @property
    def wavelength_m(self) -> float:
        """Carrier wavelength [m]."""
        return C_LIGHT_M_S / self.frequency_hz


_F0 = 10.23e6  # fundamental frequency of GPS and Galileo [Hz], IS-GPS-200 3.3.1.1

#: The band table. BDS band digits follow RINEX 3.04: 1 = B1C, 2 = B1I, 5 = B2a, 6 = B3I,
#: 7 = B2b/B2I, 8 = B2a+b (AltBOC).
BANDS: tuple[Band, ...] = (
    Band("G", "1", "L1", 154 * _F0),
    Band("G", "2", "L2", 120 * _F0),
    Band("G", "5", "L5", 115 * _F0),
    Band("C", "1", "B1C", 1575.42e6),
    Band("C", "2", "B1I", 1561.098e6),
    Band("C", "5", "B2a", 1176.45e6),
    Band("C", "6", "B3I", 1268.52e6),
    Band("C", "7", "B2b", 1207.14e6),
    Band("C", "8", "B2ab", 1191.795e6),
    Band("E", "1", "E1", 154 * _F0),
    Band("E", "5", "E5a", 115 * _F0),
    Band("E", "6", "E6", 125 * _F0),
    Band("E", "7", "E5b", 118 * _F0),
    Band("E", "8", "E5ab", 116.5 * _F0),
)

_BY_KEY = {(b.system, b.band): b for b in BANDS}
_BY_NAME = {(b.system, b.name): b for b in BANDS}

#: RINEX 2 observation names -> RINEX 3 codes, per system. GPS: P-code (Z-tracking / semi-
#: codeless) = W, C/A = C; the carrier phase of a RINEX 2 "L1" is reported on the C/A
#: channel and "L2" on the semi-codeless P(Y) channel by dual-frequency receivers such as
#: the BlackJack. Other names keep band and get the attribute X ("mixed").
RINEX2_TO_RINEX3 = {
    "G": {"C1": "C1C", "P1": "C1W", "L1": "L1C", "D1": "D1C", "S1": "S1C",
          "C2": "C2X", "P2": "C2W", "L2": "L2W", "D2": "D2W", "S2": "S2W",
          "C5": "C5X", "L5": "L5X", "D5": "D5X", "S5": "S5X"},
    "E": {"C1": "C1X", "L1": "L1X", "S1": "S1X", "C5": "C5X", "L5": "L5X", "S5": "S5X",
          "C7": "C7X", "L7": "L7X", "S7": "S7X", "C8": "C8X", "L8": "L8X", "S8": "S8X"},
    "C": {"C2": "C2I", "L2": "L2I", "S2": "S2I", "C7": "C7I", "L7": "L7I", "S7": "S7I",
          "C6": "C6I", "L6": "L6I", "S6": "S6I"},
}


def band(system: str, key: str) -> Band:
    """Look up a band by system and either its RINEX band digit or its name.

    Parameters
    ----------
    system : str
        RINEX system letter.
    key : str
        Band digit (``"1"``), band name (``"B2a"``) or a full RINEX 3 code (``"C5P"``).

    Raises
    ------
    KeyError
        If the system/band is not in :data:`BANDS`; the message lists what is known.
    """
    if (system, key) in _BY_NAME:
        return _BY_NAME[(system, key)]
    digit = key[1] if len(key) == 3 else key
    try:
        return _BY_KEY[(system, digit)]
    except KeyError:
        known = ", ".join(f"{b.system}{b.band}={b.name}" for b in BANDS)
        raise KeyError(f"unknown band '{key}' for system '{system}' (known: {known})") from None


def frequency_hz(system: str, key: str) -> float:
    """Carrier frequency [Hz] of a band or observation code (see :func:`band`)."""
    return band(system, key).frequency_hz


def wavelength_m(system: str, key: str) -> float:
    """Carrier wavelength [m] of a band or observation code (see :func:`band`)."""
    return band(system, key).wavelength_m


def rinex3_code(system: str, name: str) -> str:
    """Return the RINEX 3 code for a RINEX 2 or RINEX 3 observation name.

    Three-character names are returned unchanged; two-character RINEX 2 names are mapped
    with :data:`RINEX2_TO_RINEX3`.

    Raises
    ------
    KeyError
        If a RINEX 2 name has no mapping for the system.
    """
    if len(name) == 3:
        return name
    try:
        return RINEX2_TO_RINEX3[system][name]
    except KeyError:
        raise KeyError(f"no RINEX 3 code for RINEX 2 observation '{name}' of system "
                       f"'{system}'") from None


def obs_type(code: str) -> str:
    """Observation type letter of a RINEX code: C (code), L (phase), D (Doppler), S (C/N0)."""
    return code[0]


def code_band(code: str) -> str:
    """Band digit of a RINEX 3 code."""
    return code[1]


#: Satellites in geostationary orbit, per system (RINEX ids). BeiDou assigns PRN 1-5 and
#: 59-63 to its GEO satellites (BDS-2 and BDS-3), the ones that broadcast the D2 navigation
#: message (BDS-SIS-ICD-B1I-3.0, navigation message section; CSNO constellation status,
#: CSNO 2024).
GEO_SATELLITES: dict[str, frozenset[str]] = {
    "C": frozenset([f"C{prn:02d}" for prn in (*range(1, 6), *range(59, 64))]),
}


def system_of(sv) -> np.ndarray:
    """GNSS system letters (``G``, ``C``, ``E``, ...) of RINEX-3 satellite ids (``G07``), any
    shape, flattened: shape (n,)."""
    return np.array([str(s)[:1] for s in np.ravel(np.asarray(sv, dtype=object))], dtype="<U1")


def is_geo(sv: str) -> bool:
    """True for a satellite id (``"C03"``) of :data:`GEO_SATELLITES`."""
    return sv in GEO_SATELLITES.get(sv[:1], ())


@dataclass(frozen=True)
class SystemSignals(Settings):
    """Signals of one GNSS that a campaign processes (config ``signals.<system>``).

    Attributes
    ----------
    phase : tuple of 2 str
        The two carrier phases (RINEX 3 codes; the first is frequency 1).
    code : tuple of str
        Every code observation to ingest and assess.
    pod_code : tuple of 2 str
        The codes, one per frequency of ``phase``, used for positioning and the wide lane.
    exclude_geo : bool
        Drop the system's geostationary satellites (:data:`GEO_SATELLITES`: BDS C01-C05,
        C59-C63) at ingest; no effect for systems without GEO satellites.
    """

    SCHEMA_DEF = "system_signals"

    phase: tuple[str, str]
    code: tuple[str, ...]
    pod_code: tuple[str, str]
    exclude_geo: bool

    @property
    def observations(self) -> list[str]:
        """Every phase and code named, in that order, without repetitions."""
        return list(dict.fromkeys([*self.phase, *self.code, *self.pod_code]))


def signal_settings(section: Mapping) -> dict[str, SystemSignals]:
    """:class:`SystemSignals` per system letter from the campaign's ``signals`` section."""
    return {system: SystemSignals.from_config(cfg) for system, cfg in section.items()}
