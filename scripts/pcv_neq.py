"""Rule pcv_neq: the day's reduced normal equations of the PCV nodes (and PCO-Z) for the direct
method (leopod.antenna.pcv_direct)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

from leopod.ambiguity.resolve import ArSettings
from leopod.antenna.pcv import PcvSettings
from leopod.antenna.pcv_direct import arc_normals
from leopod.estimation.arc import ArcData
from leopod.estimation.fixed_arc import FloatSolution
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import load_netcdf, write_netcdf
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging
from leopod.workflow.settings import pod_settings


def main(date: str, sat: str, inputs: Mapping, outputs: Mapping, *, settings: PcvSettings,
         pod: Mapping, pco_body_m, ambiguity: ArSettings | None, yaw_flips,
         signal_bias: Mapping | None = None, attitude: LeoAttitude | None = None) -> None:
    """Normal equations of the arc of ``date`` into ``outputs["neq"]``.

    ``inputs``: those of scripts/float_pod.py plus ``float_orbit``, ``float_parameters``,
    ``float_ambiguities``, ``float_residuals`` (float POD) and, for the fixed POD, ``table``
    (ambiguity step); ``pod``: :func:`leopod.workflow.settings.pod_settings` of the POD.
    """
    arc = pod["arc"]
    data = ArcData.read(inputs, signal_bias=signal_bias, sampling_s=arc.sampling_s)
    float_solution = FloatSolution.read(parameters=inputs["float_parameters"],
                                        ambiguities=inputs["float_ambiguities"],
                                        residuals=inputs["float_residuals"],
                                        orbit=inputs["float_orbit"])
    table = load_netcdf(inputs["table"], "ambiguity table") if "table" in inputs else None
    neq = arc_normals(date, data, pod["signals"], arc, pod["pod"], pod["forces"], pco_body_m,
                      float_solution, settings, table=table, ambiguity=ambiguity,
                      satellite=sat, code_correction=pod["code_correction"],
                      yaw_flips=yaw_flips, attitude=attitude)
    write_netcdf(neq, outputs["neq"], step="pcv_neq", reference_frame="antenna",
                 inputs=[*(inputs[k] for k in ("float_parameters", "float_orbit")),
                         *([inputs["table"]] if table is not None else []), *data.files],
                 title=f"PCV normal equations {sat} {date}")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    inputs = plain(sm.input)
    main(sm.wildcards.date, sm.wildcards.sat, inputs, plain(sm.output),
         settings=PcvSettings.from_config(p.pcv), pod=pod_settings(p.signals, p.pod, p.code_bias),
         pco_body_m=leo_antenna_of(p.pco_body_m, p.leo_antenna, inputs),
         ambiguity=ArSettings.from_config(p.settings) if "table" in inputs else None,
         yaw_flips=p.yaw_flips, signal_bias=getattr(p, "signal_bias", None),
         attitude=load_leo_attitude(p.attitude, attitude_files(sm)))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("pcv_neq", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
