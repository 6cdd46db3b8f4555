"""Writer of CNES/CLS (GRG) wide-lane satellite biases as ``WL`` records.

The record layout, sign convention and Dataset schema are those of the reader,
:mod:`leopod.io.wlbias`; the RINEX clock E19.12 number format is that of
:mod:`leopod.io.clock_write`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from leopod.io._text import write_text
from leopod.io.clock_write import value_records
from leopod.io.wlbias import _SV

__all__ = ["wl_bias_records", "write_wl_bias"]


def wl_bias_records(ds: xr.Dataset) -> list[str]:
    """The ``WL`` records of ``ds`` as text lines of at most 59 characters.

    Layout of a RINEX clock data record (A2,1X,A4,1X,I4,4I3,F10.6,I3,3X,E19.12[,1X,E19.12]):
    e.g. ``WL G01 2016  1  1  0  0  0.000000  1   -0.123000000000E+00``; the second value
    (standard deviation) is written only where ``wl_bias_sigma_cyc`` is finite. Lines with
    one value fit the 60 columns of a RINEX header ``COMMENT``, so they can be passed as
    ``comments`` to :func:`leopod.io.clock_write.write_rinex_clock` to give a clock file in the
    GRG style (WL records in its header), which :func:`read_wl_bias` reads.

    Parameters
    ----------
    ds : xarray.Dataset
        ``wl_bias_cyc`` (time, sv) [WL cycles] and optional ``wl_bias_sigma_cyc`` (time, sv),
        the schema of :func:`read_wl_bias`; NaN entries are skipped. Values are written with
        the sign they have in ``ds`` (CNES convention: see :func:`write_wl_bias`).

    Returns
    -------
    list of str
        One line per finite (time, sv), time-major, satellites in ``ds`` order.

    Raises
    ------
    ValueError
        If ``wl_bias_cyc`` is missing or a satellite id is not of the form ``G01``.
    """
    if "wl_bias_cyc" not in ds:
        raise ValueError("the Dataset has no 'wl_bias_cyc' variable")
    value = ds["wl_bias_cyc"].transpose("time", "sv").values
    sigma = (ds["wl_bias_sigma_cyc"].transpose("time", "sv").values
             if "wl_bias_sigma_cyc" in ds else np.full(value.shape, np.nan))
    svs = [str(s) for s in ds["sv"].values]
    bad = [s for s in svs if not _SV.match(s)]
    if bad:
        raise ValueError(f"satellite ids must look like 'G01', got {bad}")
    epochs = [_epoch_text(t) for t in ds["time"].values.astype("datetime64[ns]")]
    return value_records("WL", svs, epochs, value, sigma)


def write_wl_bias(ds: xr.Dataset, path: str | Path) -> None:
    """Write wide-lane satellite biases as a file of CNES/CLS ``WL`` records.

    The file holds only ``WL`` lines (:func:`wl_bias_records`), which :func:`read_wl_bias`
    reads back exactly to 12 significant digits (E19.12). It is written atomically; a name
    ending in ``.gz`` is gzip-compressed.

    Sign convention: the value is written as given. The convention of the CNES/CLS files,
    followed by the simulator (:func:`leopod.simulate.biases.ar_products`), is taken to be
    ``HMW/λ_WL = N_WL + μ_r − μ^s`` with ``μ^s`` the file value, i.e. the file holds the
    negative of the satellite term of the HMW combination: the public GRG converter
    (YuanxinPan/clkcomb, ``read_grg_bias`` and ``grg2snx.cpp``) negates the value to get that
    term. A user fixes ``N_WL = HMW/λ_WL + μ^s − μ_r``.

    Parameters
    ----------
    ds : xarray.Dataset
        ``wl_bias_cyc`` (time, sv) [WL cycles], optional ``wl_bias_sigma_cyc`` (time, sv).
    path : str or Path
        Output file.

    Raises
    ------
    ValueError
        As :func:`wl_bias_records`, or if no value is finite.
    """
    lines = wl_bias_records(ds)
    if not lines:
        raise ValueError("no finite wide-lane bias to write")
    text = "\n".join(lines) + "\n"
    write_text(path, text)


def _epoch_text(t: np.datetime64) -> str:
    """``I4,4I3,F10.6`` epoch of a RINEX clock data record (1 µs resolution)."""
    day = t.astype("datetime64[D]")
    us = int((t - day) / np.timedelta64(1, "us"))
    year, month, dom = (int(x) for x in str(day).split("-"))
    hour, rest = divmod(us, 3_600_000_000)
    minute, rest = divmod(rest, 60_000_000)
    return f"{year:4d}{month:3d}{dom:3d}{hour:3d}{minute:3d}{rest / 1e6:10.6f}"
