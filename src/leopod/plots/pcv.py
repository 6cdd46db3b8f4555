"""Sky plots of an estimated PCV map (rule ``pcv``; Wang et al. 2024, Fig. 6).

Polar plots in the antenna frame as :func:`leopod.plots.quality.plot_skyplot` draws them:
azimuth 0° at the top (+X, flight direction, by default) increasing clockwise towards +Y,
zenith angle radial with the boresight at the centre. Each node is drawn over its
neighbourhood (± half a step), the cell whose residuals it averages.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

from leopod.plots import save_figure  # noqa: E402

__all__ = ["plot_pcv_map"]

_M_TO_MM = 1e3


def _edges(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Cell edges in azimuth [rad] and zenith [deg] centred on the nodes."""
    da, dz = float(ds.attrs["az_step_deg"]), float(ds.attrs["zenith_step_deg"])
    az = np.r_[ds.azimuth_deg.values - da / 2, ds.azimuth_deg.values[-1] + da / 2]
    zen = np.clip(np.r_[ds.zenith_deg.values - dz / 2, ds.zenith_deg.values[-1] + dz / 2],
                  0.0, 90.0)
    return np.radians(az), zen


def _polar(fig, pos):
    ax = fig.add_subplot(pos, projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_rlim(0, 90)
    # zenith rings; the rim (90°, the horizon) unlabelled, where the azimuth 90° label sits
    ax.set_yticks([30, 60], ["30°", "60°"])
    ax.set_rlabel_position(112.5)
    ax.grid(alpha=0.3)
    return ax


def plot_pcv_map(ds: xr.Dataset, path, title: str = "") -> None:
    """Estimated ΔPCV [mm] and residuals per node (two polar panels); the colour scale of
    ΔPCV is symmetric, to the 98th percentile of its magnitude.

    Parameters
    ----------
    ds : xarray.Dataset
        Map Dataset of :func:`leopod.antenna.pcv.stack_residuals`: ``pcv_if_m`` and
        ``count`` (azimuth_deg, zenith_deg), attributes ``az_step_deg``,
        ``zenith_step_deg``, ``datum``.
    path : str or path-like
        PNG to write.
    title : str
        Prefix of the figure title.
    """
    theta, zen = _edges(ds)
    pcv = ds.pcv_if_m.values * _M_TO_MM
    finite = np.abs(pcv[np.isfinite(pcv)])
    vmax = float(np.percentile(finite, 98)) if finite.size and finite.max() > 0 else 1.0
    fig = plt.figure(figsize=(11, 5.4))
    ax = _polar(fig, 121)
    mesh = ax.pcolormesh(theta, zen, np.ma.masked_invalid(pcv.T), cmap="RdBu_r",
                         vmin=-vmax, vmax=vmax, shading="flat", rasterized=True)
    fig.colorbar(mesh, ax=ax, shrink=0.7, pad=0.1, label="ΔPCV ionosphere-free [mm]")
    rms = float(np.sqrt(np.nanmean(pcv**2))) if finite.size else float("nan")
    ax.set_title(f"ΔPCV, datum {ds.attrs['datum']} (RMS {rms:.2f} mm)", fontsize=10)
    ax = _polar(fig, 122)
    count = ds["count"].values.astype(float)
    mesh = ax.pcolormesh(theta, zen, np.ma.masked_less(count.T, 1), cmap="viridis",
                         norm=LogNorm(vmin=1, vmax=max(count.max(), 10)), shading="flat",
                         rasterized=True)
    fig.colorbar(mesh, ax=ax, shrink=0.7, pad=0.1, label="phase observations per node")
    ax.set_title(f"phase observations per node (estimated: ≥ {ds.attrs['min_count']})",
                 fontsize=10)
    head = f"{title}: " if title else ""
    fig.suptitle(f"{head}phase centre variation, {ds.attrs['az_step_deg']:g}° × "
                 f"{ds.attrs['zenith_step_deg']:g}° (antenna frame, azimuth 0° = +X = flight "
                 "direction, zenith angle radial)", fontsize=10)
    save_figure(fig, path)
