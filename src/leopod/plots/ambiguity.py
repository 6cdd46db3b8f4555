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


def _guard_line(table: xr.Dataset, lane: str) -> str:
    """The product guard's figures of one lane (attributes of the table), or ""."""
    n = table.attrs.get(f"{lane}_guard_n_sd")
    if not n:
        return "guard: not tested"
    return (f"guard: {n} SDs, mean cos {table.attrs[f'{lane}_guard_mean_cos']:.2f}, "
            f"p = {table.attrs[f'{lane}_guard_p_value']:.2g}")


def plot_fractional_parts(table: xr.Dataset, path, *, title: str = "") -> None:
    """Histograms of the WL and NL fractional parts (float minus nearest integer) [cycles].

    Parameters
    ----------
    table : xarray.Dataset
        Single-difference table of :func:`leopod.ambiguity.resolve.resolve_arc`: every
        candidate with a finite value is drawn (fixed ones filled, others outlined), with the
        fixing rates and the product guard's verdict and statistics
        (:mod:`leopod.ambiguity.consistency`) from its attributes.
    path : str or Path
        PNG file.
    title : str
        Satellite and day.
    """
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), sharey=False)
    bins = np.linspace(-0.5, 0.5, 41)
    for ax, lane, limit_key in ((axes[0], "wl", "WL"), (axes[1], "nl", "NL")):
        frac = table[f"{lane}_fraction_cyc"].values
        fixed = table[f"{lane}_fixed"].values == 1
        ok = np.isfinite(frac)
        ax.hist(frac[ok & fixed], bins=bins, color="tab:blue", label=f"fixed ({(ok & fixed).sum()})")
        ax.hist(frac[ok & ~fixed], bins=bins, histtype="step", color="tab:red",
                label=f"not fixed ({(ok & ~fixed).sum()})")
        rate = table.attrs.get(f"{lane}_fixing_rate", np.nan)
        ax.set_title(f"{limit_key}: fixing rate {100 * rate:.1f} % (independent set)\n"
                     f"{_guard_line(table, lane)}", fontsize=9)
        ax.set_xlabel("float minus nearest integer [cycles]")
        ax.set_ylabel("single differences")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    verdict = table.attrs.get("product_guard", "not tested")
    fig.suptitle(_heading(title, f"fractional parts of the single-difference ambiguities; "
                                 f"AR product {verdict}"))
    fig.tight_layout()
    save_figure(fig, path)
