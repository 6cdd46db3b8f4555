"""Snakemake script of rule code_bias: see leopod.codebias.period and leopod.plots.codebias."""

from leopod.codebias.period import estimate_period, map_settings
from leopod.codebias.products import statistics_csv
from leopod.codebias.samples import load_quality
from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.codebias import plot_code_bias_counts, plot_code_bias_maps, plot_mp_elevation
from leopod.workflow.log import configure_logging


def main(inp, out, params, sat, period, log):
    cfg = params.settings
    quality = [load_quality(p, cfg["signals"]) for p in inp.quality]
    maps, stats = estimate_period(quality, cfg["signals"], map_settings(cfg), period=period,
                                  satellite=sat, yaw_flips=params.yaw_flips,
                                  min_elevation_deg=cfg["min_elevation_deg"])
    write_netcdf(maps, out.nc, step="code_bias", inputs=inp.quality, time_system="GPS",
                 reference_frame="antenna", title=f"code-bias maps {params.title}")
    write_text(out.statistics, statistics_csv(maps))
    plot_code_bias_maps(maps, out.maps, title=f"code-bias maps {params.title}")
    plot_code_bias_counts(maps, out.counts, title=f"observations per node {params.title}")
    plot_mp_elevation({s: (st.el_deg, st.before_m, st.after_m) for s, st in stats.items()},
                      maps, out.mp_elevation, title=f"code multipath {params.title}")


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.input, sm.output, sm.params, sm.wildcards.sat, sm.wildcards.period, log)
