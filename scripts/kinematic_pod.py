"""Rule kinematic_pod: kinematic positions and clocks of one satellite-day
(leopod.estimation.kinematic), linearised at the float reduced-dynamic orbit."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import textwrap
from collections.abc import Mapping

import numpy as np

from leopod.ambiguity.resolve import ArSettings
from leopod.codebias.apply import CodeCorrection
from leopod.dynamics.force_config import ForceModelSettings
from leopod.estimation.arc import ArcData, ArcSettings, setup_arc
from leopod.estimation.fixed_arc import constraints_of
from leopod.estimation.float_pod import PodSettings
from leopod.estimation.kinematic import (
    KinematicSettings,
    kinematic_dataset,
    kinematic_pod,
    kinematic_sp3_dataset,
)
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.io.sp3_write import write_sp3
from leopod.plots.kinematic import plot_kinematic_rtn
from leopod.signals import SystemSignals
from leopod.time.calendar import parse_date_id
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging
from leopod.workflow.settings import pod_settings


def main(date: str, inputs: Mapping, outputs: Mapping, *, signals: SystemSignals,
         arc: ArcSettings, pod: PodSettings, forces: ForceModelSettings,
         pco_body_m: Mapping | None, code_correction: CodeCorrection | None, yaw_flips,
         kinematic: KinematicSettings, ambiguity: ArSettings, title: str, sp3_id: str,
         signal_bias: Mapping | None = None, attitude: LeoAttitude | None = None) -> None:
    """Kinematic POD of the arc of ``date``; the epochs of the day are written.

    ``inputs``: those of scripts/float_pod.py plus ``float_orbit`` (the reference orbit) and,
    for ``kinematic.ambiguities == "fixed"``, ``table`` (ambiguity step); ``outputs``:
    ``nc``, ``sp3`` and ``figure`` paths.
    """
    data = ArcData.read(inputs, signal_bias=signal_bias, sampling_s=arc.sampling_s)
    reference = load_netcdf(inputs["float_orbit"])
    problem = setup_arc(date, data, signals, arc, forces, pco_body_m,
                        code_correction=code_correction, yaw_flips=yaw_flips,
                        apriori_orbit=reference.pos_itrf_m, attitude=attitude)
    constraints = None
    if kinematic.ambiguities == "fixed":
        constraints = constraints_of(load_netcdf(inputs["table"]),
                                     ambiguity.constraint_sigma_m)
    result = kinematic_pod(problem.observations, problem.products, reference, problem.t_ref,
                           pod, kinematic, eop=problem.eop, constraints=constraints,
                           **problem.antennas)
    day = np.datetime64(parse_date_id(date), "ns")
    ds = kinematic_dataset(result, eop=problem.eop).sel(
        time=slice(day, day + np.timedelta64(86400, "s") - np.timedelta64(1, "ns")))
    kind = f"kinematic ({kinematic.ambiguities} ambiguities)"
    write_netcdf(ds, outputs["nc"], step="kinematic_pod", reference_frame=data.coordinate_system,
                 title=f"{kind} orbit {title}", time_system="GPS",
                 inputs=[inputs["float_orbit"], *data.files,
                         *([inputs["table"]] if constraints is not None else [])])
    write_sp3(kinematic_sp3_dataset(ds, sp3_id), outputs["sp3"], orbit_type="KIN",
              coordinate_system=data.coordinate_system,
              comments=tuple(textwrap.wrap(f"leopod {kind} orbit {title}; record "
                                           "accuracy exponents: formal sigmas", 77)))
    plot_kinematic_rtn(ds, outputs["figure"], title=title)


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.wildcards.date, plain(sm.input), plain(sm.output),
         **pod_settings(p.signals, p.pod, p.code_bias), pco_body_m=leo_antenna_of(p.pco_body_m, p.leo_antenna, plain(sm.input)),
         yaw_flips=p.yaw_flips, kinematic=KinematicSettings.from_config(p.kinematic),
         ambiguity=ArSettings.from_config(p.settings), title=p.title, sp3_id=p.sp3_id,
         signal_bias=getattr(p, "signal_bias", None), attitude=load_leo_attitude(p.attitude, attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("kinematic_pod", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
