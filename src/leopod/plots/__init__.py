"""Figures of the workflow steps (matplotlib, Agg backend)."""

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.layout_engine import PlaceHolderLayoutEngine

from leopod.io.netcdf import atomic_path

#: Resolution of every workflow figure [dots per inch].
DPI = 110
#: zlib level of the PNG files: level 1 encodes a POD residual figure twice as fast as the
#: default 6 for files 2-10 % larger (the same pixels).
PNG_COMPRESS_LEVEL = 1


#: Metadata that would stamp a file with the software or the time, left out per format, and
#: a fixed salt of the SVG element ids: the same figure gives the same bytes.
_NO_STAMP = {"png": {"Software": None},
             "svg": {"Creator": None, "Date": None},
             "pdf": {"Creator": None, "Producer": None, "CreationDate": None}}


def save_figure(fig, path: str | Path) -> None:
    """Write a figure atomically (format from the name's suffix: png, svg, pdf; config
    ``report.figure_format``) and close it.

    No software or time stamp is written (:data:`_NO_STAMP`), so the same figure gives the
    same bytes; PNG files are compressed with :data:`PNG_COMPRESS_LEVEL`. A figure laid out by
    ``fig.tight_layout()`` keeps a placeholder layout engine, for which ``savefig`` would
    draw the whole figure once more before drawing it into the file (a tenth of the time of
    the POD figures); the layout is done, so the engine is dropped first (same pixels).
    """
    if isinstance(fig.get_layout_engine(), PlaceHolderLayoutEngine):
        fig.set_layout_engine(None)
    try:
        fmt = Path(path).suffix.lstrip(".").lower() or "png"
        extra = ({"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}} if fmt == "png"
                 else {})
        with atomic_path(path) as tmp, plt.rc_context({"svg.hashsalt": "leopod"}):
            fig.savefig(tmp, format=fmt, dpi=DPI, metadata=_NO_STAMP.get(fmt), **extra)
    finally:
        plt.close(fig)


def dots(ax, x, y, *, size_pt2: float = 1.0, **style) -> None:
    """Point cloud of ``x``, ``y`` drawn as markers of one line (rasterised), not a scatter.

    Looks like ``ax.scatter(x, y, s=size_pt2, **style)`` with one colour (round markers of
    that area [pt²] with the default edge of 1 pt in the same colour) but Agg stamps one
    cached marker instead of a path per point: about 5 times faster for the tens of
    thousands of residuals of a POD day.
    """
    ax.plot(np.asarray(x), np.asarray(y), linestyle="none", marker="o",
            markersize=float(np.sqrt(size_pt2)), markeredgewidth=1.0, rasterized=True, **style)


def by_solution(data: xr.Dataset | Mapping[str, xr.Dataset]) -> dict[str, xr.Dataset]:
    """``{label: Dataset}`` of the solutions to draw; a single Dataset gets the empty label."""
    if isinstance(data, xr.Dataset):
        return {"": data}
    if not data:
        raise ValueError("no solutions to plot")
    return dict(data)
