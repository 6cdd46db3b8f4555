"""Rule float_pod: float reduced-dynamic POD of one satellite-day (leopod.estimation.arc)."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

from collections.abc import Mapping

from leopod.codebias.apply import CodeCorrection
from leopod.dynamics.force_config import ForceModelSettings
from leopod.estimation.arc import ArcData, ArcSettings, run_arc
from leopod.estimation.float_pod import PodSettings
from leopod.estimation.write import ARC_PRODUCTS, gate_arc, log_arc, write_arc, write_linearisation
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.attitude import load_leo_attitude
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
         code_correction: CodeCorrection | None, yaw_flips, title: str, sp3_id: str,
         signal_bias: Mapping | None = None, attitude: LeoAttitude | None = None,
         gate: GateSettings | None = None) -> None:
    """Float POD of the arc of ``date`` from the files ``inputs`` into the files ``outputs``.

    ``inputs``: lists ``obs``, ``quality``, ``leo``, ``orbit``, ``clock`` and optional
    ``antenna``, ``code_bias`` paths; ``outputs``: the paths of ``ARC_PRODUCTS`` and
    ``ARC_FIGURES``, and optionally ``linearisation`` (the last linearisation, for the fixed
    POD: :mod:`leopod.estimation.linearisation`).
    The settings are those of :func:`leopod.estimation.arc.run_arc`; ``gate`` (the quality
    gate, :mod:`leopod.validation.quality_gate`) marks the day in the log and the parameters
    file.
    """
    data = ArcData.read(inputs, signal_bias=signal_bias, sampling_s=arc.sampling_s)
    solution = run_arc(date, data, signals, arc, pod, forces, pco_body_m,
                       code_correction=code_correction, yaw_flips=yaw_flips, attitude=attitude)
    log_arc(solution, f"float POD {date}")
    if gate is not None:
        gate_arc(solution, gate, f"float POD {date}", parse_date_id(date), arc.sampling_s)
    write_arc(solution, **{k: outputs[k] for k in ARC_PRODUCTS}, step="float_pod",
              kind="float", title=title, sp3_id=sp3_id, inputs=data.files,
              day=parse_date_id(date), coordinate_system=data.coordinate_system)
    if "linearisation" in outputs:
        write_linearisation(solution, outputs["linearisation"], title=title, inputs=data.files)
    plot_arc(solution.orbit, solution.residuals, **{k: outputs[k] for k in ARC_FIGURES},
             title=title, solution="float", reference="a-priori (code-only) orbit")


def run(sm) -> None:
    """Call :func:`main` with the job's files and settings."""
    configure_logging(sm)
    p = sm.params
    main(sm.wildcards.date, plain(sm.input), plain(sm.output),
         **pod_settings(p.signals, p.pod, p.code_bias, p.macro_model),
         pco_body_m=leo_antenna_of(p.pco_body_m, p.leo_antenna, plain(sm.input)),
         yaw_flips=p.yaw_flips, title=p.title, sp3_id=p.sp3_id,
         signal_bias=getattr(p, "signal_bias", None), attitude=load_leo_attitude(p.attitude, attitude_files(sm)),
         gate=GateSettings.from_config(p.pod["quality_gate"]))


if __name__ == "__main__":
    if "snakemake" not in globals():  # by hand: a job of the default campaign
        from leopod.workflow.boundary import mock_snakemake

        snakemake = mock_snakemake("float_pod", sat="hy2b-sim", date="2019-002")
    run(snakemake)  # noqa: F821 (injected by Snakemake)
