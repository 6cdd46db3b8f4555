"""A satellite's macro model and attitude for the plate forces (drag, SRP, Earth radiation).

``satellites.<sat>.macro_model`` gives the flat plates of a satellite
(:class:`leopod.dynamics.srp.MacroModel`): a list of plates or the built-in ``grace`` model;
the drag, SRP and Earth-radiation sections of ``pod.forces`` use them with ``plates: true``
(cannonball otherwise, the default). :func:`macro_model_from_config` builds the model.

**The GRACE macro model** (:func:`grace_macro_model`): the twelve plates of the GRACE
satellites in the science reference frame (SRF: +X towards the K-band horn, +Z to nadir when
flying nominally), from the GRACE Product Specification Document (Bettadpur 2012, GRACE
327-720, table of the satellite macro model): front and rear panels 0.9551567 m², the outer
(solar-array) side panels 3.1554792 m² tilted with normals (0, ±0.766044, −0.642787), the
inner side panels 0.2282913 m² with normals (0, ∓0.766044, 0.642787), nadir 6.0711120 m²,
zenith (solar array) 2.1673620 m² and the four faces of the K-band horn 0.0461901 m²; visible
specular / diffuse reflectivities and infrared emissivities 0.40 / 0.26 / 0.62 for the panels
of the body and the horn, 0.05 / 0.30 / 0.81 for the solar arrays, 0.68 / 0.20 / 0.75 for the
nadir panel. The same areas, normals, visible absorption 1 − ρ_s − ρ_d and infrared absorption
ε appear in the GRACE-FO panel model of Siemes et al. (2023, J. Space Weather Space Clim. 13,
16, Table A3; its arrays differ). The infrared reflectance 1 − ε is split between specular and
diffuse in the visible proportion (an assumption: the table gives ε only). No plate C_D is
given there: every plate takes ``drag_coefficient`` (default 2.3, as the cannonball).

**Attitude along a reference orbit** (:class:`Plates`): the plate normals need the GCRF →
body rotation. The satellite's law (:func:`leopod.frames.leo_attitude.leo_body_axes`: nominal,
yaw steering with offsets, or quaternion files) is evaluated once per arc at equidistant nodes
(``step_s``, 10 s) of a reference orbit, the one the drag density follows
(:meth:`leopod.dynamics.forces.ForceModel.follow`), and interpolated elementwise (Lagrange, 8
points) in the force kernels. A law of the state (nominal) on the reference orbit instead of
the integrated one errs by the angle the two subtend at the geocentre (≲ 1e-5 rad for 100 m).
The interpolated matrix is not exactly orthonormal between nodes; for the smooth nominal
rotation (one turn per revolution) the 10-s, degree-7 interpolation is exact to ~1e-13, but
near a yaw flip or a fast yaw-steering turn (β ≈ 0) the polynomial rings over ±40 s.
Partials hold the attitude fixed (module :mod:`leopod.dynamics.srp`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numba
import numpy as np

from leopod.dynamics.srp import MacroModel, _plate_normals
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes
from leopod.numerics.interpolate import lagrange_equidistant

__all__ = ["GRACE_PLATES", "Plates", "grace_macro_model",
           "macro_model_from_config", "plate_normals_at"]

_ATTITUDE_POINTS = 8        # Lagrange points of the tabulated attitude (degree 7)
_VELOCITY_STEP_S = 1.0      # half step of the central difference of the reference orbit

#: GRACE plates (Bettadpur 2012; module docstring): name, SRF normal, area [m²], visible
#: specular and diffuse reflectivity, infrared emissivity.
GRACE_PLATES = (
    ("front", (1.0, 0.0, 0.0), 0.9551567, 0.40, 0.26, 0.62),
    ("rear", (-1.0, 0.0, 0.0), 0.9551567, 0.40, 0.26, 0.62),
    ("starboard outer", (0.0, 0.766044, -0.642787), 3.1554792, 0.05, 0.30, 0.81),
    ("starboard inner", (0.0, -0.766044, 0.642787), 0.2282913, 0.40, 0.26, 0.62),
    ("port outer", (0.0, -0.766044, -0.642787), 3.1554792, 0.05, 0.30, 0.81),
    ("port inner", (0.0, 0.766044, 0.642787), 0.2282913, 0.40, 0.26, 0.62),
    ("nadir", (0.0, 0.0, 1.0), 6.0711120, 0.68, 0.20, 0.75),
    ("zenith", (0.0, 0.0, -1.0), 2.1673620, 0.05, 0.30, 0.81),
    ("horn front", (1.0, 0.0, 0.0), 0.0461901, 0.40, 0.26, 0.62),
    ("horn rear", (-1.0, 0.0, 0.0), 0.0461901, 0.40, 0.26, 0.62),
    ("horn starboard", (0.0, 1.0, 0.0), 0.0461901, 0.40, 0.26, 0.62),
    ("horn port", (0.0, -1.0, 0.0), 0.0461901, 0.40, 0.26, 0.62),
)


def _infrared(specular, diffuse, emissivity):
    """Infrared specular and diffuse reflectivities: 1 − ε split as in the visible (all
    diffuse for a black plate in the visible); ε None: those of the visible."""
    spec, diff = np.asarray(specular, float), np.asarray(diffuse, float)
    if emissivity is None:
        return spec, diff
    eps = np.asarray(emissivity, dtype=float)
    if np.any((eps < 0.0) | (eps > 1.0)):
        raise ValueError("emissivity must be in [0, 1]")
    total = spec + diff
    share = np.divide(spec, total, out=np.zeros_like(total), where=total > 0.0)
    return (1.0 - eps) * share, (1.0 - eps) * (1.0 - share)


def grace_macro_model(mass_kg: float, drag_coefficient: float = 2.3) -> MacroModel:
    """The GRACE macro model (module docstring) for a satellite mass [kg] and plate C_D [1]."""
    _, normals, area, spec, diff, eps = zip(*GRACE_PLATES, strict=True)
    spec_ir, diff_ir = _infrared(spec, diff, eps)
    return MacroModel(normal_body=np.array(normals), area_m2=np.array(area),
                      specular=np.array(spec), diffuse=np.array(diff),
                      drag_coefficient=float(drag_coefficient), mass_kg=float(mass_kg),
                      specular_ir=spec_ir, diffuse_ir=diff_ir)


def macro_model_from_config(section: Mapping | None, where: str = "macro_model"
                            ) -> MacroModel | None:
    """The macro model of ``satellites.<sat>.macro_model`` (schema ``$defs/macro_model``).

    Parameters
    ----------
    section : mapping or None
        ``builtin`` (``grace``) or ``plates`` (a list of mappings with ``normal_body``,
        ``area_m2``, ``specular``, ``diffuse``, ``emissivity`` (null: grey),
        ``drag_coefficient`` (null: the section's), ``sun_tracking`` (0, +1 front, −1 back
        face of an array turning about ``panel_axis_body``)), ``mass_kg``,
        ``drag_coefficient``, ``panel_axis_body``. None: no macro model.
    where : str
        Name of the section in error messages.

    Raises
    ------
    ValueError
        Naming the section, the plate and the field at fault.
    """
    if section is None:
        return None
    builtin, plates = section.get("builtin"), list(section.get("plates") or ())
    mass, cd = section.get("mass_kg"), float(section.get("drag_coefficient", 2.3))
    if mass is None:
        raise ValueError(f"{where}: mass_kg is required")
    if (builtin is None) == (not plates):
        raise ValueError(f"{where}: give either builtin or plates (builtin {builtin!r}, "
                         f"{len(plates)} plates)")
    if builtin is not None:
        if builtin != "grace":
            raise ValueError(f"{where}.builtin: unknown model {builtin!r} (known: grace)")
        return grace_macro_model(mass, cd)
    columns = {key: [] for key in ("normal_body", "area_m2", "specular", "diffuse",
                                   "drag_coefficient", "panel", "specular_ir", "diffuse_ir")}
    for i, plate in enumerate(plates):
        try:
            spec_ir, diff_ir = _infrared(plate["specular"], plate["diffuse"],
                                         plate.get("emissivity"))
            MacroModel(normal_body=[plate["normal_body"]], area_m2=plate["area_m2"],
                       specular=plate["specular"], diffuse=plate["diffuse"],
                       drag_coefficient=cd, mass_kg=mass, specular_ir=spec_ir,
                       diffuse_ir=diff_ir, panel=[plate.get("sun_tracking", 0)])
        except (KeyError, ValueError, TypeError) as err:
            raise ValueError(f"{where}.plates[{i}]: {err}") from None
        for key, value in (("normal_body", plate["normal_body"]), ("area_m2", plate["area_m2"]),
                           ("specular", plate["specular"]), ("diffuse", plate["diffuse"]),
                           ("drag_coefficient", plate.get("drag_coefficient") or cd),
                           ("panel", plate.get("sun_tracking", 0)),
                           ("specular_ir", spec_ir), ("diffuse_ir", diff_ir)):
            columns[key].append(value)
    return MacroModel(mass_kg=float(mass), panel_axis_body=np.asarray(
        section.get("panel_axis_body", (0.0, 1.0, 0.0)), dtype=float),
        **{k: np.asarray(v, dtype=float if k != "panel" else np.int64)
           for k, v in columns.items()})


# ------------------------------------------------------------------ attitude along an orbit


@numba.njit(cache=True)
def plate_normals_at(t, pos, sun, data):  # pragma: no cover - numba
    """GCRF plate normals (k, 3) at time t [s] and GCRF position and Sun [m] from the
    :meth:`Plates.kernel_data` tuple (attitude interpolated, Sun-tracking arrays turned)."""
    table = data[8]
    row = np.empty(9)
    lagrange_equidistant(t, table[0], table[1], table[2], table[3], row)
    return _plate_normals(row.reshape(3, 3), data[0], data[6], data[7], pos, sun)


class Plates:
    """A macro model flown with an attitude law over an arc (module docstring).

    Parameters
    ----------
    model : MacroModel
    attitude : LeoAttitude or None
        The satellite's law (None: nominal); the ``file`` law with its quaternions attached.
    env : ArcEnvironment
        Epochs, Sun and the arc span.
    step_s : float
        Node spacing of the tabulated attitude [s].
    """

    def __init__(self, model: MacroModel, attitude: LeoAttitude | None, env,
                 step_s: float = 10.0):
        self.model, self.attitude, self.env, self.step_s = model, attitude, env, float(step_s)
        self._table: tuple | None = None

    def follow(self, positions) -> None:
        """Tabulate the attitude along a reference orbit ``positions(t_s (n,)) -> (n, 3)``
        (GCRF [m]) from the start to the end of the arc (and a node beyond)."""
        lo, hi = self.env.t_start_s - self.step_s, self.env.t_end_s + self.step_s
        n = max(int(np.ceil((hi - lo) / self.step_s - 1e-9)), _ATTITUDE_POINTS - 1) + 1
        t = lo + self.step_s * np.arange(n)
        h = _VELOCITY_STEP_S
        pos = positions(t)
        vel = (positions(t + h) - positions(t - h)) / (2.0 * h)
        axes = leo_body_axes(self.attitude, pos, vel, self.env.sun_m(t),
                             times=self.env.times(t))
        if not np.isfinite(axes).all():
            raise ValueError("plates: the attitude law gives no rotation at some epochs of "
                             "the arc")
        self._table = (float(t[0]), self.step_s, _ATTITUDE_POINTS,
                       np.ascontiguousarray(axes.reshape(n, 9)))

    @property
    def ready(self) -> bool:
        """True once :meth:`follow` has tabulated the attitude."""
        return self._table is not None

    def kernel_data(self) -> tuple:
        """``(normal_body, area, specular, diffuse, specular_ir, diffuse_ir, panel,
        panel_axis, attitude table, mass, drag_coefficient)`` for the jitted kernels."""
        if self._table is None:
            raise ValueError("plates: no reference orbit to take the attitude along (follow())")
        m = self.model
        return (m.normal_body, m.area_m2, m.specular, m.diffuse, m.specular_ir, m.diffuse_ir,
                m.panel, m.panel_axis_body, self._table, float(m.mass_kg), m.drag_coefficient)

    def normals(self, t_s: float, pos_m: np.ndarray, sun_m: np.ndarray) -> np.ndarray:
        """GCRF plate normals (k, 3) at one epoch [s] (:func:`plate_normals_at`)."""
        return plate_normals_at(float(t_s), np.ascontiguousarray(pos_m, dtype=float),
                                np.ascontiguousarray(sun_m, dtype=float), self.kernel_data())
