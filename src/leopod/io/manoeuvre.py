"""Reader of leopod manoeuvre files: the thrust arcs of a satellite, one line per burn.

Operators publish manoeuvres as lists of burns with their start and end epochs and the
thrust or velocity change of each; baseline determination estimates one set of constant
R/T/N accelerations per listed manoeuvre (Mao et al. 2023; Zhang et al. 2024, Table 1).
leopod writes and reads the minimal text
form of such a list (:mod:`leopod.io.manoeuvre_write`)::

    # leopod manoeuvre file 1.0
    # satellite: lt1-b
    # time system: GPS
    # start end acc_R acc_T acc_N [m/s2] dv_R dv_T dv_N [m/s]
    2022-07-14T12:00:00.000000 2022-07-14T12:02:00.000000 0.0 8.3333e-05 0.0 0.0 0.01 0.0

* lines starting with ``#`` are comments; the header keys ``satellite`` and ``time system``
  (``# key: value``) are read into the dataset attributes; the first line must be the
  ``# leopod manoeuvre file`` identification;
* each data line: start and end epochs (ISO 8601, GPS time unless the header says otherwise),
  the constant acceleration in the satellite's radial, along-track, cross-track frame (RTN of
  :func:`leopod.frames.rtn.rtn_matrix`) [m/s²] and the velocity change it gives,
  acceleration × duration [m/s] (redundant, for readers that want the size at a glance; the
  reader checks it to 1e-6 relative);
* burns are in time order and do not overlap.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from leopod.io._fields import iso_epoch_ns, require_line_end
from leopod.io._text import FormatError, parse_float, read_lines

__all__ = ["MAGIC", "Manoeuvre", "read_manoeuvres"]

#: Identification of the first line.
MAGIC = "# leopod manoeuvre file"
_NS_PER_S = 1e9


@dataclass(frozen=True)
class Manoeuvre:
    """One burn: a constant RTN acceleration between two epochs.

    Attributes
    ----------
    start, end : numpy.datetime64
        Epochs of the burn (ns, the file's time system).
    acc_rtn_m_s2 : tuple of float
        Acceleration in R, T, N [m/s²].
    """

    start: np.datetime64
    end: np.datetime64
    acc_rtn_m_s2: tuple[float, float, float]

    @property
    def duration_s(self) -> float:
        """Length of the burn [s]."""
        return float((self.end - self.start) / np.timedelta64(1, "ns")) / _NS_PER_S

    @property
    def dv_rtn_m_s(self) -> np.ndarray:
        """Velocity change acceleration × duration [m/s], shape (3,)."""
        return np.asarray(self.acc_rtn_m_s2, dtype=float) * self.duration_s


def _epoch(text: str, path, line: int, field: str) -> np.datetime64:
    """``YYYY-MM-DDThh:mm:ss[.fffffffff]`` -> datetime64[ns] (io._fields.iso_epoch_ns)."""
    return np.datetime64(iso_epoch_ns(text, path, line, field), "ns")


def read_manoeuvres(path: str | Path) -> tuple[tuple[Manoeuvre, ...], dict[str, str]]:
    """Read a manoeuvre file (module docstring).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    manoeuvres : tuple of Manoeuvre
        In file order (time order).
    header : dict of str to str
        The ``# key: value`` comment lines (``satellite``, ``time system``).

    Raises
    ------
    FormatError
        Naming file, line and field: missing identification, a line without 8 fields, an epoch
        or number that does not parse, end not after start, a velocity change that is not
        acceleration × duration, burns out of order or overlapping.
    """
    lines = read_lines(path)
    require_line_end(lines, path)
    if not lines or not lines[0].startswith(MAGIC):
        raise FormatError(path, 1, "identification", f"first line must start with {MAGIC!r}")
    header: dict[str, str] = {}
    burns: list[Manoeuvre] = []
    for number, text in enumerate(lines, start=1):
        if text.startswith("#"):
            key, sep, value = text[1:].partition(":")
            if sep and number > 1:
                header[key.strip()] = value.strip()
            continue
        if not text.strip():
            continue
        parts = text.split()
        if len(parts) != 8:
            raise FormatError(path, number, "record", f"expected 8 fields (start end acc_R "
                              f"acc_T acc_N dv_R dv_T dv_N), found {len(parts)}")
        start = _epoch(parts[0], path, number, "start")
        end = _epoch(parts[1], path, number, "end")
        if not end > start:
            raise FormatError(path, number, "end", f"end {parts[1]} is not after start")
        names = ("acc_R", "acc_T", "acc_N", "dv_R", "dv_T", "dv_N")
        values = [parse_float(v, path=path, line=number, field=n,
                              kind="acceleration_m_s2" if n[0] == "a" else "velocity_change_m_s")
                  for v, n in zip(parts[2:], names)]
        burn = Manoeuvre(start, end, tuple(values[:3]))
        dv = np.asarray(values[3:])
        if not np.allclose(burn.dv_rtn_m_s, dv, rtol=1e-6, atol=1e-12):
            raise FormatError(path, number, "dv_R dv_T dv_N", f"velocity change {dv.tolist()} "
                              f"is not acceleration x duration {burn.dv_rtn_m_s.tolist()}")
        if burns and start < burns[-1].end:
            raise FormatError(path, number, "start", "burns must be in time order and must "
                              "not overlap")
        burns.append(burn)
    return tuple(burns), header
