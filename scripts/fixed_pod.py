"""Rule fixed_pod: the float POD re-solved with the fixed ambiguities (estimation.fixed_arc)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

from leopod.ambiguity.resolve import ArSettings
from leopod.codebias.apply import CodeCorrection
from leopod.dynamics.force_config import ForceModelSettings
from leopod.estimation.arc import ArcData, ArcSettings
from leopod.estimation.fixed_arc import FloatSolution, run_fixed_arc
from leopod.estimation.float_pod import PodSettings
from leopod.estimation.linearisation import read_linearisation
from leopod.estimation.write import ARC_PRODUCTS, gate_arc, log_arc, write_arc
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
from leopod.io.netcdf import load_netcdf
from leopod.plots.pod import ARC_FIGURES, plot_arc
from leopod.signals import SystemSignals
from leopod.time.calendar import parse_date_id
from leopod.validation.quality_gate import GateSettings
from leopod.workflow.boundary import attitude_files, leo_antenna_of, plain
from leopod.workflow.log import configure_logging
from leopod.workflow.settings import pod_settings


def main(date: str, inputs: Mapping, outputs: Mapping, *, signals: SystemSignals,
         arc: ArcSettings, pod: PodSettings, forces: ForceModelSettings,
         pco_body_m: Mapping | None,
         code_correction: CodeCorrection | None, yaw_flips, ambiguity: ArSettings,
         title: str, sp3_id: str, signal_bias: Mapping | None = None,
         attitude: LeoAttitude | None = None, gate: GateSettings | None = None) -> None:
    """Ambiguity-fixed POD of the arc of ``date`` from ``inputs`` into ``outputs``.

    ``inputs``: those of scripts/float_pod.py plus ``table`` (ambiguity step) and
    ``float_orbit``, ``float_parameters``, ``float_ambiguities``, ``float_residuals`` and
    optionally ``linearisation`` (float POD; without it the orbit is integrated again at the
    float estimates); ``outputs``: the paths of ``ARC_PRODUCTS`` and ``ARC_FIGURES``; ``gate`` (the
    quality gate, :mod:`leopod.validation.quality_gate`) marks the day in the log and the
    parameters file.
    """
    data = ArcData.read(inputs, signal_bias=signal_bias, sampling_s=arc.sampling_s)
    float_solution = FloatSolution.read(parameters=inputs["float_parameters"],
                                        ambiguities=inputs["float_ambiguities"],
                                        residuals=inputs["float_residuals"],
                                        orbit=inputs["float_orbit"])
    linearisation = (read_linearisation(load_netcdf(inputs["linearisation"],
                                                    "float POD linearisation"))
                     if "linearisation" in inputs else None)
    fixed = run_fixed_arc(date, data, signals, arc, pod, forces, pco_body_m,
                          load_netcdf(inputs["table"], "ambiguity table"), float_solution, ambiguity,
                          code_correction=code_correction, yaw_flips=yaw_flips,
                          attitude=attitude, linearisation=linearisation)
    log_arc(fixed.arc, f"fixed POD {date}")
    if gate is not None:
        gate_arc(fixed.arc, gate, f"fixed POD {date}", parse_date_id(date), arc.sampling_s)
    write_arc(fixed.arc, **{k: outputs[k] for k in ARC_PRODUCTS}, step="fixed_pod",
              kind="ambiguity-fixed", title=title, sp3_id=sp3_id,
              inputs=[inputs["table"], inputs["float_orbit"], inputs["float_parameters"],
                      *([inputs["linearisation"]] if linearisation else []), *data.files],
              day=parse_date_id(date),
              coordinate_system=data.coordinate_system)
    plot_arc(fixed.arc.orbit, fixed.arc.residuals, **{k: outputs[k] for k in ARC_FIGURES},
             title=title, solution="ambiguity-fixed", reference="float POD orbit")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.wildcards.date, plain(sm.input), plain(sm.output),
         **pod_settings(p.signals, p.pod, p.code_bias, p.macro_model),
         pco_body_m=leo_antenna_of(p.pco_body_m, p.leo_antenna, plain(sm.input)),
         yaw_flips=p.yaw_flips, ambiguity=ArSettings.from_config(p.settings), title=p.title,
         sp3_id=p.sp3_id, signal_bias=getattr(p, "signal_bias", None),
         attitude=load_leo_attitude(p.attitude, attitude_files(sm)),
         gate=GateSettings.from_config(p.pod["quality_gate"]))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("fixed_pod", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
