"""Rule code_bias: antenna-frame code-bias maps of one satellite and period
(leopod.codebias.period, leopod.plots.codebias)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

from leopod.codebias.estimate import MapSettings
from leopod.codebias.period import estimate_period
from leopod.codebias.products import statistics_csv
from leopod.codebias.samples import load_quality
from leopod.io import write_text
from leopod.io.netcdf import write_netcdf
from leopod.plots.codebias import plot_code_bias_counts, plot_code_bias_maps, plot_mp_elevation
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging


def main(quality_paths, outputs: Mapping, *, codes, settings: MapSettings,
         min_elevation_deg: float, sat: str, period: str, yaw_flips, title: str,
         sampling_s: float | None = None) -> None:
    """Maps of ``codes`` (None: every code assessed) from the daily quality files of a period
    into ``outputs``: ``nc``, ``statistics`` (CSV), ``maps``, ``counts``, ``mp_elevation``;
    the epochs on the grid of ``sampling_s`` [s] only (None: every epoch)."""
    quality = [load_quality(p, codes, step_s=sampling_s) for p in quality_paths]
    maps, stats = estimate_period(quality, codes, settings, period=period, satellite=sat,
                                  yaw_flips=yaw_flips, min_elevation_deg=min_elevation_deg)
    write_netcdf(maps, outputs["nc"], step="code_bias", inputs=quality_paths, time_system="GPS",
                 reference_frame="antenna", title=f"code-bias maps {title}")
    write_text(outputs["statistics"], statistics_csv(maps))
    plot_code_bias_maps(maps, outputs["maps"], title=title)
    plot_code_bias_counts(maps, outputs["counts"], title=title)
    plot_mp_elevation({s: (st.el_deg, st.before_m, st.after_m) for s, st in stats.items()},
                      maps, outputs["mp_elevation"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    cfg = sm.params.settings
    main(list(sm.input.quality), plain(sm.output), codes=cfg["signals"],
         settings=MapSettings.from_config(cfg), min_elevation_deg=cfg["min_elevation_deg"],
         sat=sm.wildcards.sat, period=sm.wildcards.period, yaw_flips=sm.params.yaw_flips,
         title=sm.params.title, sampling_s=cfg["sampling_s"])


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("code_bias", sat="hy2b-sim", period="2019-01")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
