"""Figures of the ambiguity resolution: fractional parts of the WL and NL single differences."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from leopod.plots import save_figure
from leopod.plots.pod import _heading

__all__ = ["plot_fractional_parts"]


def plot_fractional_parts(table: xr.Dataset, path, *, title: str = "") -> None:
    """Histograms of the WL and NL fractional parts (float minus nearest integer) [cycles].

    Parameters
    ----------
    table : xarray.Dataset
        Single-difference table of :func:`leopod.ambiguity.resolve.resolve_arc` (rows with
        ``independent`` set are drawn; fixed ones filled, others outlined).
    path : str or Path
        PNG file.
    title : str
        Satellite and day.
    """
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=False)
    bins = np.linspace(-0.5, 0.5, 41)
    sel = table.independent.values == 1
    for ax, lane, limit_key in ((axes[0], "wl", "WL"), (axes[1], "nl", "NL")):
        frac = table[f"{lane}_fraction_cyc"].values[sel]
        fixed = table[f"{lane}_fixed"].values[sel] == 1
        ok = np.isfinite(frac)
        ax.hist(frac[ok & fixed], bins=bins, color="tab:blue", label=f"fixed ({(ok & fixed).sum()})")
        ax.hist(frac[ok & ~fixed], bins=bins, histtype="step", color="tab:red",
                label=f"not fixed ({(ok & ~fixed).sum()})")
        rate = table.attrs.get(f"{lane}_fixing_rate", np.nan)
        ax.set_title(f"{limit_key}: fixing rate {100 * rate:.1f} % (independent set)")
        ax.set_xlabel("float minus nearest integer [cycles]")
        ax.set_ylabel("single differences")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(_heading(title, "fractional parts of the single-difference ambiguities"))
    fig.tight_layout()
    save_figure(fig, path)
