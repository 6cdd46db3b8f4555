"""Figures of the workflow steps (matplotlib, Agg backend)."""

from collections.abc import Mapping

import xarray as xr


def by_solution(data: xr.Dataset | Mapping[str, xr.Dataset]) -> dict[str, xr.Dataset]:
    """``{label: Dataset}`` of the solutions to draw; a single Dataset gets the empty label."""
    if isinstance(data, xr.Dataset):
        return {"": data}
    if not data:
        raise ValueError("no solutions to plot")
    return dict(data)
