"""Reader of ANTEX antenna phase-centre files (ANTEX 1.3 and 1.4).

Why one module of 622 lines: one reader and the two classes it returns (AntennaPattern,
AntexFile), whose fields the parse fills directly (interpolation of the patterns included).

Format: "ANTEX: The Antenna Exchange Format, Version 1.4", M. Rothacher and R. Schmid,
15 September 2010 (files.igs.org/pub/station/general/antex14.txt); version 1.3 files have the
same record layout.

:func:`read_antex` returns an :class:`AntexFile`; one antenna is an :class:`AntennaPattern`:

- ``antex.satellite("G05", epoch)`` - the satellite antenna of PRN G05 whose
  ``VALID FROM``/``VALID UNTIL`` period contains ``epoch`` (GPS time, as in ANTEX);
- ``antex.receiver("AOAD/M_T NONE")`` - a receiver antenna by type and radome (``GOCE`` for the
  LEO antenna of ``GOCE_MAIN_0001.ATX``, whose radome field is blank);
- ``pattern.pco_m("G01")`` - phase-centre offset [m]: north/east/up for a receiver antenna,
  x/y/z of the satellite body frame for a satellite antenna;
- ``pattern.pcv_m("G01", zenith_deg, azimuth_deg)`` - phase-centre variation [m], linear in the
  zenith (nadir for satellites) angle, bilinear on the azimuth x zenith grid when the file gives
  one (``DAZI > 0``) and an azimuth is passed;
- ``pattern.to_dataset()`` - the pattern as an :class:`xarray.Dataset`.

Frequencies are named by the ANTEX code ``sNN`` (``G01``, ``G02``, ``E05``, ``C01`` = BDS-3
B1C, ``C05`` = B2a, ...), which ANTEX 1.3 and 1.4 share and whose digit is the RINEX 3 band.

Sign convention (ANTEX 1.4, section 3): mean phase centre = reference point + PCO, and
observed range = geometric range to the mean phase centre + PCV. Receiver azimuth counts
clockwise from north toward east; satellite azimuth counts clockwise from the y axis toward
the x axis looking along -z. The file's millimetres are converted to metres once, here.

The whole file is parsed and checked when read (about 0.08 s for the 2.7 MB igs05_1627.atx).
``START OF FREQ RMS`` blocks are skipped. A ``# OF FREQUENCIES`` count that differs from the
frequency blocks present is logged, not fatal (real subsets of IGS files keep the original
count).

Dataset of :meth:`AntennaPattern.to_dataset`
--------------------------------------------
dims
    ``frequency`` (str, e.g. ``"G01"``), ``zenith_deg`` (float, zenith angle for receivers,
    nadir angle for satellites), ``azimuth_deg`` (only when ``DAZI > 0``), and ``neu``
    (``north, east, up``; receivers) or ``xyz`` (``x, y, z``; satellites).
data variables
    ``pco_m`` (frequency, neu|xyz) [m]; ``pcv_noazi_m`` (frequency, zenith_deg) [m];
    ``pcv_m`` (frequency, azimuth_deg, zenith_deg) [m], only when ``DAZI > 0``.
attrs
    ``kind`` ("satellite"/"receiver"), ``antenna_type``, ``serial``, ``svn``, ``cospar_id``,
    ``valid_from``, ``valid_until`` (ISO strings, "" when absent), ``time_system`` ("GPS"),
    ``dazi_deg``, ``sinex_code``, ``calibration_method``, ``calibrated_by``,
    ``antex_version``, ``pcv_type``, ``reference_antenna``, ``source_file``.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._fields import epoch_ns
from leopod.io._text import (
    FormatError,
    fixed_float,
    parse_float,
    parse_floats,
    parse_int,
    read_lines,
)

__all__ = ["AntennaPattern", "AntexFile", "read_antex"]

log = logging.getLogger(__name__)

_MM_TO_M = 1e-3
_SAT_SERIAL = re.compile(r"^[GRECJIS]\d\d$")
_FREQ_CODE = re.compile(r"^[A-Z]\d\d$")
_NAT = np.datetime64("NaT", "ns")

# Labels skipped between records: comments and (when the line is blank) empty lines.
_IGNORED = {"COMMENT", ""}


@dataclass(eq=False)
class AntennaPattern:
    """Phase-centre offsets and variations of one antenna entry of an ANTEX file.

    Attributes
    ----------
    kind : str
        ``"satellite"`` or ``"receiver"``.
    antenna_type : str
        Antenna type and radome as written (``"BLOCK IIA"``, ``"LEIAR25.R4      LEIT"``),
        trailing blanks removed.
    serial : str
        Serial number field: the PRN ``sNN`` for satellite antennas, "" if blank.
    svn : str
        SVN ``sNNN`` of a satellite antenna ("" if absent).
    cospar_id : str
        COSPAR ID of a satellite antenna ("" if absent).
    valid_from, valid_until : numpy.datetime64
        Validity period in GPS time [ns]; NaT when the file gives none (open).
    zenith_deg : numpy.ndarray, shape (n_zen,)
        Zenith (receiver) or nadir (satellite) angles of the pattern [deg].
    dazi_deg : float
        Azimuth increment [deg]; 0 when the pattern has no azimuth dependence.
    frequencies : tuple of str
        ANTEX frequency codes in file order.
    """

    kind: str
    antenna_type: str
    serial: str
    svn: str
    cospar_id: str
    valid_from: np.datetime64
    valid_until: np.datetime64
    zenith_deg: np.ndarray
    dazi_deg: float
    frequencies: tuple[str, ...]
    pco: dict[str, np.ndarray] = field(repr=False)
    noazi: dict[str, np.ndarray] = field(repr=False)
    grid: dict[str, np.ndarray] = field(repr=False)
    meta: dict[str, str | float] = field(repr=False)

    @property
    def azimuth_deg(self) -> np.ndarray | None:
        """Azimuths of the grid rows, 0..360 inclusive [deg], or None if ``DAZI = 0``."""
        if self.dazi_deg == 0:
            return None
        n = int(round(360.0 / self.dazi_deg)) + 1
        return np.linspace(0.0, 360.0, n)

    @property
    def pco_axes(self) -> tuple[str, str, str]:
        """Names of the PCO components: north/east/up (receiver) or x/y/z (satellite)."""
        return ("x", "y", "z") if self.kind == "satellite" else ("north", "east", "up")

    def _check_freq(self, freq: str) -> str:
        if freq not in self.pco:
            raise KeyError(f"{self.kind} antenna '{self.antenna_type}' {self.serial}: no "
                           f"frequency '{freq}' (available: {', '.join(self.frequencies)})")
        return freq

    def pco_m(self, freq: str) -> np.ndarray:
        """Phase-centre offset of one frequency.

        Parameters
        ----------
        freq : str
            ANTEX frequency code (``"G01"``).

        Returns
        -------
        numpy.ndarray, shape (3,)
            Offset [m] along :attr:`pco_axes`.

        Raises
        ------
        KeyError
            If the antenna has no such frequency (the message lists those it has).
        """
        return self.pco[self._check_freq(freq)].copy()

    def pcv_m(self, freq: str, zenith_deg, azimuth_deg=None, *, outside: str = "raise"):
        """Phase-centre variation, interpolated in the pattern.

        Parameters
        ----------
        freq : str
            ANTEX frequency code (``"G01"``).
        zenith_deg : float or array_like
            Zenith angle (receiver) or nadir angle (satellite) [deg].
        azimuth_deg : float or array_like, optional
            Azimuth [deg] (ANTEX convention, any value, taken modulo 360), broadcast against
            ``zenith_deg``. Without it, or when the file has no azimuth grid, the
            azimuth-independent ``NOAZI`` pattern is used.
        outside : {"raise", "nearest", "nan"}
            What to do with angles beyond the pattern's zenith range: raise ValueError, hold
            the edge value, or return NaN.

        Returns
        -------
        numpy.ndarray or float
            PCV [m], shape of the broadcast inputs. Linear interpolation in zenith, bilinear
            in (azimuth, zenith) on a grid.
        """
        freq = self._check_freq(freq)
        zen = np.asarray(zenith_deg, dtype=float)
        use_grid = azimuth_deg is not None and self.dazi_deg > 0
        if use_grid:
            zen, az = np.broadcast_arrays(zen, np.asarray(azimuth_deg, dtype=float))
        lo, hi = self.zenith_deg[0], self.zenith_deg[-1]
        out_of_range = (zen < lo) | (zen > hi)
        if outside not in ("raise", "nearest", "nan"):
            raise ValueError(f"outside must be 'raise', 'nearest' or 'nan', not {outside!r}")
        if outside == "raise" and np.any(out_of_range):
            bad = zen[out_of_range].ravel()[0]
            raise ValueError(f"{self.kind} antenna '{self.antenna_type}' {self.serial}: angle "
                             f"{bad} deg outside the pattern range [{lo}, {hi}] deg "
                             f"(pass outside='nearest' to hold the edge value)")
        zc = np.clip(zen, lo, hi)
        if use_grid:
            value = _bilinear(self.grid[freq], lo, self.zenith_deg[1] - lo, self.dazi_deg,
                              zc, np.mod(az, 360.0))
        else:
            value = np.interp(zc, self.zenith_deg, self.noazi[freq])
        if outside == "nan":
            value = np.where(out_of_range, np.nan, value)
        return value[()] if np.ndim(value) == 0 else value

    def to_dataset(self) -> xr.Dataset:
        """The pattern as a Dataset (schema in the module docstring)."""
        axis = "xyz" if self.kind == "satellite" else "neu"
        freqs = list(self.frequencies)
        coords = {"frequency": freqs, "zenith_deg": self.zenith_deg, axis: list(self.pco_axes)}
        angle = "nadir angle" if self.kind == "satellite" else "zenith angle"
        data = {
            "pco_m": (("frequency", axis), np.stack([self.pco[f] for f in freqs]),
                      {"units": "m", "long_name": "phase centre offset"}),
            "pcv_noazi_m": (("frequency", "zenith_deg"),
                            np.stack([self.noazi[f] for f in freqs]),
                            {"units": "m", "long_name":
                             f"azimuth-independent phase centre variation vs {angle}"}),
        }
        if self.dazi_deg > 0:
            coords["azimuth_deg"] = self.azimuth_deg
            data["pcv_m"] = (("frequency", "azimuth_deg", "zenith_deg"),
                             np.stack([self.grid[f] for f in freqs]),
                             {"units": "m",
                              "long_name": f"phase centre variation vs azimuth and {angle}"})
        ds = xr.Dataset(data, coords=coords)
        ds["zenith_deg"].attrs.update(units="degree", long_name=angle)
        if self.dazi_deg > 0:
            ds["azimuth_deg"].attrs.update(units="degree", long_name="azimuth (ANTEX convention)")
        ds.attrs.update(
            kind=self.kind, antenna_type=self.antenna_type, serial=self.serial, svn=self.svn,
            cospar_id=self.cospar_id, valid_from=_iso(self.valid_from),
            valid_until=_iso(self.valid_until), time_system="GPS", dazi_deg=self.dazi_deg,
            **self.meta)
        return ds


def _bilinear(grid, zen0, dzen, dazi, zen, az):
    """Bilinear interpolation on a regular (azimuth, zenith) grid [same units as grid]."""
    n_az, n_zen = grid.shape
    fz = (zen - zen0) / dzen
    iz = np.clip(np.floor(fz).astype(int), 0, n_zen - 2)
    tz = fz - iz
    fa = az / dazi
    ia = np.clip(np.floor(fa).astype(int), 0, n_az - 2)
    ta = fa - ia
    return ((1 - ta) * ((1 - tz) * grid[ia, iz] + tz * grid[ia, iz + 1])
            + ta * ((1 - tz) * grid[ia + 1, iz] + tz * grid[ia + 1, iz + 1]))


def _iso(t: np.datetime64) -> str:
    return "" if np.isnat(t) else str(t)


class AntexFile:
    """All antennas of one ANTEX file, looked up by PRN and epoch or by receiver type.

    Attributes
    ----------
    path : Path
        The file read.
    attrs : dict
        Header information: ``antex_version`` (float), ``satellite_system``, ``pcv_type``
        ("A" absolute / "R" relative), ``reference_antenna``.
    antennas : list of AntennaPattern
        Every antenna entry, in file order.
    window : (numpy.datetime64, numpy.datetime64) or None
        GPS-time span outside which :meth:`satellite` refuses to choose an entry (a subset of
        a file kept for some days, :mod:`leopod.io.product_netcdf`); None: any epoch.
    """

    def __init__(self, path: Path, attrs: dict, antennas: list[AntennaPattern],
                 window: tuple[np.datetime64, np.datetime64] | None = None):
        self.path = path
        self.attrs = attrs
        self.antennas = antennas
        self.window = window
        self._sat: dict[str, list[AntennaPattern]] = {}
        self._rcv: dict[str, list[AntennaPattern]] = {}
        for ant in antennas:
            if ant.kind == "satellite":
                self._sat.setdefault(ant.serial, []).append(ant)
            else:
                self._rcv.setdefault(_type_key(ant.antenna_type), []).append(ant)

    def __len__(self) -> int:
        return len(self.antennas)

    def __repr__(self) -> str:
        return (f"AntexFile({self.path.name!r}, {len(self._sat)} satellite PRNs, "
                f"{len(self._rcv)} receiver antenna types)")

    @property
    def prns(self) -> list[str]:
        """PRNs (``sNN``) that have at least one satellite antenna entry, sorted."""
        return sorted(self._sat)

    @property
    def receiver_types(self) -> list[str]:
        """Receiver antenna types (type and radome, blanks collapsed), sorted."""
        return sorted(self._rcv)

    def satellite(self, prn: str, epoch) -> AntennaPattern:
        """The antenna of satellite ``prn`` valid at ``epoch``.

        Parameters
        ----------
        prn : str
            Satellite code ``sNN`` (``"G05"``).
        epoch : numpy.datetime64, datetime or ISO str
            Epoch in GPS time. ``VALID FROM``/``VALID UNTIL`` are inclusive; a missing bound
            is open.

        Raises
        ------
        KeyError
            If the file has no entry of ``prn`` valid at ``epoch`` (the message names both
            and lists the validity periods the file has for that PRN).
        ValueError
            If ``epoch`` lies outside :attr:`window` (the entries valid then were not kept).
        """
        t = np.datetime64(epoch, "ns")
        if self.window is not None and not (self.window[0] <= t <= self.window[1]):
            raise ValueError(f"{self.path.name}: satellite antennas are kept for "
                             f"{self.window[0]} .. {self.window[1]} only, not for {t}")
        entries = self._sat.get(prn, [])
        valid = [a for a in entries
                 if (np.isnat(a.valid_from) or a.valid_from <= t)
                 and (np.isnat(a.valid_until) or t <= a.valid_until)]
        if not valid:
            periods = "; ".join(f"{a.svn or '?'} {_iso(a.valid_from) or '-inf'} .. "
                                f"{_iso(a.valid_until) or 'open'}" for a in entries)
            raise KeyError(f"{self.path.name}: no satellite antenna for {prn} valid at {t}"
                           + (f" (entries: {periods})" if entries else " (PRN absent)"))
        if len(valid) > 1:
            log.warning("%s: %d antenna entries of %s are valid at %s; using the one that "
                        "starts last", self.path.name, len(valid), prn, t)
        return max(valid, key=lambda a: a.valid_from if not np.isnat(a.valid_from)
                   else np.datetime64("1900-01-01", "ns"))

    def receiver(self, antenna_type: str, serial: str | None = None) -> AntennaPattern:
        """A receiver antenna by type (and radome), optionally by serial number.

        Parameters
        ----------
        antenna_type : str
            Antenna type and radome separated by blanks (``"AOAD/M_T NONE"``,
            ``"LEIAR25.R4 LEIT"``); a type given without radome also matches ``NONE``.
        serial : str, optional
            Serial number; without it an entry with blank serial is preferred, and a type
            with a single entry matches whatever its serial.

        Raises
        ------
        KeyError
            If no entry matches, or several do and ``serial`` does not choose.
        """
        key = _type_key(antenna_type)
        entries = self._rcv.get(key) or self._rcv.get(f"{key} NONE", [])
        if serial is not None:
            entries = [a for a in entries if a.serial == serial.strip()]
        elif len(entries) > 1:
            entries = [a for a in entries if not a.serial] or entries
        if len(entries) == 1:
            return entries[0]
        if not entries:
            raise KeyError(f"{self.path.name}: no receiver antenna '{antenna_type}'"
                           + (f" with serial '{serial}'" if serial is not None else ""))
        raise KeyError(f"{self.path.name}: receiver antenna '{antenna_type}' has entries for "
                       f"serials {[a.serial for a in entries]}; pass serial=")


def _type_key(antenna_type: str) -> str:
    return " ".join(antenna_type.split())


def read_antex(path: str | Path) -> AntexFile:
    """Read an ANTEX 1.3/1.4 file (plain, .gz or .Z).

    Parameters
    ----------
    path : str or Path
        The ANTEX file.

    Returns
    -------
    AntexFile
        All antennas, PCOs and PCVs in metres (see the module docstring).

    Raises
    ------
    FormatError
        On a missing header record, an antenna without ``END OF ANTENNA``, an invalid
        ``ZEN1 / ZEN2 / DZEN`` or ``DAZI``, a PCV line with the wrong number of values, a
        non-numeric or non-finite number, or any record out of place.
    """
    path = Path(path)
    lines = read_lines(path)
    labels = [ln[60:80].rstrip() for ln in lines]
    attrs, k = _parse_header(lines, labels, path)
    antennas = []
    n = len(lines)
    while k < n:
        label = labels[k]
        if label == "START OF ANTENNA":
            end, k_next = _end_of_antenna(labels, k, path)
            antennas.append(_parse_antenna(lines, labels, k, end, path, attrs))
            k = k_next
        elif label in _IGNORED and (label or not lines[k].strip()):
            k += 1
        else:
            raise FormatError(path, k + 1, label or lines[k][:20].strip(),
                              "record outside an antenna block (expected START OF ANTENNA)")
    if not antennas:
        raise FormatError(path, None, "START OF ANTENNA", "the file holds no antenna")
    return AntexFile(path, attrs, antennas)


def _parse_header(lines, labels, path) -> tuple[dict, int]:
    """Parse the header; return its attrs and the index of the line after END OF HEADER."""
    attrs: dict = {}
    for k, (line, label) in enumerate(zip(lines, labels)):
        if label == "ANTEX VERSION / SYST":
            attrs["antex_version"] = fixed_float(line, 0, 8, path, k + 1, "ANTEX VERSION")
            attrs["satellite_system"] = line[20:21].strip()
        elif label == "PCV TYPE / REFANT":
            attrs["pcv_type"] = line[0:1]
            attrs["reference_antenna"] = line[20:40].strip()
        elif label == "END OF HEADER":
            for record, key in (("ANTEX VERSION / SYST", "antex_version"),
                                ("PCV TYPE / REFANT", "pcv_type")):
                if key not in attrs:
                    raise FormatError(path, None, record, "mandatory header record missing")
            if attrs["pcv_type"] not in ("A", "R"):
                raise FormatError(path, None, "PCV TYPE / REFANT",
                                  f"PCV type '{attrs['pcv_type']}' is neither A nor R")
            return attrs, k + 1
        elif label == "START OF ANTENNA":
            break
    raise FormatError(path, None, "END OF HEADER", "mandatory header record missing")


def _end_of_antenna(labels, start, path) -> tuple[int, int]:
    """(index ending the block opened at ``start``, index where the next block may start).

    The block ends at its END OF ANTENNA; a block that the next START OF ANTENNA opens
    without one (a subset file cut and pasted, e.g. georust's igs14_small.atx) ends there,
    with a logged warning: its records up to END OF FREQUENCY are complete and are checked.
    """
    for j in range(start + 1, len(labels)):
        if labels[j] == "END OF ANTENNA":
            return j, j + 1
        if labels[j] == "START OF ANTENNA":
            log.warning("%s:%d: antenna opened at line %d is not closed by END OF ANTENNA "
                        "before the next START OF ANTENNA; closed there", path.name, j + 1,
                        start + 1)
            return j, j
    raise FormatError(path, len(labels), "END OF ANTENNA",
                      f"antenna opened at line {start + 1} is not closed (file truncated?)")


def _parse_antenna(lines, labels, start, end, path, file_attrs) -> AntennaPattern:
    """Parse one block START OF ANTENNA (index ``start``) .. END OF ANTENNA (``end``)."""
    info: dict = {"valid_from": _NAT, "valid_until": _NAT}
    meta: dict = {"sinex_code": "", "calibration_method": "", "calibrated_by": "",
                  "antex_version": file_attrs["antex_version"],
                  "pcv_type": file_attrs["pcv_type"],
                  "reference_antenna": file_attrs.get("reference_antenna", ""),
                  "source_file": path.name}
    pco, noazi, grid = {}, {}, {}
    k = start + 1
    while k < end:
        line, label, lineno = lines[k], labels[k], k + 1
        if label == "TYPE / SERIAL NO":
            info["type"] = line[0:20].rstrip()
            info["serial"] = line[20:40].strip()
            info["svn"] = line[40:50].strip()
            info["cospar"] = line[50:60].strip()
        elif label in ("METH / BY / # / DATE", "METH / BY / DATE"):
            meta["calibration_method"] = line[0:20].strip()
            meta["calibrated_by"] = line[20:40].strip()
        elif label == "DAZI":
            info["dazi"] = _dazi(line, path, lineno)
        elif label == "ZEN1 / ZEN2 / DZEN":
            info["zen"] = _zenith_grid(line, path, lineno)
        elif label == "# OF FREQUENCIES":
            info["n_freq"] = (parse_int(line[0:6], path, lineno, "# OF FREQUENCIES"), lineno)
        elif label in ("VALID FROM", "VALID UNTIL"):
            info["valid_from" if label == "VALID FROM" else "valid_until"] = \
                _epoch(line, path, lineno, label)
        elif label == "SINEX CODE":
            meta["sinex_code"] = line[0:10].strip()
        elif label == "START OF FREQUENCY":
            for record, key in (("TYPE / SERIAL NO", "type"), ("DAZI", "dazi"),
                                ("ZEN1 / ZEN2 / DZEN", "zen")):
                if key not in info:
                    raise FormatError(path, lineno, record,
                                      f"record missing before the first START OF FREQUENCY "
                                      f"of the antenna at line {start + 1}")
            k = _parse_frequency(lines, labels, k, end, info, path, pco, noazi, grid)
            continue
        elif label == "START OF FREQ RMS":
            k = _skip_rms(labels, k, end, path)
        elif label not in _IGNORED or (not label and line.strip()):
            raise FormatError(path, lineno, label or line[:20].strip(),
                              "unexpected record inside an antenna block")
        k += 1
    if "type" not in info:
        raise FormatError(path, start + 1, "TYPE / SERIAL NO",
                          "antenna block without TYPE / SERIAL NO")
    if not pco:
        raise FormatError(path, end + 1, "START OF FREQUENCY",
                          f"antenna '{info['type']}' at line {start + 1} has no frequency")
    if "n_freq" in info and info["n_freq"][0] != len(pco):
        # Not fatal: every frequency block present was read and checked; real subsets of
        # IGS files (e.g. Orekit's igs20-small.atx) keep the original count.
        log.warning("%s:%d: # OF FREQUENCIES announces %d frequencies, antenna '%s' has %d",
                    path.name, info["n_freq"][1], info["n_freq"][0], info["type"], len(pco))
    is_sat = bool(_SAT_SERIAL.match(info["serial"]))
    return AntennaPattern(
        kind="satellite" if is_sat else "receiver", antenna_type=info["type"],
        serial=info["serial"], svn=info["svn"], cospar_id=info["cospar"],
        valid_from=info["valid_from"], valid_until=info["valid_until"],
        zenith_deg=info["zen"], dazi_deg=info["dazi"], frequencies=tuple(pco),
        pco=pco, noazi=noazi, grid=grid, meta=meta)


def _dazi(line, path, lineno) -> float:
    dazi = fixed_float(line, 0, 8, path, lineno, "DAZI", kind="angle_deg")
    if dazi < 0 or dazi >= 360 or (dazi > 0 and abs(360 / dazi - round(360 / dazi)) > 1e-9):
        raise FormatError(path, lineno, "DAZI",
                          f"azimuth increment {dazi} deg must be 0 or divide 360")
    return dazi


def _zenith_grid(line, path, lineno) -> np.ndarray:
    zen1 = fixed_float(line, 0, 8, path, lineno, "ZEN1")
    zen2 = fixed_float(line, 8, 14, path, lineno, "ZEN2")
    # DZEN of at least 0.01 deg bounds the grid to 18 001 nodes (real files: 0.5-5 deg)
    dzen = parse_float(line[14:20], path, lineno, "ZEN1 / ZEN2 / DZEN", lo=0.01, hi=180.0)
    if not (0 <= zen1 < zen2 <= 180) or dzen <= 0:
        raise FormatError(path, lineno, "ZEN1 / ZEN2 / DZEN",
                          f"need 0 <= ZEN1 < ZEN2 <= 180 and DZEN > 0, got {zen1} {zen2} {dzen}")
    steps = (zen2 - zen1) / dzen
    if abs(steps - round(steps)) > 1e-6:
        raise FormatError(path, lineno, "ZEN1 / ZEN2 / DZEN",
                          f"ZEN2 - ZEN1 = {zen2 - zen1} is not a multiple of DZEN = {dzen}")
    return zen1 + dzen * np.arange(int(round(steps)) + 1)


def _epoch(line, path, lineno, label) -> np.datetime64:
    """Decode a VALID FROM / VALID UNTIL record (5I6, F13.7) into datetime64[ns]."""
    y, mo, d, h, mi = (parse_int(line[6 * i:6 * i + 6], path, lineno, f"{label} {name}",
                                 lo=0)
                       for i, name in enumerate(("year", "month", "day", "hour", "minute")))
    sec = fixed_float(line, 30, 43, path, lineno, f"{label} second")
    return np.datetime64(epoch_ns(y, mo, d, h, mi, sec, path, lineno, label,
                                  leap_second=True), "ns")


def _parse_frequency(lines, labels, k, end, info, path, pco, noazi, grid):
    """Parse START OF FREQUENCY at index ``k``; fill pco/noazi/grid; return the next index."""
    start_no = k + 1
    code = lines[k][3:6]
    if not _FREQ_CODE.match(code):
        raise FormatError(path, start_no, "START OF FREQUENCY",
                          f"frequency code '{lines[k][:8].strip()}' is not of the form sNN")
    if code in pco:
        raise FormatError(path, start_no, "START OF FREQUENCY",
                          f"frequency {code} appears twice in the antenna")
    zen = info["zen"]
    dazi = info["dazi"]
    n_az = int(round(360.0 / dazi)) + 1 if dazi > 0 else 0
    k = _next_line(labels, k, end, path, code)
    if labels[k] != "NORTH / EAST / UP":
        raise FormatError(path, k + 1, "NORTH / EAST / UP",
                          f"expected after START OF FREQUENCY {code}")
    line = lines[k]
    pco[code] = _MM_TO_M * np.array(
        [fixed_float(line, 10 * i, 10 * i + 10, path, k + 1, f"{code} {axis}",
                     kind="antenna_mm")
         for i, axis in enumerate(("NORTH", "EAST", "UP"))])
    k = _next_line(labels, k, end, path, code)
    if lines[k][3:8] != "NOAZI":
        raise FormatError(path, k + 1, "NOAZI", f"expected the NOAZI line of frequency {code}")
    noazi[code] = _MM_TO_M * _pcv_row(lines[k], len(zen), path, k + 1, f"{code} NOAZI")
    if n_az:
        n = len(zen)
        tokens, line_nos = [], []
        for i in range(n_az):
            k = _next_line(labels, k, end, path, code)
            line = lines[k]
            az = fixed_float(line, 0, 8, path, k + 1, f"{code} azimuth")
            if abs(az - i * dazi) > 1e-6:
                raise FormatError(path, k + 1, f"{code} azimuth",
                                  f"azimuth {az} where {i * dazi:g} was expected "
                                  f"(DAZI = {dazi:g})")
            row = line[8:].split()
            if len(row) != n:
                raise FormatError(path, k + 1, f"{code} azimuth {az:g}",
                                  f"{len(row)} PCV values where ZEN1/ZEN2/DZEN gives {n}")
            tokens += row
            line_nos += [k + 1] * n
        values = parse_floats(tokens, line_nos, lambda j: f"{code} azimuth {(j // n) * dazi:g} "
                              f"#{j % n + 1}", path, kind="antenna_mm")
        grid[code] = _MM_TO_M * values.reshape(n_az, n)
    k = _next_line(labels, k, end, path, code)
    if labels[k] != "END OF FREQUENCY" or lines[k][3:6] != code:
        raise FormatError(path, k + 1, "END OF FREQUENCY",
                          f"expected END OF FREQUENCY {code} (frequency opened at line "
                          f"{start_no}); wrong number of PCV rows?")
    return k + 1


def _next_line(labels, k, end, path, code) -> int:
    if k + 1 >= end:
        raise FormatError(path, end + 1, "END OF FREQUENCY",
                          f"antenna ends inside frequency {code}")
    return k + 1


def _pcv_row(line, n, path, lineno, field) -> np.ndarray:
    """Parse the ``n`` F8.2 values after the 8-character row label, in mm."""
    tokens = line[8:].split()
    if len(tokens) != n:
        raise FormatError(path, lineno, field,
                          f"{len(tokens)} PCV values where ZEN1/ZEN2/DZEN gives {n}")
    return parse_floats(tokens, [lineno] * n, lambda i: f"{field} #{i + 1}", path,
                        kind="antenna_mm")


def _skip_rms(labels, k, end, path) -> int:
    """Index of the END OF FREQ RMS closing the RMS block at ``k``."""
    for j in range(k + 1, end):
        if labels[j] == "END OF FREQ RMS":
            return j
    raise FormatError(path, end + 1, "END OF FREQ RMS",
                      f"RMS block opened at line {k + 1} is not closed")
