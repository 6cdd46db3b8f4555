"""Typed settings of the steps from the sections of a validated campaign configuration.

Scripts call these at the script boundary (:mod:`leopod.workflow.boundary`); below them the
library takes only frozen settings and resolved paths, never a configuration dict.
"""

from __future__ import annotations

from collections.abc import Mapping

from leopod.codebias.apply import CodeCorrection
from leopod.dynamics.force_config import ForceModelSettings
from leopod.dynamics.model_files import resolve_model_paths
from leopod.dynamics.plates import macro_model_from_config
from leopod.estimation.arc import ArcSettings
from leopod.estimation.float_pod import PodSettings
from leopod.signals import signal_settings

__all__ = ["pod_settings"]


def pod_settings(signals: Mapping, pod: Mapping, code_bias: Mapping,
                 macro_model: Mapping | None = None) -> dict:
    """Settings of a POD step (float or fixed) as keyword arguments of ``run_arc``.

    Parameters
    ----------
    signals, pod, code_bias : mapping
        The validated ``signals``, ``pod`` and ``code_bias`` sections.
    macro_model : mapping, optional
        The validated ``satellites.<sat>.macro_model`` (None: no plates).

    Returns
    -------
    dict
        ``signals`` (:class:`~leopod.signals.SystemSignals` of ``pod.system``, or a dict of
        them per system when ``pod.system`` is a list), ``arc``
        (:class:`~leopod.estimation.arc.ArcSettings`), ``pod``
        (:class:`~leopod.estimation.float_pod.PodSettings`), ``forces`` (the force
        configuration with ``satkit:`` model names resolved to installed files and the
        satellite's plates) and
        ``code_correction`` (:class:`~leopod.codebias.apply.CodeCorrection`).
    """
    system = pod["system"]
    by_system = signal_settings(signals)
    return {"signals": (by_system[system] if isinstance(system, str)
                        else {x: by_system[x] for x in system}),
            "arc": ArcSettings.from_config(pod), "pod": PodSettings.from_config(pod),
            "forces": ForceModelSettings.from_config(
                resolve_model_paths(pod["forces"]),
                macro_model_from_config(macro_model, "satellites.<sat>.macro_model")),
            "code_correction": CodeCorrection.from_config(code_bias)}
