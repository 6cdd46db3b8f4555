"""Rule ingest: canonical observations, GNSS products at their epochs and the a-priori orbit
of one satellite-day (leopod.ingest)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import numpy as np

from leopod.frames.leo_attitude import LeoAttitude
from leopod.gnss.products import GnssProducts
from leopod.ingest import apriori_from_sp3, apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import write_netcdf
from leopod.io.product_netcdf import read_antenna_product, read_clock_product, read_orbit_product
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import SystemSignals, signal_settings
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(obs_path, orbit_path, clock_path, apriori_path, antenna_path, out_obs, out_gnss,
         out_leo, signals: Mapping[str, SystemSignals], pco_body_m, sp3_id,
         attitude: LeoAttitude | None = None) -> None:
    """Ingest one RINEX observation file with its GNSS products (paths; optional ones None)
    into ``out_obs``, ``out_gnss`` and ``out_leo`` (netCDF).

    The products are the netCDF files of the gnss_products rule (or SP3, RINEX clock and
    ANTEX files: :mod:`leopod.io.product_netcdf` reads either); ``apriori_path`` is an SP3
    file of the LEO."""
    raw = read_rinex_obs(obs_path, systems=list(signals))
    obs = canonical_observations(raw, signals)
    log.info("%s: %d epochs, %d satellites, signals %s", obs_path, obs.sizes["time"],
             obs.sizes["sv"], " ".join(k for k in obs.data_vars if "_" not in k))
    day_start = obs.time.values[0].astype("datetime64[D]")
    orbit = read_orbit_product(orbit_path)
    if clock_path:
        clock = read_clock_product(clock_path)
    else:
        log.warning("no clock product: the SP3 clock records of %s are used", orbit_path)
        clock = orbit
    products = GnssProducts.from_datasets(orbit, clock,
                                          day_start, systems=list(signals),
                                          max_extrapolation_s=900.0)
    gnss = gnss_at_epochs(products, obs.time.values)
    n_extra = int(gnss.extrapolated.values.any(axis=1).sum())
    if n_extra:
        log.warning("GNSS orbits extrapolated beyond the product at %d epochs (flagged)", n_extra)
    if apriori_path:
        leo = apriori_from_sp3(read_sp3(apriori_path, gps_time=True), sp3_id, obs.time.values)
    else:
        antex = read_antenna_product(antenna_path) if antenna_path else None
        leo = apriori_from_spp(obs, products, signals, pco_body_m, antex, attitude)
        log.info("code-only orbit: %d of %d epochs, median residual RMS %.2f m, median PDOP %.2f",
                 np.isfinite(leo.pos_m.values[:, 0]).sum(), leo.sizes["time"],
                 float(np.nanmedian(leo.rms_m)), float(np.nanmedian(leo.pdop)))
    inputs = [p for p in (obs_path, orbit_path, clock_path, apriori_path, antenna_path) if p]
    write_netcdf(obs, out_obs, step="ingest", inputs=inputs, time_system="GPS",
                 title="canonical GNSS observations")
    write_netcdf(gnss, out_gnss, step="ingest", inputs=inputs, time_system="GPS",
                 reference_frame=str(orbit.attrs.get("coordinate_system", "ITRF")),
                 title="GNSS orbits and clocks at observation epochs")
    write_netcdf(leo, out_leo, step="ingest", inputs=inputs, time_system="GPS",
                 reference_frame="ITRF", title="a-priori LEO orbit")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(obs_path=sm.input.obs, orbit_path=sm.input.orbit, clock_path=sm.input.get("clock"),
         apriori_path=sm.input.get("apriori"), antenna_path=sm.input.get("antenna"),
         out_obs=sm.output.obs, out_gnss=sm.output.gnss, out_leo=sm.output.leo,
         signals=signal_settings(sm.params.signals), pco_body_m=leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, plain(sm.input)),
         sp3_id=sm.params.sp3_id, attitude=load_leo_attitude(sm.params.attitude,
                                                            attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("ingest", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
