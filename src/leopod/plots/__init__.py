"""Figures of the workflow steps (matplotlib, Agg backend)."""

from collections.abc import Mapping
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
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


def by_solution(data: xr.Dataset | Mapping[str, xr.Dataset]) -> dict[str, xr.Dataset]:
    """``{label: Dataset}`` of the solutions to draw; a single Dataset gets the empty label."""
    if isinstance(data, xr.Dataset):
        return {"": data}
    if not data:
        raise ValueError("no solutions to plot")
    return dict(data)
