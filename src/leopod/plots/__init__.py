"""Figures of the workflow steps (matplotlib, Agg backend)."""

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from leopod.io.netcdf import atomic_path

#: Resolution of every workflow figure [dots per inch].
DPI = 110


def save_figure(fig, path: str | Path) -> None:
    """Write a figure atomically (format from the name's suffix) and close it.

    No ``Software`` metadata is written, so the same figure gives the same bytes.
    """
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=Path(path).suffix.lstrip(".") or "png", dpi=DPI,
                        metadata={"Software": None})
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
