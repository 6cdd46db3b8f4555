"""Configurable force model in the GCRF for one orbit arc, built from typed settings.

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

drag, SRP and Earth radiation act on the plates of the satellite's macro model instead of a
cannonball when their section says ``plates: true`` (``ForceModelSettings.macro_model`` and
the ``attitude`` of :func:`build_force_model`; :mod:`leopod.dynamics.plates`);
* :class:`leopod.dynamics.srp.SolarRadiation` — cannonball with the conical Earth shadow, scale
  factor(s) (M&G 2000, sec. 3.4);
* :class:`leopod.dynamics.earth_radiation.EarthRadiation` — albedo and infrared of the Earth
  (Knocke et al. 1988), scale factor(s);
* :class:`leopod.dynamics.empirical.Empirical` — constant + once-per-revolution accelerations
  per interval;
* :class:`leopod.dynamics.manoeuvre.Manoeuvres` — a constant R/T/N acceleration over each burn
  of the satellite's manoeuvre list (``manoeuvres`` of :func:`build_force_model`; the section
  ``manoeuvre`` holds their a-priori sigma).

Slowly varying inputs (Earth rotation, Sun, Moon, tidal corrections) are interpolated on the
time grids of :class:`leopod.dynamics.environment.ArcEnvironment`. Per call (Swarm-A, degree 120
with its gradient): gravity ~40 µs, MSIS drag ~50 µs (Harris–Priester ~30 µs), the others
~2-7 µs each (benchmarks/dynamics_full.py).

Configuration: :class:`ForceModelSettings`, one typed section per force
(:class:`GravitySettings`, :class:`TideSettings`, :class:`ThirdBodySettings`,
:class:`RelativitySettings`, :class:`DragSettings`, :class:`SrpSettings`,
:class:`EarthRadiationSettings`, :class:`EmpiricalSettings`, :class:`ManoeuvreSettings`) and the grids of :class:`EnvironmentSettings`, built with
:meth:`ForceModelSettings.from_config` from the ``pod.forces`` section of a campaign (or any
mapping of that shape). A force is off when its section is absent, ``None``, ``False`` or has
``enabled: False``; the keys of a section present default to the campaign schema's
(``$defs/force_*``). Model files are paths (``satkit:`` names are resolved before, at the
script boundary, :func:`leopod.dynamics.model_files.resolve_model_paths`); the gravity field
may also be an xarray Dataset of :func:`leopod.io.icgem.read_icgem`. In the drag, srp,
earth_radiation and empirical sections ``apriori``, ``estimate`` and ``sigma`` (a-priori constraint, None = free)
are read by :func:`leopod.dynamics.forces.apriori_parameters`,
:func:`~leopod.dynamics.forces.estimated_parameters` and
:func:`~leopod.dynamics.forces.constraint_sigmas`.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from leopod.astro.ephemeris import Ephemeris
from leopod.dynamics.drag import Drag, HarrisPriesterDensity, MsisDensity
from leopod.dynamics.earth_radiation import EarthRadiation
from leopod.dynamics.empirical import Empirical, EmpiricalModel
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.forces import Force, ForceModel, PointMassGravity, interval_edges
from leopod.dynamics.gravity_field import EarthGravity, GravityField, decimal_year
from leopod.dynamics.manoeuvre import Manoeuvres
from leopod.dynamics.ocean_tides import OceanTides
from leopod.dynamics.plates import Plates
from leopod.dynamics.relativity import Relativity
from leopod.dynamics.srp import MacroModel, SolarRadiation
from leopod.dynamics.third_body import ThirdBodies
from leopod.dynamics.tides import TideModel
from leopod.frames.leo_attitude import LeoAttitude
from leopod.io.icgem import read_icgem
from leopod.io.manoeuvre import Manoeuvre
from leopod.io.space_weather import read_space_weather
from leopod.settings import Settings
from leopod.time.eop import EarthOrientation

__all__ = ["DragSettings", "EarthRadiationSettings", "EmpiricalSettings", "EnvironmentSettings",
           "ForceModelSettings",
           "GravitySettings", "ManoeuvreSettings", "RelativitySettings", "SrpSettings", "ThirdBodySettings",
           "TideSettings", "arc_environment", "build_force_model"]

logger = logging.getLogger(__name__)

# ---------------------------------------------------------------------------------- settings
@dataclass(frozen=True)
class EnvironmentSettings(Settings):
    """Grids of Earth rotation [s] and Sun/Moon positions [s], ephemeris file (None: DE421)."""

    SCHEMA_DEF = "force_environment"

    rotation_step_s: float
    ephemeris_step_s: float
    ephemeris: str | None


@dataclass(frozen=True)
class GravitySettings(Settings):
    """Static field: ICGEM path or Dataset, degree (None: 120 or the field's), gradient
    degree (None: full)."""

    SCHEMA_DEF = "force_gravity"

    field: object
    max_degree: int | None
    gradient_degree: int | None


@dataclass(frozen=True)
class TideSettings(Settings):
    """Tidal corrections: solid, ocean (FES2004 path or None) to ``ocean_max_degree``, solid
    and ocean pole tides, step of their table [s]."""

    SCHEMA_DEF = "force_tides"

    solid: bool
    ocean: str | None
    ocean_max_degree: int
    solid_pole: bool
    ocean_pole: bool
    step_s: float


@dataclass(frozen=True)
class ThirdBodySettings(Settings):
    """Sun and Moon point masses."""

    SCHEMA_DEF = "force_third_body"

    sun: bool
    moon: bool


@dataclass(frozen=True)
class RelativitySettings(Settings):
    """Lense-Thirring and de Sitter terms besides the Schwarzschild term."""

    SCHEMA_DEF = "force_relativity"

    lense_thirring: bool
    de_sitter: bool


@dataclass(frozen=True)
class DragSettings(Settings):
    """Drag on a cannonball (C_D A/m or coefficient × area / mass) or on the satellite's
    plates, density model, scale factors."""

    SCHEMA_DEF = "force_drag"

    cd_area_mass_m2_kg: float | None
    drag_coefficient: float
    area_m2: float | None
    mass_kg: float | None
    plates: bool
    density: str | None
    space_weather: str | None
    msis_version: float
    hp_exponent: float
    interval_s: float | None
    apriori: float
    estimate: bool
    sigma: float | None


@dataclass(frozen=True)
class SrpSettings(Settings):
    """SRP on a cannonball (C_R A/m or coefficient × area / mass) or on the satellite's
    plates, shadow, scale factors."""

    SCHEMA_DEF = "force_srp"

    cr_area_mass_m2_kg: float | None
    reflectivity_coefficient: float
    area_m2: float | None
    mass_kg: float | None
    plates: bool
    shadow: bool
    r_earth_m: float
    interval_s: float | None
    apriori: float
    estimate: bool
    sigma: float | None


@dataclass(frozen=True)
class EarthRadiationSettings(Settings):
    """Earth radiation pressure (albedo + infrared) on a cannonball (C_R A/m or coefficient ×
    area / mass) or the plates, rings of the visible cap, scale factors."""

    SCHEMA_DEF = "force_earth_radiation"

    cr_area_mass_m2_kg: float | None
    reflectivity_coefficient: float
    area_m2: float | None
    mass_kg: float | None
    plates: bool
    rings: int
    r_earth_m: float
    interval_s: float | None
    apriori: float
    estimate: bool
    sigma: float | None


@dataclass(frozen=True)
class EmpiricalSettings(Settings):
    """Piecewise empirical accelerations: interval [s], directions, terms, parameters."""

    SCHEMA_DEF = "force_empirical"

    interval_s: float
    directions: tuple[str, ...]
    terms: tuple[str, ...]
    apriori: float
    estimate: bool
    sigma: float | None


@dataclass(frozen=True)
class ManoeuvreSettings(Settings):
    """Accelerations of the listed burns: estimated or not, a-priori sigma [m/s²]."""

    SCHEMA_DEF = "force_manoeuvre"

    estimate: bool
    sigma: float | None


_SECTIONS = {"gravity": GravitySettings, "tides": TideSettings,
             "third_body": ThirdBodySettings, "relativity": RelativitySettings,
             "drag": DragSettings, "srp": SrpSettings,
             "earth_radiation": EarthRadiationSettings, "empirical": EmpiricalSettings,
             "manoeuvre": ManoeuvreSettings}


@dataclass(frozen=True)
class ForceModelSettings:
    """The force model of an arc: one section per force (None: off), the environment and
    the satellite's plates (None: none)."""

    environment: EnvironmentSettings
    gravity: GravitySettings | None
    tides: TideSettings | None
    third_body: ThirdBodySettings | None
    relativity: RelativitySettings | None
    drag: DragSettings | None
    srp: SrpSettings | None
    earth_radiation: EarthRadiationSettings | None
    empirical: EmpiricalSettings | None
    manoeuvre: ManoeuvreSettings | None
    macro_model: MacroModel | None = None

    @classmethod
    def from_config(cls, section: Mapping,
                    macro_model: MacroModel | None = None) -> ForceModelSettings:
        """Settings from a ``pod.forces``-shaped mapping (module docstring), with the plates
        of the satellite (``satellites.<sat>.macro_model``,
        :func:`leopod.dynamics.plates.macro_model_from_config`) for the forces on plates.

        Raises
        ------
        ValueError
            Naming an unknown section or key.
        TypeError
            If a section is not a mapping, True/False or None.
        """
        unknown = sorted(set(section) - {*_SECTIONS, "environment"})
        if unknown:
            raise ValueError(f"force config: unknown sections {unknown} "
                             f"(known: {sorted([*_SECTIONS, 'environment'])})")
        return cls(environment=_typed("environment", section.get("environment") or {},
                                      EnvironmentSettings), macro_model=macro_model,
                   **{name: _typed(name, section.get(name), kind)
                      for name, kind in _SECTIONS.items()})


def _typed(name: str, value, kind: type[Settings]):
    """The settings of one section, or None if it is switched off."""
    if value is None or value is False:
        return None
    if value is True:
        value = {}
    if not isinstance(value, Mapping):
        raise TypeError(f"force config '{name}' must be a mapping, True/False or None")
    fields = {f.name for f in dataclasses.fields(kind)}
    unknown = sorted(set(value) - fields - {"enabled"})
    if unknown:
        raise ValueError(f"force config '{name}': unknown keys {unknown}")
    if not value.get("enabled", True):
        return None
    return kind.from_config({k: v for k, v in value.items() if k != "enabled"})


# ---------------------------------------------------------------------------------- builder
@functools.lru_cache(maxsize=4)
def _read_icgem(path: str) -> xr.Dataset:
    return read_icgem(path)


@functools.lru_cache(maxsize=4)
def _ocean_tides(path: str, max_degree: int) -> OceanTides:
    return OceanTides.from_file(path, max_degree=max_degree)


@functools.lru_cache(maxsize=2)
def _space_weather(path: str) -> xr.Dataset:
    return read_space_weather(path)


def _area_mass(name: str, value: float | None, coefficient: float, area_m2: float | None,
               mass_kg: float | None) -> float:
    """C A/m [m²/kg] given, or coefficient × area_m2 / mass_kg."""
    if value is not None:
        return float(value)
    if area_m2 is None or mass_kg is None:
        raise ValueError(f"force config '{name}': give the coefficient times area over mass, "
                         "or area_m2 and mass_kg")
    return float(coefficient) * float(area_m2) / float(mass_kg)


def _gravity(cfg: GravitySettings, tides_cfg: TideSettings | None,
             env: ArcEnvironment) -> Force:
    ds = cfg.field
    if ds is None:
        raise ValueError("force config 'gravity' needs 'field' (ICGEM path or Dataset)")
    if not isinstance(ds, xr.Dataset):
        ds = _read_icgem(str(Path(ds)))
    epoch = decimal_year(env.t_ref)
    available = int(ds.attrs.get("max_degree", ds.sizes["n"] - 1))
    max_degree = min(120, available) if cfg.max_degree is None else cfg.max_degree
    field = GravityField(ds, max_degree, epoch_decimal_year=epoch)
    gradient_field = None
    if cfg.gradient_degree is not None and cfg.gradient_degree < field.max_degree:
        gradient_field = GravityField(ds, cfg.gradient_degree, epoch_decimal_year=epoch)
    tides = None
    if tides_cfg is not None:
        ocean = tides_cfg.ocean
        if ocean is not None:
            ocean = _ocean_tides(str(Path(ocean)), int(tides_cfg.ocean_max_degree))
        try:
            tides = TideModel(field.tide_system, ocean=ocean, solid=tides_cfg.solid,
                              solid_pole=tides_cfg.solid_pole, ocean_pole=tides_cfg.ocean_pole,
                              gm_earth_m3_s2=field.gm_m3_s2, radius_m=field.radius_m)
        except ValueError as err:
            raise ValueError(f"tides with the gravity field {field.modelname}: {err}") from None
        if not (tides.solid or tides.solid_pole or tides.ocean_pole or ocean is not None):
            tides = None
    # the tide grid exists only with tides: its step comes from their settings
    grid = {} if tides is None else {"tide_step_s": float(tides_cfg.step_s)}
    return EarthGravity(field, env, tides, gradient_field=gradient_field, **grid)


def _plates(name: str, cfg, plates: Plates | None) -> Plates | None:
    """The plates of a force whose section asks for them (``plates: true``), else None."""
    if not cfg.plates:
        return None
    if plates is None:
        raise ValueError(f"force config '{name}': plates: true, but the satellite has no "
                         "macro_model (satellites.<sat>.macro_model)")
    return plates


def _cannonball(name: str, cfg, value: float | None, coefficient: float,
                plates: Plates | None) -> float:
    """C A/m of a cannonball force [m²/kg] (:func:`_area_mass`; 0 when it acts on plates)."""
    return 0.0 if plates is not None else _area_mass(name, value, coefficient, cfg.area_m2,
                                                     cfg.mass_kg)


def _drag(cfg: DragSettings, env: ArcEnvironment, span_s: tuple[float, float],
          plates: Plates | None) -> Drag:
    kind = cfg.density or ("msis" if cfg.space_weather is not None else "harris_priester")
    if kind == "msis":
        if cfg.space_weather is None:
            raise ValueError("force config 'drag': density 'msis' needs 'space_weather'")
        density = MsisDensity(_space_weather(str(Path(cfg.space_weather))),
                              version=cfg.msis_version)
    elif kind == "harris_priester":
        density = HarrisPriesterDensity(cfg.hp_exponent)
    else:
        raise ValueError(f"force config 'drag': unknown density '{kind}' "
                         "(harris_priester or msis)")
    edges = interval_edges(*span_s, cfg.interval_s)
    plates = _plates("drag", cfg, plates)
    coef = _cannonball("drag", cfg, cfg.cd_area_mass_m2_kg, cfg.drag_coefficient, plates)
    return Drag(env, density, coef, edges,
                plates=plates, apriori=cfg.apriori, estimate=cfg.estimate, sigma=cfg.sigma)


def _srp(cfg: SrpSettings, env: ArcEnvironment, span_s: tuple[float, float],
         plates: Plates | None) -> SolarRadiation:
    edges = interval_edges(*span_s, cfg.interval_s)
    plates = _plates("srp", cfg, plates)
    coef = _cannonball("srp", cfg, cfg.cr_area_mass_m2_kg, cfg.reflectivity_coefficient, plates)
    return SolarRadiation(env, coef, edges, shadow=cfg.shadow, r_earth_m=cfg.r_earth_m, plates=plates,
                          apriori=cfg.apriori, estimate=cfg.estimate, sigma=cfg.sigma)


def _earth_radiation(cfg: EarthRadiationSettings, env: ArcEnvironment,
                     span_s: tuple[float, float], plates: Plates | None) -> EarthRadiation:
    edges = interval_edges(*span_s, cfg.interval_s)
    plates = _plates("earth_radiation", cfg, plates)
    coef = _cannonball("earth_radiation", cfg, cfg.cr_area_mass_m2_kg,
                       cfg.reflectivity_coefficient, plates)
    return EarthRadiation(env, coef, edges, rings=cfg.rings, r_earth_m=cfg.r_earth_m, plates=plates,
                          apriori=cfg.apriori, estimate=cfg.estimate, sigma=cfg.sigma)


def _empirical(cfg: EmpiricalSettings, span_s: tuple[float, float]) -> Empirical:
    edges = interval_edges(*span_s, cfg.interval_s)
    model = EmpiricalModel(edges, directions=tuple(cfg.directions), terms=tuple(cfg.terms))
    return Empirical(model, apriori=cfg.apriori, estimate=cfg.estimate, sigma=cfg.sigma)


def arc_environment(settings: ForceModelSettings, t_ref, t_start_s: float, t_end_s: float, *,
                    eop: EarthOrientation | None = None) -> ArcEnvironment:
    """The grids of Earth rotation, Sun and Moon of an arc (``settings.environment``), for
    one or several force models of the arc (arguments as :func:`build_force_model`)."""
    grids = settings.environment
    return ArcEnvironment(
        t_ref, t_start_s, t_end_s, eop=eop,
        ephemeris=None if grids.ephemeris is None else Ephemeris(grids.ephemeris),
        rotation_step_s=grids.rotation_step_s, ephemeris_step_s=grids.ephemeris_step_s)


def build_force_model(settings: ForceModelSettings, t_ref, t_start_s: float, t_end_s: float, *,
                      eop: EarthOrientation | None = None,
                      environment: ArcEnvironment | None = None,
                      manoeuvres: Sequence[Manoeuvre] = (),
                      attitude: LeoAttitude | None = None) -> ForceModel:
    """Force model of an arc (module docstring).

    Parameters
    ----------
    settings : ForceModelSettings
    t_ref : datetime64
        Reference epoch (GPS-time label); force times are TT s since it.
    t_start_s, t_end_s : float
        The arc [s since ``t_ref``] (intervals of estimated parameters start at ``t_start_s``).
    eop : EarthOrientation, optional
        EOP (default: installed IERS data).
    environment : ArcEnvironment, optional
        Grids to reuse (must cover the arc, may cover more: e.g. output epochs beyond the
        observations); built from ``settings.environment`` over the arc otherwise.
    manoeuvres : sequence of Manoeuvre, optional
        Burns of the satellite (:func:`leopod.io.manoeuvre.read_manoeuvres`; epochs GPS time);
        those acting inside the arc are modelled when ``settings.manoeuvre`` is on.
    attitude : LeoAttitude, optional
        Attitude law flown by the plates of ``settings.macro_model`` (None: nominal).

    Returns
    -------
    ForceModel
        Forces in the order gravity, third bodies, relativity, drag, SRP, Earth radiation,
        empirical, manoeuvres.
    """
    env = (arc_environment(settings, t_ref, t_start_s, t_end_s, eop=eop) if environment is None
           else environment)
    forces: list[Force] = []
    forces.append(PointMassGravity() if settings.gravity is None
                  else _gravity(settings.gravity, settings.tides, env))
    if settings.third_body is not None:
        forces.append(ThirdBodies(env, settings.third_body.sun, settings.third_body.moon))
    if settings.relativity is not None:
        forces.append(Relativity(env, settings.relativity.lense_thirring,
                                 settings.relativity.de_sitter))
    macro = settings.macro_model
    plates = None if macro is None else Plates(macro, attitude, env)
    span = (t_start_s, t_end_s)     # the estimated parameters' intervals start at t_start_s
    for cfg, make in ((settings.drag, _drag), (settings.srp, _srp),
                      (settings.earth_radiation, _earth_radiation)):
        if cfg is not None:
            forces.append(make(cfg, env, span, plates))
    if settings.empirical is not None:
        forces.append(_empirical(settings.empirical, span))
    burns = None
    if settings.manoeuvre is not None:
        burns = Manoeuvres.of(manoeuvres, t_ref, t_start_s, t_end_s,
                              estimate=settings.manoeuvre.estimate,
                              sigma=settings.manoeuvre.sigma)
    elif manoeuvres:
        logger.warning("%d manoeuvres listed but pod.forces.manoeuvre is off: not modelled",
                       len(manoeuvres))
    if burns is not None:
        forces.append(burns)
    model = ForceModel(forces)
    logger.info("force model: %s; %d parameters", ", ".join(type(f).__name__ for f in forces),
                model.n_params)
    on_plates = [type(f).__name__ for f in forces if getattr(f, "plates", None) is not None]
    if on_plates:
        logger.info("%s on the %d plates of the macro model, attitude %s", ", ".join(on_plates),
                    macro.area_m2.size, "nominal" if attitude is None else attitude.describe())
    return model
