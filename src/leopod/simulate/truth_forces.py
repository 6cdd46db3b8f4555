"""Truth force model of the closed-loop simulator: configuration and random parameter values.

The truth orbit (:mod:`leopod.simulate.truth_orbit`) is integrated under a force model that
deliberately differs from what an estimator will use:

* gravity ITU_GRACE16 (satkit-data) to degree 150 (the default campaign's estimator: the same
  field to degree 120, so degrees 121-150 are the mismatch; EGM96 against a modern field would
  be an unrealistically large one);
* solid Earth tides (IERS 2010 steps 1-2), solid Earth and ocean pole tides; ocean tides only
  when a FES2004 file is given;
* Sun and Moon (DE421), relativity (IERS 2010 eq. 10.12);
* drag: cannonball with NRLMSISE-00 density (CelesTrak space weather of satkit-data) and a
  drag scale factor that varies from one 90-min interval to the next,
  ``s_k = 1 + 0.15 sin(2π t_k / 1 d) + N(0, 0.05²)`` (t_k: midpoint of interval k since
  the start of the arc);
* solar radiation pressure: cannonball with the conical Earth shadow, scale 1;
* unmodelled stochastic accelerations: piecewise constant in R, T, N over 10-min intervals,
  drawn from N(0, σ²) with σ = (2, 5, 3)·1e-8 m/s² (an ``empirical`` section with
  ``directions: [R, T, N]``, ``terms: [const]``, not estimated).

**Formations.** Two satellites a few km apart (LT-1 B ~5 km, 0.7 s, behind LT-1 A) fly
through the same thermosphere and the same radiation environment: density structures
(travelling atmospheric disturbances, gravity waves, the day-night bulge) have horizontal scales
of hundreds to thousands of km (a physical argument, not a fitted model: the correlation of
Gaussian-shaped structures of scale L across a separation d is ``exp(−d²/2L²)``, 0.9999 for
d = 5 km and L = 300 km), and twins of one design in the same
attitude see the same Sun, albedo and Earth infrared. What differs is the satellites'
own part: ballistic coefficient and surface properties (a few per cent for twins of one
design, propellant use) and thermal re-radiation. A follower's truth therefore samples the
leader's random field, drawn from the leader's own seed, with a correlation ``ρ``
(``satellites.<sat>.formation.truth_correlation``)::

    x_B = ρ x_A + sqrt(1 − ρ²) x_B,own

for each stochastic acceleration component and for the random part ``N(0, σ²)`` of each drag
scale (the periodic part is already common). Each satellite alone keeps the statistics of
the single-satellite truth (variance σ²); the differential part ``x_B − x_A`` has the sigma
``σ sqrt(2 (1 − ρ))`` (ρ = 0.999: 4.5 % of σ, i.e. (0.9, 2.2, 1.3)e-9 m/s² in R, T, N for
the default σ). The intervals are the same in time for both (the 0.7-s lag of the follower
moves an interval edge by 0.1 % of its 600 s, ignored). ρ = 0 gives the independent draws of
two unrelated satellites, bit-identical to the truth before formations shared a field.

The per-interval values enter the integration as the force-model parameter vector (in the
order of ``ForceModel.parameters``), not as a-priori values, so they are exact and stored
with the orbit. All draws come from ``numpy.random.SeedSequence(seed)``: the same seed gives
bit-identical orbits.

Magnitudes along the default orbit (2019-01-01, 6 h, RMS): drag 3e-10 m/s², SRP 4e-8 m/s²,
stochastic accelerations 6e-8 m/s², Sun and Moon 9e-7 m/s²; the gravity difference
ITU_GRACE16 to 150 minus the same field to 120 is only 1e-12 m/s² at 971 km (6 h RMS; the
attenuation (R/r)^n kills degrees above 120), so at this altitude the dynamic mismatch is the
drag and the stochastic accelerations (EGM96 to 150 minus EGM2008 to 120 would be
2.5e-7 m/s², mostly degrees 10-30).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from leopod.dynamics.forces import ForceModel, apriori_parameters, interval_edges
from leopod.settings import Settings

__all__ = ["TruthDynamics", "TruthForces", "default_models", "truth_force_config"]

_RTN = ["R", "T", "N"]


@dataclass(frozen=True)
class TruthDynamics(Settings):
    """Settings of the truth force model (config ``simulate.truth``; the schema's defaults:
    HY-2B-like cannonball).

    Attributes
    ----------
    gravity_degree : int
        Maximum degree of the gravity field.
    mass_kg : float
        Spacecraft mass [kg].
    drag_area_m2, srp_area_m2 : float
        Cross-sections for drag and radiation pressure [m²] (illustrative values for a
        box-wing satellite with ~10 m² of Sun-pointing arrays).
    drag_coefficient, reflectivity_coefficient : float
        C_D and C_R (M&G 2000, sec. 3.5.1 and 3.4.1).
    drag_interval_s : float
        Length of the intervals of constant drag scale [s].
    drag_scale_amplitude, drag_scale_period_s, drag_scale_sigma : float
        ``s_k = 1 + amplitude sin(2π t_k / period) + N(0, sigma²)``.
    stochastic_interval_s : float
        Length of the intervals of constant stochastic acceleration [s].
    stochastic_sigma_rtn_m_s2 : tuple of float
        Standard deviations of the stochastic accelerations in R, T, N [m/s²].
    """

    SCHEMA_DEF = "simulate_truth"

    gravity_degree: int
    mass_kg: float
    drag_area_m2: float
    srp_area_m2: float
    drag_coefficient: float
    reflectivity_coefficient: float
    drag_interval_s: float
    drag_scale_amplitude: float
    drag_scale_period_s: float
    drag_scale_sigma: float
    stochastic_interval_s: float
    stochastic_sigma_rtn_m_s2: tuple[float, float, float]


def default_models() -> dict[str, Path | None]:
    """Installed model files: ITU_GRACE16 and CelesTrak space weather from satkit-data, no ocean
    tides (keys ``gravity_field``, ``space_weather``, ``ocean_tides``)."""
    import satkit_data

    data = Path(satkit_data.__file__).parent / "data"
    return {"gravity_field": data / "ITU_GRACE16.gfc", "space_weather": data / "SW-All.csv",
            "ocean_tides": None}


@dataclass(frozen=True, eq=False)
class TruthForces:
    """Truth force-model configuration and the values of its per-interval parameters.

    Attributes
    ----------
    config : dict
        Configuration for :func:`leopod.dynamics.force_config.build_force_model`.
    span_s : float
        Length of the arc [s] (force-model time runs from 0 to ``span_s``).
    drag_edges_s : ndarray, shape (n_drag + 1,)
        Interval boundaries of the drag scale [s since the arc start].
    drag_scale : ndarray, shape (n_drag,)
        Drag scale factor per interval.
    stochastic_edges_s : ndarray, shape (n_stoch + 1,)
        Interval boundaries of the stochastic accelerations [s since the arc start].
    stochastic_acc_rtn_m_s2 : ndarray, shape (n_stoch, 3)
        Stochastic accelerations in R, T, N per interval [m/s²].
    values : dict of str to float
        The same values under their force-model parameter names (``drag_scale_k``,
        ``emp_const_R_k``, ``emp_const_T_k``, ``emp_const_N_k``).
    """

    config: dict
    span_s: float
    drag_edges_s: np.ndarray
    drag_scale: np.ndarray
    stochastic_edges_s: np.ndarray
    stochastic_acc_rtn_m_s2: np.ndarray
    values: dict[str, float] = field(init=False, repr=False)

    def __post_init__(self):
        values = {f"drag_scale_{k}": float(s) for k, s in enumerate(self.drag_scale)}
        for k, acc in enumerate(self.stochastic_acc_rtn_m_s2):
            values.update({f"emp_const_{axis}_{k}": float(a) for axis, a in zip(_RTN, acc)})
        object.__setattr__(self, "values", values)

    def parameter_vector(self, force_model: ForceModel) -> np.ndarray:
        """Parameters (P,) of ``force_model`` (built from :attr:`config`): the truth values
        of the drag scales and stochastic accelerations, the a priori values otherwise
        (SRP scale 1).

        Raises
        ------
        ValueError
            If a truth parameter is not in the force model (config and arc do not match).
        """
        params = apriori_parameters(force_model)
        index = {name: i for i, name in enumerate(force_model.parameters)}
        missing = sorted(set(self.values) - set(index))
        if missing:
            raise ValueError(f"truth parameters not in the force model: {missing[:5]}")
        for name, value in self.values.items():
            params[index[name]] = value
        return params


def _drag_scales(edges_s: np.ndarray, dyn: TruthDynamics, noise: np.ndarray):
    """``1 + A sin(2π t_mid / P) + noise`` per interval (``noise``: the N(0, σ²) draws)."""
    mid = 0.5 * (edges_s[:-1] + edges_s[1:])
    periodic = dyn.drag_scale_amplitude * np.sin(2.0 * np.pi * mid / dyn.drag_scale_period_s)
    return 1.0 + periodic + noise


def _random_draws(span_s: float, seed: int, dyn: TruthDynamics
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The random parameters of an arc from ``seed``: drag-interval edges (n_drag + 1,),
    drag-scale noise ``N(0, σ²)`` (n_drag,), stochastic-interval edges (n_stoch + 1,) and
    stochastic accelerations (n_stoch, 3) [m/s²] (two streams spawned from
    ``numpy.random.SeedSequence(seed)``)."""
    drag_rng, stoch_rng = (np.random.default_rng(s)
                           for s in np.random.SeedSequence(seed).spawn(2))
    drag_edges = interval_edges(0.0, span_s, dyn.drag_interval_s)
    stoch_edges = interval_edges(0.0, span_s, dyn.stochastic_interval_s)
    sigma = np.asarray(dyn.stochastic_sigma_rtn_m_s2, dtype=float)
    drag_noise = drag_rng.normal(0.0, dyn.drag_scale_sigma, drag_edges.size - 1)
    stoch = stoch_rng.normal(0.0, 1.0, (stoch_edges.size - 1, 3)) * sigma
    return drag_edges, drag_noise, stoch_edges, stoch


