"""Configurable force model in the GCRF for one orbit arc, built from a plain dict.

Forces (each a :class:`leopod.dynamics.forces.Force`, defined beside its physics; time ``t_s`` =
TT seconds since the reference epoch ``t_ref`` of the arc, a GPS-time datetime64 label; since
TT − GPST is constant, ``t_s`` is also GPS seconds since ``t_ref``):

* :class:`leopod.dynamics.gravity_field.EarthGravity` — static spherical-harmonic field
  (:class:`leopod.dynamics.gravity_field.GravityField`) plus the tidal
  ΔC̄nm, ΔS̄nm of :class:`leopod.dynamics.tides.TideModel` (solid Earth steps 1-2, ocean
  FES2004, solid and ocean pole tides; IERS Conventions 2010 ch. 6), evaluated in the ITRF and
  rotated: ``a = R ∇U(Rᵀ r)``, ``∂a/∂r = R G Rᵀ`` (G = ∇∇U; the tidal part of G, < 1e-7 of it,
  is neglected);
* :class:`leopod.dynamics.third_body.ThirdBodies` — Sun and Moon point masses with the indirect
  term (Montenbruck & Gill 2000, eq. 3.37), DE421;
* :class:`leopod.dynamics.relativity.Relativity` — IERS Conventions 2010 eq. (10.12) (partials
  neglected, ~1e-9 relative);
* :class:`leopod.dynamics.drag.Drag` — cannonball, Harris–Priester or NRLMSISE-00 density, a
  scale factor per interval (M&G 2000, sec. 3.5);
* :class:`leopod.dynamics.srp.SolarRadiation` — cannonball with the conical Earth shadow, scale
  factor(s) (M&G 2000, sec. 3.4);
* :class:`leopod.dynamics.empirical.Empirical` — constant + once-per-revolution accelerations
  per interval.

Slowly varying inputs (Earth rotation, Sun, Moon, tidal corrections) are interpolated on the
time grids of :class:`leopod.dynamics.environment.ArcEnvironment`. Per call (Swarm-A, degree 120
with its gradient): gravity ~40 µs, MSIS drag ~50 µs (Harris–Priester ~30 µs), the others
~2-7 µs each (benchmarks/dynamics_full.py).

Configuration (:func:`build_force_model`): a dict with one section per force; a force is off
when its section is absent, ``None``, ``False`` or has ``enabled: False``. Keys (defaults)::

    environment: rotation_step_s (60), ephemeris_step_s (600), ephemeris (None: DE421 of
                skyfield-data) -- grids shared by the forces (not a force)
    gravity:    field (ICGEM path or xarray Dataset from read_icgem), max_degree (120 or the
                field's degree if lower), gradient_degree (None: full degree; lower is
                faster, partials approximate)         -- off: point mass GM_E (IERS 2010)
    tides:      solid (True), ocean (FES2004 path or None), ocean_max_degree (30),
                solid_pole (True), ocean_pole (True), step_s (300)  -- applied to gravity
    third_body: sun (True), moon (True)
    relativity: lense_thirring (True), de_sitter (True)
    drag:       cd_area_mass_m2_kg, or drag_coefficient (2.3) with area_m2 and mass_kg;
                density ("msis" if space_weather is given, else "harris_priester"),
                space_weather (CelesTrak CSV),
                msis_version (0), hp_exponent (6), interval_s (None: one scale for the arc)
    srp:        cr_area_mass_m2_kg, or reflectivity_coefficient (1.3) with area_m2, mass_kg;
                shadow (True), r_earth_m (R_E), interval_s (None)
    empirical:  interval_s (10800), directions (["T", "N"]), terms (["const", "cos", "sin"])

and, in the drag, srp and empirical sections, ``apriori`` (scale 1, empirical 0), ``estimate``
(drag and empirical True, srp False) and ``sigma`` (a priori constraint, None = free), read by
:func:`leopod.dynamics.forces.apriori_parameters`, :func:`~leopod.dynamics.forces.estimated_parameters`
and :func:`~leopod.dynamics.forces.constraint_sigmas`.
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Mapping
from pathlib import Path

import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.constants import R_EARTH_EQUATOR_M
from leopod.dynamics.drag import Drag, HarrisPriesterDensity, MsisDensity
from leopod.dynamics.empirical import Empirical, EmpiricalModel
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.forces import Force, ForceModel, PointMassGravity, interval_edges
from leopod.dynamics.gravity_field import EarthGravity, GravityField, decimal_year
from leopod.dynamics.ocean_tides import OceanTides
from leopod.dynamics.relativity import Relativity
from leopod.dynamics.srp import SolarRadiation
from leopod.dynamics.third_body import ThirdBodies
from leopod.dynamics.tides import TideModel
from leopod.io.icgem import read_icgem
from leopod.io.space_weather import read_space_weather
from leopod.time.eop import EarthOrientation

__all__ = ["build_force_model"]

logger = logging.getLogger(__name__)

#: Default drag coefficient C_D of a compact LEO (M&G 2000, sec. 3.5.1: 2.0-2.3 typical) [1].
DEFAULT_DRAG_COEFFICIENT = 2.3
#: Default radiation pressure coefficient C_R = 1 + ε of a cannonball (M&G 2000, sec. 3.4.1) [1].
DEFAULT_REFLECTIVITY_COEFFICIENT = 1.3


# ---------------------------------------------------------------------------------- builder

_SECTIONS = {
    "environment": {"rotation_step_s", "ephemeris_step_s", "ephemeris"},
    "gravity": {"enabled", "field", "max_degree", "gradient_degree"},
    "tides": {"enabled", "solid", "ocean", "ocean_max_degree", "solid_pole", "ocean_pole",
              "step_s"},
    "third_body": {"enabled", "sun", "moon"},
    "relativity": {"enabled", "lense_thirring", "de_sitter"},
    "drag": {"enabled", "cd_area_mass_m2_kg", "drag_coefficient", "area_m2", "mass_kg",
             "density", "space_weather", "msis_version", "hp_exponent", "interval_s",
             "apriori", "estimate", "sigma"},
    "srp": {"enabled", "cr_area_mass_m2_kg", "reflectivity_coefficient", "area_m2", "mass_kg",
            "shadow", "r_earth_m", "interval_s", "apriori", "estimate", "sigma"},
    "empirical": {"enabled", "interval_s", "directions", "terms", "apriori", "estimate",
                  "sigma"},
}


def _section(config: Mapping, name: str) -> dict | None:
    """The settings of one force, or None if it is switched off."""
    value = config.get(name)
    if value is None or value is False:
        return None
    if value is True:
        return {}
    if not isinstance(value, Mapping):
        raise TypeError(f"force config '{name}' must be a mapping, True/False or None")
    unknown = sorted(set(value) - _SECTIONS[name])
    if unknown:
        raise ValueError(f"force config '{name}': unknown keys {unknown}")
    return None if not value.get("enabled", True) else dict(value)


@functools.lru_cache(maxsize=4)
def _read_icgem(path: str) -> xr.Dataset:
    return read_icgem(path)


@functools.lru_cache(maxsize=4)
def _ocean_tides(path: str, max_degree: int) -> OceanTides:
    return OceanTides.from_file(path, max_degree=max_degree)


@functools.lru_cache(maxsize=2)
def _space_weather(path: str) -> xr.Dataset:
    return read_space_weather(path)


def _area_mass(cfg: dict, key: str, coefficient_key: str, default: float) -> float:
    """C A/m [m²/kg] from ``key`` or from coefficient × area_m2 / mass_kg."""
    if key in cfg:
        return float(cfg[key])
    if "area_m2" not in cfg or "mass_kg" not in cfg:
        raise ValueError(f"give {key} or area_m2 and mass_kg")
    return float(cfg.get(coefficient_key, default)) * float(cfg["area_m2"]) / float(cfg["mass_kg"])


def _gravity(cfg: dict, tides_cfg: dict | None, env: ArcEnvironment) -> Force:
    if "field" not in cfg:
        raise ValueError("force config 'gravity' needs 'field' (ICGEM path or Dataset)")
    ds = cfg["field"]
    if not isinstance(ds, xr.Dataset):
        ds = _read_icgem(str(Path(ds)))
    epoch = decimal_year(env.t_ref)
    available = int(ds.attrs.get("max_degree", ds.sizes["n"] - 1))
    field = GravityField(ds, cfg.get("max_degree", min(120, available)), epoch_decimal_year=epoch)
    gradient_degree = cfg.get("gradient_degree")
    gradient_field = None
    if gradient_degree is not None and gradient_degree < field.max_degree:
        gradient_field = GravityField(ds, gradient_degree, epoch_decimal_year=epoch)
    tides = None
    if tides_cfg is not None:
        ocean = tides_cfg.get("ocean")
        if ocean is not None:
            ocean = _ocean_tides(str(Path(ocean)), int(tides_cfg.get("ocean_max_degree", 30)))
        try:
            tides = TideModel(field.tide_system, ocean=ocean, solid=tides_cfg.get("solid", True),
                              solid_pole=tides_cfg.get("solid_pole", True),
                              ocean_pole=tides_cfg.get("ocean_pole", True),
                              gm_earth_m3_s2=field.gm_m3_s2, radius_m=field.radius_m)
        except ValueError as err:
            raise ValueError(f"tides with the gravity field {field.modelname}: {err}") from None
        if not (tides.solid or tides.solid_pole or tides.ocean_pole or ocean is not None):
            tides = None
    return EarthGravity(field, env, tides, gradient_field=gradient_field,
                        tide_step_s=float((tides_cfg or {}).get("step_s", 300.0)))


def _drag(cfg: dict, env: ArcEnvironment) -> Drag:
    kind = cfg.get("density", "msis" if "space_weather" in cfg else "harris_priester")
    if kind == "msis":
        if "space_weather" not in cfg:
            raise ValueError("force config 'drag': density 'msis' needs 'space_weather'")
        density = MsisDensity(_space_weather(str(Path(cfg["space_weather"]))),
                              version=cfg.get("msis_version", 0))
    elif kind == "harris_priester":
        density = HarrisPriesterDensity(cfg.get("hp_exponent", 6.0))
    else:
        raise ValueError(f"force config 'drag': unknown density '{kind}' "
                         "(harris_priester or msis)")
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s"))
    return Drag(env, density, _area_mass(cfg, "cd_area_mass_m2_kg", "drag_coefficient",
                                         DEFAULT_DRAG_COEFFICIENT), edges,
                **_parameter_options(cfg, 1.0, True))


def _srp(cfg: dict, env: ArcEnvironment) -> SolarRadiation:
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s"))
    return SolarRadiation(env, _area_mass(cfg, "cr_area_mass_m2_kg", "reflectivity_coefficient",
                                          DEFAULT_REFLECTIVITY_COEFFICIENT), edges,
                          shadow=cfg.get("shadow", True),
                          r_earth_m=cfg.get("r_earth_m", R_EARTH_EQUATOR_M),
                          **_parameter_options(cfg, 1.0, False))


def _empirical(cfg: dict, env: ArcEnvironment) -> Empirical:
    edges = interval_edges(env.t_start_s, env.t_end_s, cfg.get("interval_s", 10800.0))
    model = EmpiricalModel(edges, directions=tuple(cfg.get("directions", ("T", "N"))),
                           terms=tuple(cfg.get("terms", ("const", "cos", "sin"))))
    return Empirical(model, **_parameter_options(cfg, 0.0, True))


def _parameter_options(cfg: dict, apriori: float, estimate: bool) -> dict:
    return {"apriori": cfg.get("apriori", apriori), "estimate": cfg.get("estimate", estimate),
            "sigma": cfg.get("sigma")}


def build_force_model(config: Mapping, t_ref, t_start_s: float, t_end_s: float, *,
                      eop: EarthOrientation | None = None,
                      environment: ArcEnvironment | None = None) -> ForceModel:
    """Force model of an arc from a plain configuration dict (module docstring).

    Parameters
    ----------
    config : mapping
        One section per force (``gravity``, ``tides``, ``third_body``, ``relativity``,
        ``drag``, ``srp``, ``empirical``) and optional ``environment`` grid settings.
    t_ref : datetime64
        Reference epoch (GPS-time label); force times are TT s since it.
    t_start_s, t_end_s : float
        The arc [s since ``t_ref``] (intervals of estimated parameters start at ``t_start_s``).
    eop : EarthOrientation, optional
        EOP (default: installed IERS data).
    environment : ArcEnvironment, optional
        Grids to reuse (must cover the arc); built from ``config["environment"]`` otherwise.

    Returns
    -------
    ForceModel
        Forces in the order gravity, third bodies, relativity, drag, SRP, empirical.
    """
    unknown = sorted(set(config) - set(_SECTIONS))
    if unknown:
        raise ValueError(f"force config: unknown sections {unknown} (known: {sorted(_SECTIONS)})")
    if environment is None:
        env_cfg = _section(config, "environment") or {}
        eph = env_cfg.get("ephemeris")
        environment = ArcEnvironment(
            t_ref, t_start_s, t_end_s, eop=eop,
            ephemeris=None if eph is None else Ephemeris(eph),
            rotation_step_s=env_cfg.get("rotation_step_s", 60.0),
            ephemeris_step_s=env_cfg.get("ephemeris_step_s", 600.0))
    env = environment
    forces: list[Force] = []
    gravity = _section(config, "gravity")
    forces.append(PointMassGravity() if gravity is None
                  else _gravity(gravity, _section(config, "tides"), env))
    third = _section(config, "third_body")
    if third is not None:
        forces.append(ThirdBodies(env, third.get("sun", True), third.get("moon", True)))
    rel = _section(config, "relativity")
    if rel is not None:
        forces.append(Relativity(env, rel.get("lense_thirring", True), rel.get("de_sitter", True)))
    for name, make in (("drag", _drag), ("srp", _srp), ("empirical", _empirical)):
        cfg = _section(config, name)
        if cfg is not None:
            forces.append(make(cfg, env))
    model = ForceModel(forces)
    logger.info("force model: %s; %d parameters", ", ".join(type(f).__name__ for f in forces),
                model.n_params)
    return model
