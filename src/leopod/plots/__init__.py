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


def fixed_layout(fig, *, left: float = 0.95, right: float = 0.25, bottom: float = 0.6,
                 top: float = 0.7, wspace: float = 0.2, hspace: float = 0.2) -> None:
    """Place a figure's subplots with fixed margins instead of ``fig.tight_layout()``.

    ``tight_layout`` measures every tick label and title before the figure is drawn, which
    draws most of it twice (a quarter of the time of a day's quality, POD and ambiguity
    figures, issue 18). The daily figures have the same axes and labels every day, so their
    margins are fixed per figure: those ``tight_layout`` chose for the default campaign's
    figures plus room for wider tick labels (e.g. ``−0.025``), looked at in the browser.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    left, right, bottom, top : float
        Margins between the figure edge and the subplots [in]: the left one holds the tick
        labels and y label, the bottom one the x label, the top one the (sup)titles.
    wspace, hspace : float
        Space between subplots as a fraction of the mean subplot width and height
        (matplotlib's ``subplots_adjust`` convention).
    """
    width, height = fig.get_size_inches()
    fig.subplots_adjust(left=left / width, right=1.0 - right / width, bottom=bottom / height,
                        top=1.0 - top / height, wspace=wspace, hspace=hspace)


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
