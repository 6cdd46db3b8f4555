"""Writer of CODE-style differential code bias (DCB) files (satellite rows only).

The layout, the sign (``DCB(P1−C1) = bias(P1) − bias(C1)``) and the Dataset schema are those
of the reader, :mod:`leopod.io.dcb`: a title line, a dashed line, the
``DIFFERENTIAL (P1-C1) CODE BIASES FOR SATELLITES AND RECEIVERS:`` block title, the
``PRN / STATION NAME`` column header and its ``***`` marker line, then one row per satellite
with the PRN in columns 1-3 and value and RMS in ns as F13.3 and F12.3 (columns 23-35 and
36-47), as in CODE's ``P1C10810_RINEX.DCB``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text

__all__ = ["write_code_dcb"]

_S_TO_NS = 1e9


def write_code_dcb(ds: xr.Dataset, path: str | Path, *, title: str | None = None,
                   allow_empty: bool = False) -> None:
    """Write the satellite DCBs of ``ds`` as a CODE DCB file.

    Parameters
    ----------
    ds : xarray.Dataset
        ``dcb_s`` (sv) [s], optional ``dcb_sigma_s`` (sv) [s] (NaN or absent: written as 0),
        attribute ``dcb_type`` (e.g. ``"P1-C1"``); NaN values are skipped.
    path : str or Path
        Output file.
    title : str, optional
        First line (default: ``"<agency> <dcb_type> DCB SOLUTION"`` from
        ``attrs["title"]`` or a generic text).
    allow_empty : bool
        Write the header alone when no value is finite (the reader then refuses the file
        with a message naming it) instead of raising.

    Raises
    ------
    ValueError
        If ``dcb_type`` is missing or not of the form ``Xn-Yn``, or no value is finite (and
        not ``allow_empty``).
    """
    dcb_type = str(ds.attrs.get("dcb_type", ""))
    if len(dcb_type) != 5 or dcb_type[2] != "-":
        raise ValueError(f"write_code_dcb({path}): attribute dcb_type {dcb_type!r} is not of "
                         "the form 'P1-C1'")
    values = ds["dcb_s"].values * _S_TO_NS
    sigma = (ds["dcb_sigma_s"].values * _S_TO_NS if "dcb_sigma_s" in ds
             else np.zeros_like(values))
    keep = np.isfinite(values)
    if not keep.any() and not allow_empty:
        raise ValueError(f"write_code_dcb({path}): no finite DCB value")
    head = title or ds.attrs.get("title") or f"GNSS {dcb_type} DCB SOLUTION"
    if dcb_type not in head:
        raise ValueError(f"write_code_dcb({path}): the title {head!r} must name {dcb_type}")
    lines = [head[:80], "-" * 80, "",
             f"DIFFERENTIAL ({dcb_type}) CODE BIASES FOR SATELLITES AND RECEIVERS:", "",
             "PRN / STATION NAME        VALUE (NS)  RMS (NS)",
             "***   ****************    *****.***   *****.***"]
    for sv, v, s in zip(ds["sv"].values[keep], values[keep], sigma[keep], strict=True):
        lines.append(f"{sv!s:<3s}{'':19s}{v:13.3f}{np.nan_to_num(s):12.3f}")
    write_text(path, "\n".join(lines) + "\n")
