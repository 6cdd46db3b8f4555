"""Simulated antenna-frame code-bias maps: a smooth function ``b(az, el)`` [m] added to one code.

A code-bias map is a static error of one code signal of the LEO receiver that depends only on
the line-of-sight direction in the antenna frame (Peng et al. 2021, eq. (2): the term ``b(e, z)``)
and, for a map with a ``yaw_branch``, on the branch of the yaw-steering law (Jiang et al. 2023).
Directions follow :func:`leopod.frames.attitude.antenna_angles`: elevation above the body X-Y
plane (towards the antenna boresight), azimuth from body +X (the flight direction in the nominal
attitude) towards +Y, in degrees. Models:

``"none"``
    Zero everywhere.
``"hy2b_p1"``
    The HY-2B P1 (``C1W``) pattern of Peng et al. (2021) (sec. II, Figs. 7-10 text and conclusion),
    built from the polar map coordinates ``r = (90° - el)/90°``, ``x = r cos az`` (flight),
    ``y = r sin az`` (cross-track) and the elliptic radius ``q = sqrt((x/a)² + (y/b)²)``:

    - inside the ellipse ``q < 1`` (long axis along azimuth 90°/270°, ``b > a``) a flat level
      ``plateau_m`` (+0.15 m: "the errors mainly varied by 10 to 20 cm"), with a Gaussian valley
      along the long axis (``x = 0``) whose bottom is ``valley_m`` (-0.3 m: "a valley along the
      axis of the area, in which the errors reach a minimum, about -0.3 m");
    - outside (``q > 1``, blended by ``s(q) = (1 + tanh((q - 1)/edge_width))/2``) a level
      ``outer_min_m + (outer_max_m - outer_min_m) cos² el`` between 0.5 and 1 m ("for the rest
      of the map, the errors vary from 0.5 to 1 m");
    - plus, outside the ellipse, a crescent ``crescent_m · g · exp(-el/crescent_scale_el_deg)``
      between azimuths ``crescent_az_deg`` = (120°, 240°) (``g`` a smooth window of the
      azimuth, 1/2 at the limits at the horizon, narrowing slightly with elevation), so that the total reaches about 3 m at the horizon ("the error increased rapidly
      and reached a maximum of 3 m in the crescent area between azimuth angles of 120° to
      240°"; "P1 code MP errors rapidly increase from sub-meter to several meters at elevation
      less than 40°").

    The crescent lies behind the satellite (azimuth 180° = against the flight direction),
    where GNSS satellites leave the field of view, as Peng et al. (2021) describes.
``"bds3_patchy"``
    Patchy near-field variations of Jiang et al. (2023) (sec. "Code multipath analysis": "patchy
    patterns with the amplitudes mainly concentrated within ±40 cm"; "at low elevation angles,
    the MPs of both frequencies predominantly fall below 0 m"): a sum of ``n_blobs`` smooth
    blobs ``exp((cos γ - 1)/w²)`` (γ the angle to a random centre, ``w`` a random width) with
    random signs, scaled so that the largest absolute value of the blob sum on a 1° grid is
    ``amplitude_m``, plus ``low_elevation_m · exp(-el/low_elevation_scale_deg)``. Centres,
    widths and signs come from ``numpy.random.default_rng(seed)``.

The mean of a map is not observable: a constant added to the map is indistinguishable from a
receiver code bias of that signal (and is absorbed by it in an estimation). :meth:`CodeBiasMap.
mean_m` gives the area-weighted mean over the hemisphere above the antenna horizon; for the
default ``"hy2b_p1"`` parameters it is +0.84 m (see ``HY2B_P1_AREA_MEAN_M``), so a map
estimated with a zero-mean (or other) datum is to be compared with ``grid() - constant``.

Elevations below 0° (below the antenna horizon) are evaluated at 0°.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
import xarray as xr

__all__ = ["HY2B_P1_AREA_MEAN_M", "MODELS", "YAW_BRANCHES", "Bds3Patchy", "CodeBiasMap",
           "Hy2bP1"]

#: Models known to :class:`CodeBiasMap`.
MODELS = ("none", "hy2b_p1", "bds3_patchy")
#: ``yaw_branch`` values of a map: every epoch, or one branch of the yaw-steering law.
YAW_BRANCHES = (None, "above_flip", "below_flip")

#: Area-weighted hemisphere mean of the default ``"hy2b_p1"`` map [m] (computed by
#: :meth:`CodeBiasMap.mean_m`; checked in tests/simulate/test_code_bias_map.py).
HY2B_P1_AREA_MEAN_M = 0.84

_DEG = np.pi / 180.0
_FINE_GRID_DEG = 1.0  # grid on which the patchy map's blob sum is normalised [deg]


@dataclass(frozen=True)
class Hy2bP1:
    """Parameters of the ``"hy2b_p1"`` model (``$defs/simulate_map_hy2b_p1`` of the campaign
    schema; its defaults reproduce Peng et al. 2021, sec. II).

    Attributes
    ----------
    plateau_m : float
        Level inside the central ellipse [m].
    valley_m : float
        Bottom of the valley along the long axis of the ellipse [m].
    valley_half_width_deg : float
        Gaussian width (1/e half-width) of the valley across the axis, in polar angle [deg].
    ellipse_el_flight_deg : float
        Elevation of the ellipse boundary on the azimuth 0°/180° axis [deg].
    ellipse_el_cross_deg : float
        Elevation of the ellipse boundary on the azimuth 90°/270° axis [deg]; lower than
        ``ellipse_el_flight_deg`` (long axis across track).
    edge_width : float
        Width of the tanh transition in elliptic radius (1 on the boundary) [1].
    outer_min_m, outer_max_m : float
        Outer level ``outer_min_m + (outer_max_m - outer_min_m) cos² el`` [m].
    crescent_m : float
        Crescent amplitude at the horizon in its centre [m] (added to ``outer_max_m``).
    crescent_az_deg : tuple of float
        Azimuth limits of the crescent [deg] (window value 1/2 there); the window is centred
        between them.
    crescent_edge_deg : float
        Width of the crescent's azimuth edges [deg].
    crescent_scale_el_deg : float
        e-folding elevation of the crescent [deg].
    """

    plateau_m: float
    valley_m: float
    valley_half_width_deg: float
    ellipse_el_flight_deg: float
    ellipse_el_cross_deg: float
    edge_width: float
    outer_min_m: float
    outer_max_m: float
    crescent_m: float
    crescent_az_deg: tuple[float, float]
    crescent_edge_deg: float
    crescent_scale_el_deg: float

    def __call__(self, az_deg: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
        r = (90.0 - el_deg) / 90.0
        x = r * np.cos(az_deg * _DEG)
        y = r * np.sin(az_deg * _DEG)
        a = (90.0 - self.ellipse_el_flight_deg) / 90.0
        b = (90.0 - self.ellipse_el_cross_deg) / 90.0
        q = np.sqrt((x / a) ** 2 + (y / b) ** 2)
        outside = 0.5 * (1.0 + np.tanh((q - 1.0) / self.edge_width))
        w = self.valley_half_width_deg / 90.0
        inner = self.plateau_m + (self.valley_m - self.plateau_m) * np.exp(-(x / w) ** 2)
        outer = (self.outer_min_m
                 + (self.outer_max_m - self.outer_min_m) * np.cos(el_deg * _DEG) ** 2)
        lo, hi = self.crescent_az_deg
        half = 0.5 * (hi - lo) * _DEG
        centre = 0.5 * (lo + hi) * _DEG
        # smooth window in azimuth: tanh of (cos Δ cos el - cos half), scaled to an angular
        # edge width; cos Δ cos el is the horizontal component of the line of sight towards
        # the crescent centre, a smooth function of the direction (also at the zenith)
        toward = np.cos(az_deg * _DEG - centre) * np.cos(el_deg * _DEG)
        window = 0.5 * (1.0 + np.tanh((toward - np.cos(half))
                                      / (np.sin(half) * self.crescent_edge_deg * _DEG)))
        crescent = self.crescent_m * window * np.exp(-el_deg / self.crescent_scale_el_deg)
        return (1.0 - outside) * inner + outside * (outer + crescent)


@dataclass(frozen=True)
class Bds3Patchy:
    """Parameters of the ``"bds3_patchy"`` model (Jiang et al. 2023, sec. "Code multipath
    analysis"; ``$defs/simulate_map_bds3_patchy`` of the campaign schema holds the defaults).

    Attributes
    ----------
    amplitude_m : float
        Largest absolute value of the blob sum [m].
    n_blobs : int
        Number of blobs.
    width_deg : tuple of float
        Range of the blob widths ``w`` [deg] (uniform).
    low_elevation_m : float
        Value of the low-elevation term at the horizon [m] (negative: Jiang et al. 2023).
    low_elevation_scale_deg : float
        e-folding elevation of the low-elevation term [deg].
    seed : int
        Seed of the random blobs.
    """

    amplitude_m: float
    n_blobs: int
    width_deg: tuple[float, float]
    low_elevation_m: float
    low_elevation_scale_deg: float
    seed: int
    _blobs: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        rng = np.random.default_rng(self.seed)
        # centres uniform on the hemisphere (uniform in sin el and in azimuth)
        el_c = np.arcsin(rng.uniform(0.0, 1.0, self.n_blobs))
        az_c = rng.uniform(0.0, 2.0 * np.pi, self.n_blobs)
        width = rng.uniform(*self.width_deg, self.n_blobs) * _DEG
        sign = rng.choice([-1.0, 1.0], self.n_blobs)
        centres = np.stack([np.cos(el_c) * np.cos(az_c), np.cos(el_c) * np.sin(az_c),
                            np.sin(el_c)], axis=-1)
        object.__setattr__(self, "_blobs", (centres, width, sign, 1.0))
        az, el = np.meshgrid(np.arange(0.0, 360.0, _FINE_GRID_DEG),
                             np.arange(0.0, 90.0 + _FINE_GRID_DEG / 2, _FINE_GRID_DEG))
        peak = np.max(np.abs(self._blob_sum(az, el)))
        object.__setattr__(self, "_blobs", (centres, width, sign, self.amplitude_m / peak))

    def _blob_sum(self, az_deg: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
        centres, width, sign, scale = self._blobs
        los = _unit_vector(az_deg, el_deg)
        cos_gamma = los @ centres.T
        return scale * np.sum(sign * np.exp((cos_gamma - 1.0) / width**2), axis=-1)

    def __call__(self, az_deg: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
        return (self._blob_sum(az_deg, el_deg)
                + self.low_elevation_m * np.exp(-el_deg / self.low_elevation_scale_deg))


@dataclass(frozen=True)
class _Zero:
    def __call__(self, az_deg: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
        return np.zeros(np.broadcast(az_deg, el_deg).shape)


_MODEL_CLASSES = {"none": _Zero, "hy2b_p1": Hy2bP1, "bds3_patchy": Bds3Patchy}


def _unit_vector(az_deg: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
    """Antenna-frame unit vectors (x flight, y, z boresight), shape ``az.shape + (3,)``."""
    az, el = np.broadcast_arrays(az_deg * _DEG, el_deg * _DEG)
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)


class CodeBiasMap:
    """An analytic antenna-frame code-bias map of one code signal.

    Parameters
    ----------
    name : {"none", "hy2b_p1", "bds3_patchy"}
        The model (module docstring).
    signal : str
        RINEX 3 code the map is added to (HY-2B P1: ``"C1W"``; BDS-3: ``"C1P"``/``"C5P"``).
    yaw_branch : {None, "above_flip", "below_flip"}
        None: added at every epoch; otherwise only while β is above / below the flip threshold
        of a yaw-steering satellite (:func:`applies`), a code error that changes with the
        attitude mode (Jiang et al. 2023: B1C and GPS L1).
    **params
        Every parameter of the model (fields of :class:`Hy2bP1` or :class:`Bds3Patchy`; tuples
        may be given as lists). The campaign schema holds their defaults: build a map from a
        validated ``simulate.code_bias_maps`` item with :meth:`from_config`.

    Raises
    ------
    ValueError
        If the model is unknown, or a parameter does not belong to it or is missing.
    """

    def __init__(self, name: str, signal: str, yaw_branch: str | None = None, **params):
        if yaw_branch not in YAW_BRANCHES:
            raise ValueError(f"unknown yaw_branch {yaw_branch!r} (known: {YAW_BRANCHES})")
        if name not in _MODEL_CLASSES:
            raise ValueError(f"unknown code-bias map model '{name}' (known: {', '.join(MODELS)})")
        cls = _MODEL_CLASSES[name]
        known = {f.name for f in fields(cls) if f.init}
        unknown = set(params) - known
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} of code-bias map model "
                             f"'{name}' (known: {sorted(known)})")
        missing = known - set(params)
        if missing:
            raise ValueError(f"code-bias map model '{name}' lacks the parameter(s) "
                             f"{sorted(missing)} (validate the map against the campaign "
                             "schema, which holds their defaults)")
        params = {k: tuple(v) if isinstance(v, list) else v for k, v in params.items()}
        self.name = name
        self.signal = signal
        self.yaw_branch = yaw_branch
        self.model = cls(**params)

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> CodeBiasMap:
        """A map from a validated item of ``simulate.code_bias_maps``
        (``{"model": ..., "signal": ..., <every parameter of the model>}``).

        Raises
        ------
        KeyError
            If ``model`` or ``signal`` is missing (the item was not validated).
        """
        cfg = dict(config)
        return cls(cfg.pop("model"), cfg.pop("signal"), **cfg)

    def __repr__(self) -> str:
        return (f"CodeBiasMap(name={self.name!r}, signal={self.signal!r}, "
                f"yaw_branch={self.yaw_branch!r}, model={self.model!r})")

    @property
    def key(self) -> str:
        """``<signal>`` or ``<signal>_<yaw_branch>``: the map's name in the truth files."""
        return self.signal if self.yaw_branch is None else f"{self.signal}_{self.yaw_branch}"

    def applies(self, below_flip: np.ndarray | None) -> np.ndarray | bool:
        """Where the map is added: True for a map without ``yaw_branch``, else the epochs of
        its branch.

        Parameters
        ----------
        below_flip : ndarray of bool, shape (n,), or None
            β below the flip threshold at each epoch; None for a satellite without the
            yaw-steering law.

        Raises
        ------
        ValueError
            If the map has a ``yaw_branch`` and ``below_flip`` is None.
        """
        if self.yaw_branch is None:
            return True
        if below_flip is None:
            raise ValueError(f"code-bias map of {self.signal} with yaw_branch "
                             f"{self.yaw_branch!r} needs a satellite with the yaw_steering law")
        return below_flip if self.yaw_branch == "below_flip" else ~below_flip

    def __call__(self, az_deg, el_deg) -> np.ndarray:
        """Map value [m] for antenna-frame azimuth and elevation [deg] (broadcast arrays).

        Parameters
        ----------
        az_deg : array_like
            Azimuth from body +X towards +Y [deg], any range.
        el_deg : array_like
            Elevation above the antenna horizon [deg]; values below 0 are evaluated at 0.

        Returns
        -------
        numpy.ndarray
            Code bias [m], shape of the broadcast inputs.
        """
        az = np.asarray(az_deg, dtype=float)
        el = np.clip(np.asarray(el_deg, dtype=float), 0.0, 90.0)
        return np.asarray(self.model(az, el), dtype=float)

    def grid(self, step_deg: float = 5.0) -> xr.Dataset:
        """The map on a cell-centred grid (the truth a code-bias estimation is compared to).

        Parameters
        ----------
        step_deg : float
            Cell size in azimuth and elevation [deg]; must divide 90.

        Returns
        -------
        xarray.Dataset
            ``code_bias_m`` (el, az) [m] at the cell centres ``az = step/2, ..., 360 - step/2``
            and ``el = step/2, ..., 90 - step/2`` [deg]; attrs name the model, signal,
            parameters, frame convention and the area-weighted mean.
        """
        n_el = round(90.0 / step_deg)
        if not np.isclose(n_el * step_deg, 90.0):
            raise ValueError(f"step_deg={step_deg} does not divide 90°")
        az = (np.arange(round(360.0 / step_deg)) + 0.5) * step_deg
        el = (np.arange(n_el) + 0.5) * step_deg
        values = self(az[None, :], el[:, None])
        return xr.Dataset(
            {"code_bias_m": (("el", "az"), values,
                             {"units": "m", "long_name": f"code bias of {self.signal} "
                                                         "(value at the cell centre)"})},
            coords={"el": ("el", el, {"units": "degree", "long_name": "elevation above the "
                                      "antenna X-Y plane (cell centre)"}),
                    "az": ("az", az, {"units": "degree", "long_name": "azimuth from body +X "
                                      "towards +Y (cell centre)"})},
            attrs={"model": self.name, "signal": self.signal,
                   "yaw_branch": self.yaw_branch or "all epochs", "step_deg": float(step_deg),
                   "parameters": repr(self.model), "area_mean_m": self.mean_m(),
                   "frame": "antenna frame of leopod.frames.attitude.antenna_angles"},
        )

    def mean_m(self, n: int = 64) -> float:
        """Area-weighted mean of the map over the hemisphere el ∈ [0°, 90°] [m].

        ``∫∫ b cos el d(el) d(az) / 2π``, by Gauss-Legendre quadrature in ``sin el`` (``n``
        nodes) and the trapezoidal rule in azimuth (``4n`` nodes, exact for periodic
        functions to the map's smoothness).
        """
        u, w = np.polynomial.legendre.leggauss(n)
        sin_el = 0.5 * (u + 1.0)
        el = np.degrees(np.arcsin(sin_el))
        az = np.arange(4 * n) * 360.0 / (4 * n)
        values = self(az[None, :], el[:, None])
        return float(0.5 * np.sum(w[:, None] * values) / (4 * n))
