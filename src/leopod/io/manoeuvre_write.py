"""Writer of leopod manoeuvre files (format: :mod:`leopod.io.manoeuvre`)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from leopod.io.manoeuvre import MAGIC, Manoeuvre

__all__ = ["write_manoeuvres"]


def _iso(epoch: np.datetime64) -> str:
    return str(np.datetime64(epoch, "us"))


def write_manoeuvres(path: str | Path, manoeuvres: Sequence[Manoeuvre], *, satellite: str,
                     time_system: str = "GPS") -> None:
    """Write the burns of a satellite, one line each (an empty list writes the header only).

    Parameters
    ----------
    path : str or Path
        Output file.
    manoeuvres : sequence of Manoeuvre
        In time order, not overlapping.
    satellite : str
        Satellite id for the header.
    time_system : str
        Time system of the epochs.

    Raises
    ------
    ValueError
        If the burns are out of order or overlap (the reader would reject the file).
    """
    for a, b in zip(manoeuvres[:-1], manoeuvres[1:]):
        if b.start < a.end:
            raise ValueError(f"manoeuvres out of order or overlapping: {a.start} .. {b.start}")
    lines = [f"{MAGIC} 1.0", f"# satellite: {satellite}", f"# time system: {time_system}",
             "# start end acc_R acc_T acc_N [m/s2] dv_R dv_T dv_N [m/s]"]
    for m in manoeuvres:
        acc = " ".join(f"{a:.10e}" for a in m.acc_rtn_m_s2)
        dv = " ".join(f"{v:.10e}" for v in m.dv_rtn_m_s)
        lines.append(f"{_iso(m.start)} {_iso(m.end)} {acc} {dv}")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
