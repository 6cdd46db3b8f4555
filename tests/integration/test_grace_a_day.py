"""Ingest and quality of the real GRACE-A day 2007-03-21 (../shared/data/grace-a_2007-080).

Authorities: the MANIFEST of the data (10 s, 8640 epochs, 7-10 satellites per epoch, LLI set
at every detected slip and at acquisition), the GRACE orbit (mean altitude about 470 km in
2007, near-circular, 89° inclination), and the receiver's own loss-of-lock flags.
"""

from pathlib import Path

import numpy as np
import pytest

from leopod.dynamics.force_config import ForceModelSettings
from leopod.estimation.arc import ArcData, ArcSettings, run_arc
from leopod.estimation.fixed_arc import FixedSolutions, FloatSolution
from leopod.estimation.float_pod import PodSettings
from leopod.frames.attitude import antenna_angles, nominal_body_axes
from leopod.gnss.products import GnssProducts
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.ingest import apriori_from_spp, canonical_observations, gnss_at_epochs
from leopod.io.antex import read_antex
from leopod.io.clock import read_rinex_clock
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.signals import signal_settings
from leopod.workflow.config import load_campaign, section_defaults

pytestmark = pytest.mark.shared
SIGNALS = signal_settings({"G": {"phase": ["L1C", "L2W"], "code": ["C1C", "C1W", "C2W"],
                                 "pod_code": ["C1W", "C2W"]}})
REPO = Path(__file__).resolve().parents[2]
PCO = {"L1": [-0.0004, -0.0004, -0.4514], "L2": [-0.0004, -0.0004, -0.4757]}


@pytest.fixture(scope="module")
def day(shared_data):
    d = shared_data / "grace-a_2007-080"
    raw = read_rinex_obs(d / "graa0800.07o.gz")
    obs = canonical_observations(raw, SIGNALS)
    products = GnssProducts.from_datasets(read_sp3(d / "cod14193.sp3.gz"),
                                          read_rinex_clock(d / "cod14193.clk.gz"),
                                          np.datetime64("2007-03-21"), max_extrapolation_s=900.0)
    gnss = gnss_at_epochs(products, obs.time.values)
    leo = apriori_from_spp(obs, products, SIGNALS, PCO, read_antex(d / "igs05_1402.atx.gz"))
    rot = nominal_body_axes(leo.pos_m.values, leo.vel_m_s.values)
    el, az = antenna_angles(rot, gnss.pos_m.sel(sv=obs.sv).values - leo.pos_m.values[:, None, :])
    q = assess_quality(obs, el, az, "G", ["L1C", "L2W"], ["C1C", "C1W", "C2W"], ["C1W", "C2W"],
                       QualitySettings.from_config(section_defaults("quality")))
    return dict(raw=raw, obs=obs, leo=leo, q=q)


def test_canonical_observations_in_metres(day):
    obs, raw = day["obs"], day["raw"]
    assert obs.sizes["time"] == 8640
    lam1 = 299_792_458.0 / 1575.42e6
    np.testing.assert_allclose(obs.L1C.sel(sv="G01").values[0], raw.L1.sel(sv="G01").values[0] * lam1)
    assert obs.C1W.attrs["rinex_name"] == "P1"


def test_code_only_orbit_is_a_grace_orbit(day):
    leo = day["leo"]
    r = np.linalg.norm(leo.pos_m.values, axis=1)
    v = np.linalg.norm(leo.vel_m_s.values, axis=1)
    ok = np.isfinite(r)
    assert ok.mean() > 0.99
    assert 6.80e6 < np.median(r[ok]) < 6.88e6           # ~470 km altitude
    assert 7.55e3 < np.median(v[ok]) < 7.75e3            # Earth-fixed speed of a ~470 km orbit
    # ionosphere-free P-code noise of the day: sqrt((2.55 MP1)^2 + (1.55 MP2)^2) ~ 0.9 m
    assert np.nanmedian(leo.rms_m.values) < 1.0
    # the kinematic positions scatter around the smoothed orbit by residual x PDOP (~1.9)
    d = np.linalg.norm(leo.pos_kinematic_m.values - leo.pos_m.values, axis=1)
    assert np.nanmedian(d) < 2.0
    assert np.nanpercentile(d, 90) < 6.0


def test_every_receiver_loss_of_lock_starts_a_pass(day):
    q, obs = day["q"], day["obs"]
    lli = ((obs.L1C_lli.values.clip(0) | obs.L2W_lli.values.clip(0)) & 1) != 0
    tracked = q.pass_id.values >= 0
    starts = (q.pass_flag.values != 0) & tracked
    assert np.all(starts[lli & tracked])


