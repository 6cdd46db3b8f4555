"""Rule quality: data quality of one satellite-day (leopod.gnss.quality, leopod.plots.quality)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
from collections.abc import Mapping

import numpy as np
import xarray as xr

from leopod.astro.sun import sun_position_ef
from leopod.codebias.scb import NADIR_VARIABLE, correct_bds2_scb
from leopod.frames.attitude import antenna_angles
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes_ef
from leopod.gnss.antenna_terms import antenna_terms
from leopod.gnss.leo_antenna import antenna_frame_of
from leopod.gnss.quality import QualitySettings, assess_quality, merge_systems
from leopod.gnss.scb import nadir_angle_deg
from leopod.gnss.signal_bias import SignalBiases, correct_signal_biases, read_signal_biases
from leopod.io._text import write_text
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.io.product_netcdf import read_antenna_product
from leopod.plots.quality import (
    plot_code_noise,
    plot_mp_elevation,
    plot_skyplot,
    plot_visibility,
    summary_html,
)
from leopod.signals import SystemSignals, code_band, signal_settings
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def day_antenna_terms(obs: xr.Dataset, gnss: xr.Dataset, leo: xr.Dataset,
                      signals: Mapping[str, SystemSignals], pco_body_m: Mapping | None,
                      antenna_path=None, gnss_attitude: str = "nominal",
                      attitude: LeoAttitude | None = None) -> xr.Dataset:
    """Antenna range terms of the bands of the phases and codes of every system
    (leopod.gnss.antenna_terms):
    the POD's LEO PCOs per band and satellite antennas (same file as the POD)."""
    bands = {s: sorted({code_band(c) for c in (*sig.phase, *sig.code, *sig.pod_code)})
             for s, sig in signals.items()}
    antex = read_antenna_product(antenna_path) if antenna_path else None
    times = obs.time.values
    return antenna_terms(times, obs.sv.values, leo.pos_m.values, leo.vel_m_s.values,
                         gnss.pos_m.values, sun_position_ef(times), bands, pco_body_m,
                         antex=antex, gnss_attitude=gnss_attitude, leo_attitude=attitude)


def main(obs_path, gnss_path, leo_path, signals: Mapping[str, SystemSignals],
         settings: QualitySettings, title: str, outputs: Mapping, *, bds2_scb: bool,
         pco_body_m: Mapping | None = None, antenna_path=None,
         signal_biases: SignalBiases | None = None, gnss_attitude: str = "nominal",
         attitude: LeoAttitude | None = None) -> None:
    """Quality of the ingest outputs (paths) into ``outputs``: ``nc``, ``mp_elevation``,
    ``skyplot``, ``noise``, ``visibility`` (PNG) and ``summary`` (HTML); the satellite signal
    biases of ``signal_biases`` (OSB/DCB, leopod.gnss.signal_bias) are removed first and, with
    ``bds2_scb``, the BDS-2 IGSO/MEO codes are corrected for the satellite-induced code bias.
    The multipath is formed without the antenna terms of the LEO PCOs ``pco_body_m`` (per band)
    and the satellite antennas of ``antenna_path`` (oriented by ``gnss_attitude``, the POD's
    setting), which the output keeps for the ambiguity step. The antenna-frame angles and the
    LEO PCO terms follow the satellite's attitude law ``attitude`` (None: nominal); with an
    ANTEX antenna (``pco_body_m`` a LeoAntenna) the angles are those of its antenna frame and
    its PCV per band is removed with its PCO."""
    obs = load_netcdf(obs_path, "ingest observation")
    gnss = load_netcdf(gnss_path, "ingest GNSS geometry").reindex(sv=obs.sv.values)
    leo = load_netcdf(leo_path, "a-priori orbit")
    rot = leo_body_axes_ef(attitude, obs.time.values, leo.pos_m.values, leo.vel_m_s.values)
    los = gnss.pos_m.values - leo.pos_m.values[:, None, :]
    el, az = antenna_angles(rot, los, antenna_frame_of(pco_body_m))
    log.info("epochs without a-priori orbit (no angles): %d",
             int((~np.isfinite(leo.pos_m.values[:, 0])).sum()))
    # nadir angle at the GNSS satellites (the argument of the BDS-2 SCB); both Earth-fixed
    nadir = xr.DataArray(nadir_angle_deg(gnss.pos_m.values, leo.pos_m.values[:, None, :]),
                         coords={"time": obs.time, "sv": obs.sv}, dims=("time", "sv"),
                         attrs={"units": "degree", "long_name": "nadir angle at the GNSS "
                                "satellite of the line to the LEO"})
    obs, _ = correct_signal_biases(
        obs, signal_biases, [c for sig in signals.values() for c in sig.observations])
    if bds2_scb:   # multipath and noise of the codes the POD and AR will use
        obs, summary = correct_bds2_scb(obs, xr.Dataset({NADIR_VARIABLE: nadir}))
        log.info("BDS-2 SCB correction: %s", summary or "no BDS-2 IGSO/MEO codes")
    terms = day_antenna_terms(obs, gnss, leo, signals, pco_body_m, antenna_path,
                              gnss_attitude, attitude)
    parts = [assess_quality(obs, el, az, system, sig.phase, sig.code, sig.pod_code, settings,
                            antenna=terms)
             for system, sig in signals.items()]
    quality = merge_systems(parts)
    quality.attrs.update(terms.attrs)
    log.info("antenna terms removed from the multipath: LEO PCO %s; GNSS %s",
             terms.attrs["antenna_leo_pco_body_m"], terms.attrs["antenna_gnss"])
    quality[NADIR_VARIABLE] = nadir.reindex(sv=quality.sv)
    quality.attrs["bds2_scb"] = int(bds2_scb)
    write_netcdf(quality, outputs["nc"], step="quality",
                 inputs=[obs_path, gnss_path, leo_path, *([antenna_path] if antenna_path else [])],
                 time_system="GPS", reference_frame="antenna", title=f"data quality {title}")
    plot_mp_elevation(parts[0], outputs["mp_elevation"], title)
    plot_skyplot(parts[0], outputs["skyplot"], title)
    plot_code_noise(parts[0], outputs["noise"], title)
    plot_visibility(parts[0], outputs["visibility"], title)
    write_text(outputs["summary"], summary_html(parts, title))
    log.info("summary: %s", outputs["summary"])


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    main(sm.input.obs, sm.input.gnss, sm.input.leo, signal_settings(sm.params.signals),
         QualitySettings.from_config(sm.params.settings), sm.params.title, plain(sm.output),
         bds2_scb=bool(sm.params.bds2_scb), pco_body_m=leo_antenna_of(sm.params.pco_body_m, sm.params.leo_antenna, plain(sm.input)),
         antenna_path=getattr(sm.input, "antenna", None) or None,
         gnss_attitude=getattr(sm.params, "gnss_attitude", "nominal"),
         attitude=load_leo_attitude(sm.params.attitude, attitude_files(sm)),
         signal_biases=read_signal_biases(plain(sm.input),
                                          getattr(sm.params, "signal_bias", None)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("quality", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
