"""Closed loop of the LEO receiver antenna model (leopod.gnss.leo_antenna): observations
simulated WITH the GOCE phase-centre pattern and estimated WITH the same antenna model give the
orbit of a simulation without any PCV; estimated WITHOUT the pattern they do not.

Authority: the simulation truth (orbit) and the real AIUB pattern of GOCE
(../shared/data/antex/GOCE_MAIN_0001.ATX; Jäggi et al. 2009, residual method, ionosphere-free
values filled in for both frequencies): PCV of -3 to +1 cm between zenith 0 and 80 deg with an
azimuthal part of about +-1 cm, the size of the pattern that paper 001 (HY-2A) estimates.

Set-up of tests/estimation/_simulated_arc.py (the default HY-2B-like day, degree-30 truth
field, float POD of 1-5 h with the default campaign's settings). The two simulations differ
only by the PCV: same truth, products and random draws, the GOCE PCO as the body-frame PCO of
both (``dict(antenna)``: ARP + R_ant PCO_b per band).

Measured (float POD of 1-5 h, 3D RMS against the truth; phase = IF phase residual RMS):

=====================================  ==========  ==========  ====================
case                                   orbit 3D    phase RMS   residual-PCV corr.
=====================================  ==========  ==========  ====================
no PCV simulated, none modelled        29.93 mm    7.93 mm
GOCE PCV simulated and modelled        29.98 mm    7.93 mm     -0.01
GOCE PCV simulated, not modelled       42.98 mm    10.92 mm    0.55
=====================================  ==========  ==========  ====================

(a 4-h float arc is at the cm level, tests/estimation/test_yaw_steering_closed_loop.py; what
matters is the difference). About 20 s on one core.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
import xarray as xr
from _bds3_arc import orbit_rms_3d_m
from _simulated_arc import DAY, GOCE, SAT, float_pod_arc, goce_world

from leopod.simulate.campaign import simulate_leo_day

HOURS = (1.0, 5.0)

pytestmark = pytest.mark.skipif(not GOCE.exists(), reason="needs ../shared/data/antex")


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    folder = tmp_path_factory.mktemp("leo_antenna")
    clock = time.perf_counter()
    world = goce_world(folder)
    cfg, antenna, pco_only, sim = world.cfg, world.antenna, world.pco_only, world.sim
    truth, biases = world.truth, world.biases
    for name, ant in (("pcv", antenna), ("nopcv", pco_only)):
        simulate_leo_day(DAY, SAT, sim, DAY, DAY, truth, biases, ant,
                         rinex3=folder / f"{name}.rnx", truth_sp3=folder / f"{name}.sp3",
                         truth_nc=folder / f"{name}.nc")
    with xr.open_dataset(folder / "pcv.nc") as f:
        truth_day = f.load()
    runs = {"reference": ("nopcv.rnx", pco_only),     # no PCV simulated nor modelled
            "matched": ("pcv.rnx", antenna),          # GOCE PCV simulated and modelled
            "unmodelled": ("pcv.rnx", pco_only)}      # GOCE PCV simulated, not modelled
    out = {}
    for case, (rinex, ant) in runs.items():
        arc = float_pod_arc(folder, cfg, rinex, ant, HOURS)
        res = arc.residuals.phase_residual_m.values
        out[case] = {"orbit_3d_m": orbit_rms_3d_m(arc.orbit, truth_day),
                     "phase_rms_m": float(np.sqrt(np.nanmean(res**2))),
                     "residuals": arc.residuals}
    out["seconds"] = time.perf_counter() - clock
    out["antenna"] = antenna
    return out


def test_the_modelled_pattern_gives_the_orbit_without_pcv(cases):
    ref, m = cases["reference"], cases["matched"]
    print(f"\nno PCV: orbit {ref['orbit_3d_m'] * 1e3:.2f} mm 3D, phase RMS "
          f"{ref['phase_rms_m'] * 1e3:.2f} mm; GOCE PCV simulated and modelled: "
          f"{m['orbit_3d_m'] * 1e3:.2f} mm, {m['phase_rms_m'] * 1e3:.2f} mm "
          f"({cases['seconds']:.0f} s)")
    assert abs(m["orbit_3d_m"] - ref["orbit_3d_m"]) < 1e-3
    assert abs(m["phase_rms_m"] - ref["phase_rms_m"]) < 0.2e-3


def _pattern_correlation(residuals: xr.Dataset, antenna) -> float:
    """Correlation of the phase residuals with the (ionosphere-free = L1, the GOCE file)
    PCV at their antenna-frame angles."""
    ok = np.isfinite(residuals.phase_residual_m.values)
    el, az = residuals.el_deg.values[ok], residuals.az_deg.values[ok]
    pcv = antenna.pcv_m("L1", 90.0 - el, az)
    r = residuals.phase_residual_m.values[ok]
    return float(np.corrcoef(r - r.mean(), pcv - pcv.mean())[0, 1])


def test_the_unmodelled_pattern_degrades_the_orbit_and_leaves_a_residual_pattern(cases):
    ref, m, u = cases["reference"], cases["matched"], cases["unmodelled"]
    corr_u = _pattern_correlation(u["residuals"], cases["antenna"])
    corr_m = _pattern_correlation(m["residuals"], cases["antenna"])
    print(f"\nGOCE PCV simulated, not modelled: orbit {u['orbit_3d_m'] * 1e3:.2f} mm 3D, "
          f"phase RMS {u['phase_rms_m'] * 1e3:.2f} mm; correlation of the residuals with the "
          f"pattern {corr_u:.2f} (modelled: {corr_m:.2f})")
    assert u["orbit_3d_m"] > ref["orbit_3d_m"] + 5e-3
    assert u["phase_rms_m"] > 1.25 * ref["phase_rms_m"]
    # the residuals follow the pattern (part of it goes into clocks, ambiguities and orbit)
    assert corr_u > 0.4
    assert abs(corr_m) < 0.1