def truth_force_config(span_s: float, *, seed: int, dynamics: TruthDynamics | None = None,
                       models: Mapping[str, object] | None = None,
                       common_seed: int | None = None,
                       correlation: float = 0.0) -> TruthForces:
    """Truth force model of an arc of ``span_s`` seconds and its random parameter values.

    Parameters
    ----------
    span_s : float
        Arc length [s] (intervals start at the arc start; the last one may be shorter).
    seed : int
        Seed of the drag-scale noise and of the stochastic accelerations (two independent
        streams spawned from ``numpy.random.SeedSequence(seed)``).
    dynamics : TruthDynamics, optional
        Force settings (default HY-2B-like).
    models : mapping, optional
        Overrides of :func:`default_models`: ``gravity_field`` (ICGEM path or Dataset),
        ``space_weather`` (CelesTrak CSV), ``ocean_tides`` (FES2004 path or None).
    common_seed : int, optional
        Seed of the field that a formation shares (the leader's ``seed``): the draws of
        ``seed`` are then mixed with those of ``common_seed`` (module docstring, Formations).
        None: the satellite's own draws only.
    correlation : float
        ρ in [0, 1] of the mix with the common field (used with ``common_seed``).

    Returns
    -------
    TruthForces
    """
    dyn = TruthDynamics.from_config({}) if dynamics is None else dynamics
    files = {**default_models(), **dict(models or {})}
    drag_edges, drag_noise, stoch_edges, stoch = _random_draws(span_s, seed, dyn)
    if common_seed is not None:
        if not 0.0 <= correlation <= 1.0:
            raise ValueError(f"correlation must be in [0, 1], not {correlation}")
        _, common_drag, _, common_stoch = _random_draws(span_s, common_seed, dyn)
        own = float(np.sqrt(1.0 - correlation**2))
        drag_noise = correlation * common_drag + own * drag_noise
        stoch = correlation * common_stoch + own * stoch
    config = {
        # the truth needs no partials: a degree-2 gradient keeps the force model cheap
        "gravity": {"field": files["gravity_field"], "max_degree": dyn.gravity_degree,
                    "gradient_degree": 2},
        "tides": {"solid": True, "solid_pole": True, "ocean_pole": True,
                  "ocean": files["ocean_tides"]},
        "third_body": {"sun": True, "moon": True},
        "relativity": {"lense_thirring": True, "de_sitter": True},
        "drag": {"area_m2": dyn.drag_area_m2, "mass_kg": dyn.mass_kg,
                 "drag_coefficient": dyn.drag_coefficient, "density": "msis",
                 "space_weather": files["space_weather"], "interval_s": dyn.drag_interval_s,
                 "estimate": False},
        "srp": {"area_m2": dyn.srp_area_m2, "mass_kg": dyn.mass_kg,
                "reflectivity_coefficient": dyn.reflectivity_coefficient, "estimate": False},
        "empirical": {"interval_s": dyn.stochastic_interval_s, "directions": list(_RTN),
                      "terms": ["const"], "estimate": False},
    }
    return TruthForces(config=config, span_s=float(span_s), drag_edges_s=drag_edges,
                       drag_scale=_drag_scales(drag_edges, dyn, drag_noise),
                       stochastic_edges_s=stoch_edges, stochastic_acc_rtn_m_s2=stoch)

