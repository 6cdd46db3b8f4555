"""Snakemake script of rule quality: see leopod.gnss.quality and leopod.plots.quality."""

import numpy as np
import xarray as xr

from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.quality import QualitySettings, assess_quality, merge_systems
from leopod.io._text import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.quality import (
    plot_code_noise,
    plot_mp_elevation,
    plot_skyplot,
    plot_visibility,
    summary_html,
)
from leopod.workflow.log import configure_logging


def main(obs_path, gnss_path, leo_path, signal_cfg, settings, title, out, log):
    with xr.open_dataset(obs_path) as f:
        obs = f.load()
    with xr.open_dataset(gnss_path) as f:
        gnss = f.load().reindex(sv=obs.sv.values)
    with xr.open_dataset(leo_path) as f:
        leo = f.load()
    rot = nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values)
    los = gnss.pos_m.values - leo.pos_m.values[:, None, :]
    el, az = antenna_angles(rot, los)
    log.info("epochs without a-priori orbit (no angles): %d",
             int((~np.isfinite(leo.pos_m.values[:, 0])).sum()))
    parts = [assess_quality(obs, el, az, system, cfg["phase"], cfg["code"], cfg["pod_code"],
                            QualitySettings(**settings))
             for system, cfg in signal_cfg.items()]
    quality = merge_systems(parts)
    write_netcdf(quality, out.nc, step="quality", inputs=[obs_path, gnss_path, leo_path],
                 time_system="GPS", reference_frame="antenna", title=f"data quality {title}")
    plot_mp_elevation(parts[0], out.mp_elevation, title)
    plot_skyplot(parts[0], out.skyplot, title)
    plot_code_noise(parts[0], out.noise, title)
    plot_visibility(parts[0], out.visibility, title)
    write_text(out.summary, summary_html(parts, title))
    log.info("summary: %s", out.summary)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    main(snakemake.input.obs, snakemake.input.gnss, snakemake.input.leo,  # noqa: F821
         snakemake.params.signals, snakemake.params.settings, snakemake.params.title,  # noqa: F821
         snakemake.output, log)  # noqa: F821
