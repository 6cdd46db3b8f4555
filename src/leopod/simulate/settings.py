"""Settings of a simulated campaign: the ``simulate`` block of a campaign configuration.

:class:`SimulationSettings` gathers everything that defines a simulated campaign (defaults: an
HY-2B-like satellite, the values documented in ``config/config.yaml``) and hands out the
random streams: every stream comes from ``numpy.random.SeedSequence([seed, crc32(label)])``
with a label naming its use, so that a file depends only on the master seed and its own label.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

import numpy as np

from leopod.simulate.biases import BiasSettings
from leopod.simulate.observations import ObservationSettings
from leopod.simulate.product_world import ProductSet
from leopod.simulate.slr import DEFAULT_STATIONS, SlrSettings
from leopod.simulate.truth_forces import TruthDynamics

__all__ = ["DEFAULT_PCO_BODY_M", "ClockSettings", "OrbitSettings", "ProductSettings",
           "SimulationSettings", "SlrSimulation"]

#: Simple antenna phase-centre offsets per band in the body frame [m]: the antenna on the
#: zenith face (-Z), 0.35 m (L1, B1C) and 0.37 m (L2, B2a) above the centre of mass.
#: (Table I of Peng et al. 2021 gives the real HY-2B values in its mechanical frame; relative
#: to the centre of mass they are L1 (-1.0367, -0.1866, -1.3776) m and L2 (-1.0361, -0.1846,
#: -1.3990) m.)
DEFAULT_PCO_BODY_M = {"L1": (0.0, 0.0, -0.35), "L2": (0.0, 0.0, -0.37),
                      "B1C": (0.0, 0.0, -0.35), "B2a": (0.0, 0.0, -0.37)}


@dataclass(frozen=True)
class OrbitSettings:
    """Initial orbit of the truth (see :func:`leopod.simulate.truth_orbit.
    initial_state_sun_synchronous`).

    Attributes
    ----------
    altitude_km : float
        Altitude above the equatorial radius [km] (HY-2B: 971 km).
    ltan_h : float
        Local time of the ascending node [h] (HY-2B: 18, dawn-dusk).
    inclination_deg : float or None
        Inclination [deg]; None: sun-synchronous (99.34° at 971 km).
    u0_deg : float
        Argument of latitude at the start of the truth [deg].
    step_s : float
        Sampling of the truth orbit [s].
    margin_s : float
        Truth before 00:00 of the first day and after 24:00 of the last [s].
    """

    altitude_km: float = 971.0
    ltan_h: float = 18.0
    inclination_deg: float | None = None
    u0_deg: float = 0.0
    step_s: float = 10.0
    margin_s: float = 300.0


@dataclass(frozen=True)
class ClockSettings:
    """Receiver and GNSS clocks (:class:`leopod.simulate.world.RandomWalkClock`).

    Attributes
    ----------
    rx_bias_s, rx_drift_s_s, rx_walk_s_sqrt_s : float
        Receiver clock offset at the world epoch [s], drift [s/s], random-walk intensity
        [s/√s] (µs level: a steered LEO receiver clock).
    gnss_bias_max_s, gnss_drift_max_s_s : float
        GNSS clock offsets and drifts are uniform in ±these [s, s/s].
    gnss_walk_s_sqrt_s : float
        GNSS clock random-walk intensity [s/√s] (1e-12: 5 ps per 30 s, 0.3 ns per day).
    """

    rx_bias_s: float = 1.5e-6
    rx_drift_s_s: float = 2e-11
    rx_walk_s_sqrt_s: float = 1e-10
    gnss_bias_max_s: float = 5e-4
    gnss_drift_max_s_s: float = 1e-11
    gnss_walk_s_sqrt_s: float = 1e-12


@dataclass(frozen=True)
class ProductSettings:
    """GNSS product files.

    Attributes
    ----------
    orbit_interval_s : float
        SP3 sampling [s].
    clock_interval_s : float
        RINEX clock sampling [s]; the GNSS clocks' random walk has nodes on this grid, so the
        linear interpolation of the product is exact.
    agency : str
        Agency / analysis-centre code (3 characters).
    """

    orbit_interval_s: float = 900.0
    clock_interval_s: float = 30.0
    agency: str = "SIM"


@dataclass(frozen=True)
class SlrSimulation:
    """Laser ranging of the simulated LEO.

    Attributes
    ----------
    retro_offset_body_m : tuple of float
        Retro-reflector offset from the centre of mass in the body frame [m]: HY-2B's LRA
        spherical centre minus its centre of mass in Peng et al. (2021) Table I (311.29, -215.43,
        986.53) - (1383.44, 6.85, 2.35) mm, taking the mechanical frame as the body frame
        (X flight, Z nadir: the LRA is on the Earth-facing side, the GPS antenna on the
        zenith side).
    stations : tuple of str or None
        CDP pad ids of the network (None: every station of
        :data:`leopod.simulate.slr.DEFAULT_STATIONS`).
    settings : SlrSettings
    """

    retro_offset_body_m: tuple[float, float, float] = (-1.07215, -0.22228, 0.98418)
    stations: tuple[str, ...] | None = None
    settings: SlrSettings = field(default_factory=SlrSettings)

    @property
    def station_list(self):
        """The stations of the network."""
        if self.stations is None:
            return DEFAULT_STATIONS
        known = {s.pad_id: s for s in DEFAULT_STATIONS}
        unknown = [p for p in self.stations if p not in known]
        if unknown:
            raise ValueError(f"unknown SLR station pad ids {unknown} (known: "
                             f"{', '.join(known)})")
        return tuple(known[p] for p in self.stations)


def _default_models() -> dict:
    return {"field": "satkit:ITU_GRACE16.gfc", "space_weather": "satkit:SW-All.csv",
            "ocean": None}


@dataclass(frozen=True)
class SimulationSettings:
    """Everything that defines a simulated campaign (defaults: an HY-2B-like satellite).

    Attributes
    ----------
    seed : int
        Master seed (module docstring).
    marker : str
        Marker name of the RINEX files.
    interval_s : float
        Observation sampling [s].
    systems : dict
        System -> RINEX 3 codes simulated (GPS C1C/C1W/C2W/L1C/L2W; BDS-3 C1P/C5P/L1P/L5P).
    orbit : OrbitSettings
    dynamics : TruthDynamics
        Truth force model (gravity degree, drag and stochastic accelerations).
    models : dict
        Truth model files: ``field`` (gravity, ICGEM), ``space_weather`` (CelesTrak CSV),
        ``ocean`` (FES2004 or None); ``satkit:<file>`` names a satkit-data file.
    clocks : ClockSettings
    products : ProductSettings
    observations : ObservationSettings
    biases : BiasSettings
    code_bias_maps : tuple of dict
        Configurations of :meth:`CodeBiasMap.from_config` (model, signal, parameters).
    gnss_antex : str or None
        ANTEX file of the GNSS antenna offsets/variations (None: centre of mass).
    gnss_products : ProductSet or None
        Real GNSS orbits, clocks and OSBs to simulate against
        (:mod:`leopod.simulate.product_world`) instead of the simulated constellation.
    gnss_eccentricity_max : float
        GNSS orbit eccentricities are uniform in [0, this) (GPS: up to ~0.02; IS-GPS-200
        Table 20-III: broadcast range up to 0.03); 0.015 gives periodic relativistic clock
        terms up to ~10 m, which circular orbits would not exercise (r·v = 0).
    slr : SlrSimulation
    leo_sp3_id : str
        Satellite id of the LEO in the truth SP3 files.
    """

    seed: int = 2018
    marker: str = "SIML"
    interval_s: float = 30.0
    systems: dict = field(default_factory=lambda: {"G": ("C1C", "C1W", "C2W", "L1C", "L2W")})
    orbit: OrbitSettings = field(default_factory=OrbitSettings)
    dynamics: TruthDynamics = field(default_factory=TruthDynamics)
    models: dict = field(default_factory=_default_models)
    clocks: ClockSettings = field(default_factory=ClockSettings)
    products: ProductSettings = field(default_factory=ProductSettings)
    observations: ObservationSettings = field(default_factory=ObservationSettings)
    biases: BiasSettings = field(default_factory=BiasSettings)
    code_bias_maps: tuple = ({"model": "hy2b_p1", "signal": "C1W"},)
    gnss_antex: str | None = None
    gnss_products: ProductSet | None = None
    gnss_eccentricity_max: float = 0.015
    slr: SlrSimulation = field(default_factory=SlrSimulation)
    leo_sp3_id: str = "L01"

    @classmethod
    def from_config(cls, cfg: Mapping | None) -> SimulationSettings:
        """Build from the ``simulate`` block of a campaign config (``config/config.yaml``
        documents every key); unknown keys raise a ``ValueError`` that names them."""
        cfg = dict(cfg or {})
        try:
            kwargs = {}
            for key, value in cfg.items():
                if key not in _PARSERS:
                    raise ValueError(f"unknown key '{key}' (known: {', '.join(_PARSERS)})")
                kwargs.update(_PARSERS[key](value))
            return cls(**kwargs)
        except (TypeError, ValueError) as err:
            raise ValueError(f"config 'simulate': {err}") from None

    def signal_codes(self) -> dict[str, tuple[str, ...]]:
        """System -> simulated RINEX 3 codes."""
        return {k: tuple(v) for k, v in self.systems.items()}

    def seed_sequence(self, label: str) -> np.random.SeedSequence:
        """The seed of the random stream ``label`` (module docstring)."""
        return np.random.SeedSequence([self.seed, zlib.crc32(label.encode())])

    def rng(self, label: str) -> np.random.Generator:
        """The random stream ``label``."""
        return np.random.default_rng(self.seed_sequence(label))

    def int_seed(self, label: str) -> int:
        """An integer seed drawn from the stream ``label`` (for seeded helpers)."""
        return int(self.seed_sequence(label).generate_state(1)[0])


def _checked(cls, value: Mapping | None, name: str):
    value = dict(value or {})
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(value) - known)
    if unknown:
        raise ValueError(f"'{name}': unknown key(s) {unknown} (known: {sorted(known)})")
    return cls(**value)


def _parse_truth(value: Mapping) -> dict:
    value = dict(value or {})
    models = dict(value.pop("models", {}) or {})
    unknown = sorted(set(models) - set(_default_models()))
    if unknown:
        raise ValueError(f"'truth.models': unknown key(s) {unknown} (known: "
                         f"{sorted(_default_models())})")
    models = {**_default_models(), **models}
    if "stochastic_sigma_rtn_m_s2" in value:
        value["stochastic_sigma_rtn_m_s2"] = tuple(value["stochastic_sigma_rtn_m_s2"])
    return {"dynamics": _checked(TruthDynamics, value, "truth"), "models": models}


def _parse_slr(value: Mapping) -> dict:
    value = dict(value or {})
    own = {k: value.pop(k) for k in ("retro_offset_body_m", "stations") if k in value}
    if "retro_offset_body_m" in own:
        own["retro_offset_body_m"] = tuple(float(v) for v in own["retro_offset_body_m"])
    if own.get("stations") is not None:
        own["stations"] = tuple(str(p) for p in own["stations"])
    return {"slr": SlrSimulation(**own, settings=_checked(SlrSettings, value, "slr"))}


_PARSERS = {
    "seed": lambda v: {"seed": int(v)},
    "marker": lambda v: {"marker": str(v)},
    "interval_s": lambda v: {"interval_s": float(v)},
    "systems": lambda v: {"systems": {str(k): tuple(c) for k, c in dict(v).items()}},
    "orbit": lambda v: {"orbit": _checked(OrbitSettings, v, "orbit")},
    "truth": _parse_truth,
    "clocks": lambda v: {"clocks": _checked(ClockSettings, v, "clocks")},
    "products": lambda v: {"products": _checked(ProductSettings, v, "products")},
    "observations": lambda v: {"observations": _checked(ObservationSettings, v,
                                                        "observations")},
    "biases": lambda v: {"biases": _checked(BiasSettings, v, "biases")},
    "code_bias_maps": lambda v: {"code_bias_maps": tuple(dict(m) for m in (v or ()))},
    "gnss_antex": lambda v: {"gnss_antex": None if v is None else str(v)},
    "gnss_products": lambda v: {"gnss_products": ProductSet.from_config(v)},
    "gnss_eccentricity_max": lambda v: {"gnss_eccentricity_max": float(v)},
    "slr": _parse_slr,
    "leo_sp3_id": lambda v: {"leo_sp3_id": str(v)},
}
