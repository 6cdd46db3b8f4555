"""Rule pcv_stack: the PCV maps of several periods stacked, with the differences between
consecutive periods (leopod.antenna.pcv.stack_maps)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import xarray as xr

from leopod.antenna.pcv import (
    PcvSettings,
    apriori_pattern,
    estimated_pattern,
    map_differences,
    pco_shift_neu,
    stack_maps,
)
from leopod.io import write_text
from leopod.io.antex_write import write_antex
from leopod.io.netcdf import write_netcdf
from leopod.plots.pcv import plot_pcv_map
from leopod.workflow.boundary import leo_antenna_of, plain
from leopod.workflow.log import configure_logging

log = logging.getLogger("leopod.pcv_stack")


def main(map_paths, outputs: Mapping, *, antenna, settings: PcvSettings, sat: str,
         title: str) -> None:
    """Stack the period maps (paths in time order) into ``outputs``: ``nc``, ``antex`` (the
    POD's antenna ``antenna`` with the stacked map added), ``map`` (PNG) and
    ``differences`` (CSV)."""
    maps = [xr.load_dataset(p) for p in map_paths]
    stacked = stack_maps(maps, settings)
    write_netcdf(stacked, outputs["nc"], step="pcv_stack", inputs=map_paths,
                 reference_frame="antenna", title=f"stacked PCV map {title}")
    apriori, _ = apriori_pattern(antenna)
    shift = pco_shift_neu(antenna, stacked)
    write_antex(outputs["antex"], [estimated_pattern(apriori, stacked, serial=sat[:20],
                                                     pco_shift_neu_m=shift)],
                comments=[c[:60] for c in (
                    f"leopod rule pcv_stack: {sat}, {len(maps)} periods",
                    f"{stacked.attrs['period']}",
                    "PCV = a-priori PCV + ionosphere-free map,",
                    "filled in for every frequency; PCO as a priori"
                    + (" + PCO-Z" if shift.any() else ""))])
    lines = ["period_a,period_b,rms_difference_m,n_nodes"]
    for a, b, rms, n in map_differences(maps):
        lines.append(f"{a},{b},{rms:.5f},{n}")
        log.info("PCV map difference %s - %s: RMS %.2f mm over %d nodes", b, a, 1e3 * rms, n)
    write_text(outputs["differences"], "\n".join(lines) + "\n")
    plot_pcv_map(stacked, outputs["map"], title=f"{title} stacked")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    files = plain(sm.input)
    main(files["maps"], plain(sm.output),
         antenna=leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, files),
         settings=PcvSettings.from_config(sm.params.settings), sat=sm.wildcards.sat,
         title=sm.params.title)


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("pcv_stack", sat="hy2b-sim")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
