"""Rule gnss_products: a day's GNSS orbits (SP3), clocks (RINEX clock) and satellite antennas
(ANTEX) parsed once and written as netCDF for ingest and the POD (leopod.io.product_netcdf)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging

import numpy as np

from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.product_netcdf import satellite_antenna_dataset, write_product
from leopod.io.sp3 import read_sp3
from leopod.time.calendar import parse_date_id
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)

#: Satellite antennas are kept for the day and one day either side: every epoch at which the
#: day's ingest or POD arc (at most 12 h beyond the day, pod.arc_before_s/arc_after_s in the
#: schema) chooses an antenna entry lies inside.
ANTENNA_MARGIN = np.timedelta64(1, "D")


def main(date: str, orbit_path, clock_path, antex_path, out_orbit, out_clock, out_antenna,
         systems: list[str]) -> None:
    """Parse the products of day ``date`` (``clock_path``/``antex_path`` and their outputs
    may be None) and write them as netCDF; all are parsed before any file is written."""
    orbit = read_sp3(orbit_path, gps_time=True)
    clock = read_rinex_clock(clock_path, gps_time=True) if clock_path else None
    antennas = None
    if antex_path:
        day = np.datetime64(parse_date_id(date), "ns")
        start, end = day - ANTENNA_MARGIN, day + np.timedelta64(1, "D") + ANTENNA_MARGIN
        antennas = satellite_antenna_dataset(read_antex(antex_path), systems, start, end)
        log.info("%s: %d satellite antenna entries of %s valid in %s .. %s", antex_path,
                 antennas.sizes["antenna"], "".join(systems), start, end)
    log.info("%s: %d epochs, %d satellites", orbit_path, orbit.sizes["time"], orbit.sizes["sv"])
    if clock is not None:
        log.info("%s: %d epochs, %d satellites", clock_path, clock.sizes["time"],
                 clock.sizes["sv"])
    products = [(orbit, out_orbit, orbit_path, "GNSS orbits (SP3)",
                 str(orbit.attrs.get("coordinate_system", "ITRF"))),
                (clock, out_clock, clock_path, "GNSS clocks (RINEX clock)", None),
                (antennas, out_antenna, antex_path, "GNSS satellite antennas (ANTEX)",
                 "satellite body")]
    written = []
    try:
        for ds, out, source, title, frame in products:
            if ds is not None:
                written.append(write_product(ds, out, inputs=[source], title=title,
                                             reference_frame=frame))
    except BaseException:
        for path in written:  # all or nothing: no partial set of products
            path.unlink(missing_ok=True)
        raise


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.wildcards.date, orbit_path=sm.input.orbit, clock_path=sm.input.get("clock"),
         antex_path=sm.input.get("antex"), out_orbit=sm.output.orbit,
         out_clock=sm.output.get("clock"), out_antenna=sm.output.get("antenna"),
         systems=list(sm.params.systems))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("gnss_products", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