def test_daily_indicators_are_plausible(day):
    q = day["q"]
    assert 7.0 <= float(q.G_mean_sv_per_epoch) <= 10.0
    assert float(q.G_completeness) > 0.99
    for code in ("C1C", "C1W", "C2W"):
        rms = float(q[f"G_mp_rms_{code}_m"])
        assert 0.05 < rms < 1.0          # decimetre level, like Wang et al. (2024) Table 2
    assert 10 < float(q.G_obs_per_slip) < 1000


@pytest.fixture(scope="module")
def three_hour_arc(day, shared_data):
    """Float reduced-dynamic POD of 00-03 h with the campaign settings of the GRACE-A config
    (the arc and its run_arc arguments)."""
    cfg = load_campaign(REPO / "config" / "grace-a-2007.yaml")
    pod = cfg["pod"]
    models = shared_data.parent / "models"
    forces = {k: dict(v) for k, v in pod["forces"].items()}
    forces["gravity"]["field"] = str(models / "gravity" / "EGM2008_120.gfc")
    forces["tides"]["ocean"] = str(models / "ocean_tides" / "fes2004_Cnm-Snm.dat")
    forces["drag"]["space_weather"] = str(models / "space_weather" / "SW-All.csv")
    d = shared_data / "grace-a_2007-080"
    t0 = np.datetime64("2007-03-21T00:00", "ns")
    data = ArcData(obs=[day["obs"]], quality=[day["q"]], leo=[day["leo"]],
                   orbit=read_sp3(d / "cod14193.sp3.gz"),
                   clock=read_rinex_clock(d / "cod14193.clk.gz"),
                   antex=read_antex(d / "igs05_1402.atx.gz"))
    args = ("2007-080", data, SIGNALS["G"], ArcSettings.from_config(pod),
            PodSettings.from_config(pod), ForceModelSettings.from_config(forces), PCO)
    limits = (t0, t0 + np.timedelta64(3, "h"))
    return run_arc(*args, limits=limits), args, limits


def test_float_pod_three_hour_arc(three_hour_arc):
    """Float reduced-dynamic POD of 00-03 h with the campaign settings of the GRACE-A config.

    Authority for the residual level: Wang et al. (2024) sec. 3.3.1 (HY-2A float reduced-dynamic
    POD, undifferenced IF phase residual RMS 7.04-7.76 mm per day); GRACE's BlackJack tracks L1/L2
    at least as well. The code residual follows the IF P-code noise of the day (~0.9 m
    from MP1/MP2, see test_code_only_orbit_is_a_grace_orbit) plus low-elevation multipath.
    """
    arc = three_hour_arc[0]
    r = arc.result
    assert r.converged
    phase_rms = np.sqrt(np.nanmean(r.phase_residual_m**2))
    code_rms = np.sqrt(np.nanmean(r.code_residual_m**2))
    # Bounds from the values measured on 2026-11-25: phase RMS 6.35 mm
    # (upper bound +0.45 mm: with the wind-up sign flipped it is 7.26 mm, so this real-data
    # test is also a witness of that sign), code RMS 1.553 m (+0.2 m), rejected phase 0.0 %
    # and code 3.4 % (+1 point), formal sigma median 5.7 mm (+30 %).
    assert 0.003 < phase_rms < 0.0068
    assert 0.5 < code_rms < 1.75
    assert r.phase_rejected.mean() < 0.01 and r.code_rejected.mean() < 0.045
    # the code-only a-priori orbit scatters by metres around the float orbit, not more
    # (measured RMS R/T/N 4.04 / 0.87 / 1.18 m)
    diff = arc.orbit.apriori_diff_rtn_m.values
    assert np.all(np.sqrt(np.nanmean(diff**2, axis=0)) < 5.0)
    # formal sigmas: mm level
    assert 1e-3 < float(arc.orbit.sigma_rtn_m.median()) < 0.0075


def test_warm_start_reproduces_a_converged_solution(three_hour_arc):
    """A converged solution is a fixed point of the iteration (analytic property of Gauss-
    Newton at convergence): linearised at its datasets (the fixed POD's start) and solved
    without constraints, it returns the same orbit, to far below its 1 mm convergence
    tolerance times the ~1e-2 contraction of the last float iteration."""
    arc, args, limits = three_hour_arc
    start = FloatSolution(parameters=arc.parameters, ambiguities=arc.ambiguities,
                          residuals=arc.residuals, orbit=arc.orbit)
    again = FixedSolutions(*args, start, limits=limits).solve()
    assert again.result.converged and again.result.integrations == 1
    d = again.orbit.pos_gcrf_m.values - arc.orbit.pos_gcrf_m.values
    assert np.max(np.abs(d)) < 1e-3
    assert np.array_equal(again.result.phase_rejected, arc.result.phase_rejected)
