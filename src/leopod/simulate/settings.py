"""Settings of a simulated campaign: the ``simulate`` section of a campaign configuration.

:class:`SimulationSettings` gathers everything that defines a simulated campaign and hands out
the random streams: every stream comes from ``numpy.random.SeedSequence([seed, crc32(label)])``
with a label naming its use, so that a file depends only on the master seed and its own label.
The keys, their checks and their defaults (an HY-2B-like satellite) are those of
``$defs/simulate`` of the campaign schema (``workflow/schemas/config.schema.yaml``); every
``from_config`` here takes a validated section (:mod:`leopod.settings`), and a settings class
with nested sections hands each to the ``from_config`` of its own class.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any, Self

import numpy as np

from leopod.settings import Settings, frozen_value
from leopod.simulate.biases import BiasSettings
from leopod.simulate.observations import ObservationSettings
from leopod.simulate.product_set import ProductSet
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


def _subsection(section: Mapping[str, Any], key: str, owner: str) -> Mapping[str, Any]:
    """``section[key]``, or a KeyError that points at the schema."""
    if key not in section:
        raise KeyError(f"{owner}: the configuration section has no {key} (validate it "
                       "against the campaign schema, which holds the defaults)")
    return section[key]


@dataclass(frozen=True)
class OrbitSettings(Settings):
    """Initial orbit of the truth (``simulate.orbit``; see
    :func:`leopod.simulate.truth_orbit.initial_state_sun_synchronous`).

    Attributes
    ----------
    altitude_km : float
        Altitude above the equatorial radius [km] (HY-2B: 971 km).
    ltan_h : float
        Local time of the ascending node [h] (HY-2B: 18, dawn-dusk).
    inclination_deg : float or None
        Inclination [deg]; None: sun-synchronous, computed for the altitude (99.34° at 971 km).
    u0_deg : float
        Argument of latitude at the start of the truth [deg].
    step_s : float
        Sampling of the truth orbit [s].
    margin_s : float
        Truth before 00:00 of the first day and after 24:00 of the last [s].
    integrator_step_s : float
        Gauss–Jackson step of the truth integration [s] (schema: what it resolves).
    """

    altitude_km: float
    ltan_h: float
    inclination_deg: float | None
    u0_deg: float
    step_s: float
    margin_s: float
    integrator_step_s: float


@dataclass(frozen=True)
class ClockSettings(Settings):
    """Receiver and GNSS clocks (``simulate.clocks``;
    :class:`leopod.simulate.world.RandomWalkClock`).

    Attributes
    ----------
    rx_bias_s, rx_drift_s_s, rx_walk_s_sqrt_s : float
        Receiver clock offset at the world epoch [s], drift [s/s], random-walk intensity
        [s/√s] (µs level: a steered LEO receiver clock).
    gnss_bias_max_s, gnss_drift_max_s_s : float
        GNSS clock offsets and drifts are uniform in ±these [s, s/s].
    gnss_walk_s_sqrt_s : float
        GNSS clock random-walk intensity [s/√s] (1e-12: 5 ps per 30 s, 0.3 ns per day).
    rx_jumps : tuple of mapping
        Steps of the receiver clock, each ``epoch`` (ISO 8601, GPS time) and ``size_s`` [s].
    """

    rx_bias_s: float
    rx_drift_s_s: float
    rx_walk_s_sqrt_s: float
    gnss_bias_max_s: float
    gnss_drift_max_s_s: float
    gnss_walk_s_sqrt_s: float
    rx_jumps: tuple


@dataclass(frozen=True)
class ProductSettings(Settings):
    """GNSS product files (``simulate.products``).

    Attributes
    ----------
    orbit_interval_s : float
        SP3 sampling [s].
    clock_interval_s : float
        RINEX clock sampling [s]; the GNSS clocks' random walk has nodes on this grid, so the
        linear interpolation of the product is exact.
    agency : str
        Agency / analysis-centre code (3 characters).
    ar_fault : str
        Fault of the AR products (:data:`leopod.simulate.product_faults.AR_FAULTS`;
        ``"none"``: consistent products).
    """

    orbit_interval_s: float
    clock_interval_s: float
    agency: str
    ar_fault: str


@dataclass(frozen=True)
class SlrSimulation(Settings):
    """Laser ranging of the simulated LEO (``simulate.slr``).

    Attributes
    ----------
    retro_offset_body_m : tuple of float
        Retro-reflector offset from the centre of mass in the body frame [m] (the schema's
        default: HY-2B's LRA spherical centre minus its centre of mass in Peng et al. (2021)
        Table I (311.29, -215.43, 986.53) - (1383.44, 6.85, 2.35) mm, taking the mechanical
        frame as the body frame: X flight, Z nadir, the LRA on the Earth-facing side, the GPS
        antenna on the zenith side).
    stations : tuple of str or None
        CDP pad ids of the network (None: every station of
        :data:`leopod.simulate.slr.DEFAULT_STATIONS`).
    settings : SlrSettings
        The other keys of the section.
    """

    retro_offset_body_m: tuple[float, float, float]
    stations: tuple[str, ...] | None
    settings: SlrSettings

    @classmethod
    def from_config(cls, section: Mapping[str, Any]) -> Self:
        """From the validated ``simulate.slr`` section (its keys other than
        ``retro_offset_body_m`` and ``stations`` are those of :class:`SlrSettings`)."""
        return cls(retro_offset_body_m=frozen_value(
                       _subsection(section, "retro_offset_body_m", cls.__name__)),
                   stations=frozen_value(_subsection(section, "stations", cls.__name__)),
                   settings=SlrSettings.from_config(section))

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


@dataclass(frozen=True)
class SimulationSettings(Settings):
    """Everything that defines a simulated campaign (the ``simulate`` section).

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
        Truth force model (gravity degree, drag and stochastic accelerations): the keys of
        ``simulate.truth`` other than ``models``.
    models : dict
        Truth model files (``simulate.truth.models``): ``field`` (gravity, ICGEM),
        ``space_weather`` (CelesTrak CSV), ``ocean`` (FES2004 or None); ``satkit:<file>``
        names a satkit-data file.
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

    seed: int
    marker: str
    interval_s: float
    systems: dict
    orbit: OrbitSettings
    dynamics: TruthDynamics
    models: dict
    clocks: ClockSettings
    products: ProductSettings
    observations: ObservationSettings
    biases: BiasSettings
    code_bias_maps: tuple
    gnss_antex: str | None
    gnss_products: ProductSet | None
    gnss_eccentricity_max: float
    slr: SlrSimulation
    leo_sp3_id: str

    @classmethod
    def from_config(cls, section: Mapping[str, Any]) -> Self:
        """From the validated ``simulate`` section (:func:`leopod.workflow.config.validated`,
        or :func:`leopod.workflow.config.with_defaults` for a partial one); each nested section
        goes to the ``from_config`` of its class.

        Raises
        ------
        KeyError
            When a key is missing: the section was not validated against the schema.
        """
        def sub(key):
            return _subsection(section, key, cls.__name__)

        truth = sub("truth")
        products = sub("gnss_products")
        nested = {
            "systems": {str(k): tuple(v) for k, v in sub("systems").items()},
            "orbit": OrbitSettings.from_config(sub("orbit")),
            "dynamics": TruthDynamics(**{f.name: frozen_value(_subsection(truth, f.name, "truth"))
                                         for f in fields(TruthDynamics)}),
            "models": dict(_subsection(truth, "models", "truth")),
            "clocks": ClockSettings.from_config(sub("clocks")),
            "products": ProductSettings.from_config(sub("products")),
            "observations": ObservationSettings.from_config(sub("observations")),
            "biases": BiasSettings.from_config(sub("biases")),
            "code_bias_maps": tuple(dict(m) for m in sub("code_bias_maps")),
            "gnss_products": None if products is None else ProductSet.from_config(products),
            "slr": SlrSimulation.from_config(sub("slr")),
        }
        flat = {f.name: frozen_value(sub(f.name)) for f in fields(cls) if f.name not in nested}
        return cls(**flat, **nested)

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
