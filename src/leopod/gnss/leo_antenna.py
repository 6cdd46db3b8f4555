"""The LEO receiver antenna: reference point, antenna frame, and PCO/PCV per frequency (ANTEX).

A satellite's antenna is either the simple table of phase-centre offsets in the body frame
(``satellites.<sat>.antenna_pco_body_m``: one vector per band, relative to the centre of
mass), or an ANTEX receiver antenna (``satellites.<sat>.antenna``, :class:`LeoAntennaSettings`):

- ``antex``: path of an ANTEX file (:mod:`leopod.io.antex`), ``type``: the antenna type and
  radome of its entry (``"GOCE"`` in ``GOCE_MAIN_0001.ATX``, Jäggi et al. 2009);
- ``arp_body_m``: the antenna reference point (ARP) from the centre of mass in the body frame
  (+X flight direction, +Z to the geocentre) [m];
- ``north_body``, ``up_body``: the antenna frame's north and up (boresight) axes in the body
  frame; east = north × up (ANTEX's north/east/up is right-handed, :func:`leopod.frames.
  attitude.antenna_frame`). The default north = +X, up = −Z gives east = +X × −Z = +Y.

Phase centre of band ``b`` in the body frame (ANTEX 1.4, sec. 3: mean phase centre = ARP +
PCO, the PCO given in north/east/up)::

    p_b = ARP + Fᵀ PCO_b(N, E, U)          (F: rows N, E, U of the antenna frame)

and its variation ``PCV_b(z, α)`` of the zenith angle ``z`` and azimuth ``α`` (clockwise from
north towards east) of the line of sight in the antenna frame, bilinear on the ANTEX azimuth
x zenith grid (or ``NOAZI``). ANTEX 1.4, sec. 3: observed range = range to the mean phase
centre + PCV, so the PCV is *added* to the modelled range of the band, code and phase alike.
The ionosphere-free PCV of a band pair (as the ionosphere-free PCO) is
``(f1² PCV1 − f2² PCV2) / (f1² − f2²)``.

ANTEX frequency codes: ``sNN`` with the system letter and the RINEX 3 band digit (``G01`` =
L1, ``G02`` = L2, ``C01`` = BDS-3 B1C, ``C05`` = B2a; :mod:`leopod.io.antex`).

:class:`LeoAntenna` is a read-only mapping band name -> body-frame phase-centre offset ``p_b``
[m], so it stands wherever the table of ``antenna_pco_body_m`` stands (ingest, POD, quality,
simulator); the steps that model the PCV ask it for :meth:`LeoAntenna.pcv_m` at the angles of
:meth:`LeoAntenna.angles` (:func:`leopod.frames.attitude.antenna_el_az`).

References
----------
Rothacher, M., Schmid, R. (2010). ANTEX: The Antenna Exchange Format, Version 1.4.
Jäggi, A., Dach, R., Montenbruck, O., Hugentobler, U., Bock, H., Beutler, G. (2009). Phase
center modeling for LEO GPS receiver antennas and its impact on precise orbit determination.
Journal of Geodesy 83, 1145–1162. doi:10.1007/s00190-009-0333-2
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from leopod import signals
from leopod.frames.attitude import antenna_el_az, antenna_frame
from leopod.io.antex import AntennaPattern, read_antex
from leopod.settings import Settings

__all__ = ["LeoAntenna", "LeoAntennaSettings", "antenna_frame_of", "antex_frequency",
           "leo_antenna",
           "receiver_pcv_if"]


@dataclass(frozen=True)
class LeoAntennaSettings(Settings):
    """The ANTEX antenna of a LEO (``satellites.<sat>.antenna``; module docstring).

    Attributes
    ----------
    antex : str or None
        Path (template) of the ANTEX file; None: no ANTEX antenna (``antenna_pco_body_m``
        or none).
    type : str or None
        Antenna type and radome of the receiver entry (``"GOCE"``).
    arp_body_m : tuple of float, shape (3,)
        Antenna reference point from the centre of mass, body frame [m].
    north_body, up_body : tuple of float, shape (3,)
        North and up (boresight) axes of the antenna frame in the body frame.
    """

    SCHEMA_DEF = "leo_antenna"

    antex: str | None
    type: str | None
    arp_body_m: tuple
    north_body: tuple
    up_body: tuple

    def __post_init__(self):
        for name in ("arp_body_m", "north_body", "up_body"):
            object.__setattr__(self, name, tuple(float(v) for v in getattr(self, name)))
        if self.antex is not None and not self.type:
            raise ValueError(f"satellites.<sat>.antenna: antex {self.antex!r} needs the "
                             "antenna 'type' (type and radome of the ANTEX entry)")
        antenna_frame(self.north_body, self.up_body)        # checks the axes


def antex_frequency(band_name: str) -> str:
    """ANTEX frequency code ``sNN`` of a band name (``"L1"`` -> ``"G01"``, ``"B2a"`` ->
    ``"C05"``).

    Raises
    ------
    KeyError
        If no system has a band of that name.
    """
    for b in signals.BANDS:
        if b.name == band_name:
            return f"{b.system}{int(b.band):02d}"
    raise KeyError(f"unknown band name {band_name!r} (known: "
                   f"{', '.join(b.name for b in signals.BANDS)})")


class LeoAntenna(Mapping):
    """A LEO receiver antenna: band name -> body-frame phase-centre offset (module docstring).

    Parameters
    ----------
    pattern : AntennaPattern
        The ANTEX receiver entry (PCO north/east/up and PCV per frequency).
    arp_body_m : array_like, shape (3,)
        Antenna reference point from the centre of mass, body frame [m].
    north_body, up_body : array_like, shape (3,)
        Antenna frame axes in the body frame (:func:`leopod.frames.attitude.antenna_frame`).
    source : str
        Where the antenna comes from (file and type), for logs and attributes.
    """

    def __init__(self, pattern: AntennaPattern, arp_body_m, north_body, up_body, *,
                 source: str = ""):
        self.pattern = pattern
        self.arp_body_m = np.asarray(arp_body_m, dtype=float).reshape(3)
        self.frame = antenna_frame(north_body, up_body)          # rows N, E, U (body)
        self.source = source or pattern.antenna_type
        self._bands = [b.name for b in signals.BANDS
                       if f"{b.system}{int(b.band):02d}" in pattern.pco]

    # -- mapping band -> phase centre ------------------------------------------------------
    def __getitem__(self, band_name: str) -> np.ndarray:
        return self.pco_body_m(band_name)

    def __iter__(self) -> Iterator[str]:
        return iter(self._bands)

    def __len__(self) -> int:
        return len(self._bands)

    def _frequency(self, band_name: str) -> str:
        freq = antex_frequency(band_name)
        if band_name not in self._bands:
            raise KeyError(f"LEO antenna {self.source}: no frequency {freq} for band "
                           f"{band_name} (the entry has {', '.join(self.pattern.frequencies)})")
        return freq

    def pco_neu_m(self, band_name: str) -> np.ndarray:
        """ANTEX PCO of the band, north/east/up of the antenna frame [m], shape (3,)."""
        return self.pattern.pco_m(self._frequency(band_name))

    def pco_body_m(self, band_name: str) -> np.ndarray:
        """Phase centre of the band from the centre of mass, body frame [m], shape (3,):
        ``ARP + Fᵀ PCO(N, E, U)``."""
        return self.arp_body_m + self.frame.T @ self.pco_neu_m(band_name)

    # -- variations ------------------------------------------------------------------------
    @property
    def has_pcv(self) -> bool:
        """True if the entry has a non-zero PCV of some frequency."""
        return any(np.any(v != 0.0) for v in self.pattern.noazi.values()) or any(
            np.any(v != 0.0) for v in self.pattern.grid.values())

    def angles(self, los_body: np.ndarray):
        """Zenith angle and azimuth of unit lines of sight (..., 3) in body coordinates
        [deg] (:func:`leopod.frames.attitude.antenna_el_az` with this antenna's frame)."""
        el, az = antenna_el_az(los_body, self.frame)
        return 90.0 - el, az

    def pcv_m(self, band_name: str, zenith_deg, azimuth_deg) -> np.ndarray:
        """PCV of the band at antenna-frame zenith and azimuth [deg] -> [m] (bilinear on the
        ANTEX grid, held at the edge beyond its zenith range)."""
        return np.asarray(self.pattern.pcv_m(self._frequency(band_name), zenith_deg,
                                             azimuth_deg, outside="nearest"), dtype=float)

    def pcv_el_az(self, band_name: str) -> Callable:
        """The band's PCV as ``f(el_deg, az_deg) -> m`` of the antenna-frame elevation."""
        return lambda el_deg, az_deg: self.pcv_m(band_name, 90.0 - np.asarray(el_deg),
                                                 az_deg)

    def describe(self) -> str:
        """One line for logs and file attributes."""
        return (f"ANTEX {self.source}: ARP {self.arp_body_m.tolist()} m, north "
                f"{self.frame[0].tolist()}, up {self.frame[2].tolist()} (body), bands "
                f"{', '.join(self._bands)}" + ("" if self.has_pcv else ", no PCV"))


def antenna_frame_of(antenna) -> np.ndarray | None:
    """The antenna frame (rows N, E, U in the body frame) of a :class:`LeoAntenna`; None for a
    plain PCO table (the default frame: N = +X, E = +Y, U = −Z)."""
    return antenna.frame if isinstance(antenna, LeoAntenna) else None


def receiver_pcv_if(antenna, system: str, phase_pair: Sequence[str]) -> Callable | None:
    """Ionosphere-free LEO PCV of a system's signal pair, ``f(el_deg, az_deg) -> m``.

    ``(f1² PCV1 − f2² PCV2) / (f1² − f2²)`` of the bands of the two phase codes; None if
    ``antenna`` is not a :class:`LeoAntenna` with variations (a plain PCO table has none).
    """
    if not isinstance(antenna, LeoAntenna) or not antenna.has_pcv:
        return None
    p1, p2 = phase_pair[:2]
    b1, b2 = signals.band(system, p1), signals.band(system, p2)
    g1, g2 = b1.frequency_hz**2, b2.frequency_hz**2
    pcv1, pcv2 = antenna.pcv_el_az(b1.name), antenna.pcv_el_az(b2.name)
    return lambda el_deg, az_deg: (g1 * pcv1(el_deg, az_deg) - g2 * pcv2(el_deg, az_deg)) \
        / (g1 - g2)


def leo_antenna(pco_body_m: Mapping | None, antenna: Mapping | LeoAntennaSettings | None,
                antex_path: str | Path | None = None):
    """The antenna of a satellite from its config keys: a :class:`LeoAntenna`, the plain
    PCO table, or None.

    Parameters
    ----------
    pco_body_m : mapping or None
        ``satellites.<sat>.antenna_pco_body_m`` (band -> body-frame offset [m]).
    antenna : mapping or LeoAntennaSettings or None
        ``satellites.<sat>.antenna``.
    antex_path : path, optional
        The ANTEX file as the step reads it (the located file); default ``antenna.antex``.

    Raises
    ------
    ValueError
        If both ``antenna_pco_body_m`` and ``antenna.antex`` are given.
    """
    settings = (antenna if isinstance(antenna, LeoAntennaSettings) or antenna is None
                else LeoAntennaSettings.from_config(dict(antenna)))
    if settings is None or settings.antex is None:
        return pco_body_m
    if pco_body_m:
        raise ValueError("satellites.<sat>: give either antenna_pco_body_m (body-frame "
                         "offsets per band) or antenna.antex (an ANTEX receiver antenna), not "
                         f"both (antenna.antex {settings.antex!r}, antenna_pco_body_m bands "
                         f"{sorted(pco_body_m)})")
    path = Path(antex_path if antex_path is not None else settings.antex)
    pattern = read_antex(path).receiver(settings.type)
    return LeoAntenna(pattern, settings.arp_body_m, settings.north_body, settings.up_body,
                      source=f"{path.name} {settings.type}")
