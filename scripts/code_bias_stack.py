"""Rule code_bias_stack: maps of several periods stacked, and their differences
(leopod.codebias.products.stack_maps)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import itertools
import logging
from collections.abc import Mapping

from leopod.codebias.products import map_difference, stack_maps
from leopod.io import write_text
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.plots.codebias import plot_code_bias_maps, plot_map_difference
from leopod.workflow.boundary import plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(map_paths, outputs: Mapping, *, title: str) -> None:
    """Stack the period maps (paths in time order) into ``outputs``: ``nc``, ``differences``
    (CSV), ``maps`` and ``difference`` (PNG)."""
    maps = [load_netcdf(p) for p in map_paths]
    stacked = stack_maps(maps)
    write_netcdf(stacked, outputs["nc"], step="code_bias_stack", inputs=map_paths,
                 time_system="GPS", reference_frame="antenna",
                 title=f"{title} stacked")
    lines = ["period_a,period_b,signal,mode,rms_difference_m"]
    for a, b in itertools.pairwise(maps):
        _, rms = map_difference(a, b)
        for sig in rms.signal.values:
            for mode in rms.mode.values:
                value = float(rms.sel(signal=sig, mode=mode))
                lines.append(f"{a.attrs['period']},{b.attrs['period']},{sig},{mode},{value:.4f}")
                log.info("map difference %s - %s %s mode %d: RMS %.3f m", b.attrs["period"],
                         a.attrs["period"], sig, mode, value)
    write_text(outputs["differences"], "\n".join(lines) + "\n")
    plot_code_bias_maps(stacked, outputs["maps"], title=f"{title} stacked")
    plot_map_difference(maps[-2], maps[-1], outputs["difference"],
                        title=f"{title} {maps[-1].attrs['period']} minus "
                              f"{maps[-2].attrs['period']}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(list(sm.input.maps), plain(sm.output), title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("code_bias_stack", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
