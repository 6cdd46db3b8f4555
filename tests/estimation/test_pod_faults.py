"""Fault catalogue of the POD chain (issue 24, item 4): real-world faults injected into one
simulated day, and what the float POD makes of them.

Authority: the truth of the closed-loop simulation (leopod.simulate: the orbit the
observations were generated from), against which every orbit is compared in R, T, N; the
SP3-d specification (Hilla 2016) for the bad-value markers. Each fault either gives an orbit
whose error against the truth is bounded (and the removed data counted in the log), or a
clear error naming its cause, and the quality gate (leopod.validation.quality_gate) marks the
day where the orbit cannot be trusted.

Set-up: the default campaign's HY-2B-like day (tests/estimation/_simulated_arc.py, degree-30
truth field), GPS float POD of 1-5 h with the default campaign's settings (0.5-5.5 h for the
gap, 0-24 h for half a day). Measured (3D RMS of orbit minus truth; ``report`` prints each):

=====================================  ==========  ==================================  =========
fault                                  3D error    removed / logged                    gate
=====================================  ==========  ==================================  =========
none (reference)                       3.0 cm      133 code outliers                   ok
2-h data gap (2-4 h)                   9.3 cm      none (13.8 cm inside the gap)       suspect
receiver clock jump of 1 ms            3.0 cm      nothing: the epoch clock absorbs it ok
10-m along-track orbit error, 1 GPS    3.4 cm      364 phase, 101 code outliers        ok
10-ns clock jump in the products       3.1 cm      418 phase outliers                  ok
SP3 0.000000 / 999999.999999 records   3.2 cm      131 observations without products   ok
SP3 manoeuvre flag "M" (3 records)     3.2 cm      3 records, 131 observations         ok
unannounced 5-cm/s burn                8.4 m       937 phase, 764 code outliers        failed
the same burn announced                3.0 cm      none                                ok
half a day of data                     2.7 cm      orbit ends at 11:59:30              suspect
epochs with 3 satellites (30)          2.9 cm      30 epochs (no code-only solution)   ok
damaged netCDF of an earlier run       --          FormatError naming the file         --
=====================================  ==========  ==================================  =========
"""

from __future__ import annotations

import copy
import logging
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from _simulated_arc import DAY, REPO, SAT, T0, arc_data, simulated_gnss_world

from leopod.constants import C_LIGHT_M_S
from leopod.estimation.arc import ArcData, run_arc
from leopod.ingest import canonical_observations
from leopod.io._text import FormatError
from leopod.io.clock import read_rinex_clock
from leopod.io.manoeuvre import Manoeuvre
from leopod.io.rinex_obs import read_rinex_obs
from leopod.io.sp3 import read_sp3
from leopod.io.sp3_write import write_sp3
from leopod.signals import signal_settings
from leopod.simulate.campaign import simulate_leo_day, simulate_truth
from leopod.simulate.settings import SimulationSettings
from leopod.validation.compare import difference_rtn, rms_rtn
from leopod.validation.quality_gate import GateSettings, check, pod_figures
from leopod.workflow.config import load_campaign, with_defaults
from leopod.workflow.settings import pod_settings

CFG = load_campaign(REPO / "config" / "config.yaml")
PCO = CFG["satellites"][SAT]["antenna_pco_body_m"]
HOURS = (1.0, 5.0)
SECTION = {"truth": {"gravity_degree": 30}}
GATE = GateSettings.from_config(CFG["pod"].get("quality_gate", {}))


def at(hours: float) -> np.datetime64:
    return T0 + np.timedelta64(round(3600 * hours), "s")


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    folder = tmp_path_factory.mktemp("faults")
    sim = SimulationSettings.from_config(with_defaults("simulate", SECTION))
    truth, biases = simulated_gnss_world(folder, sim)
    return SimpleNamespace(folder=folder, sim=sim, truth=truth, biases=biases,
                           orbit=read_sp3(folder / "g.sp3"),
                           clock=read_rinex_clock(folder / "g_int.clk"))


def leo_day(world, name: str, sim: SimulationSettings | None = None,
            truth: xr.Dataset | None = None):
    """Canonical observations and truth of the simulated day (``sim``/``truth`` replacing
    the world's)."""
    f = world.folder
    simulate_leo_day(DAY, SAT, sim or world.sim, DAY, DAY,
                     world.truth if truth is None else truth, world.biases, PCO,
                     rinex3=f / f"{name}.rnx", truth_sp3=f / f"{name}.sp3",
                     truth_nc=f / f"{name}.nc")
    obs = canonical_observations(read_rinex_obs(f / f"{name}.rnx"),
                                 signal_settings(CFG["signals"]))
    return obs, xr.load_dataset(f / f"{name}.nc")


@pytest.fixture(scope="module")
def nominal(world):
    obs, truth = leo_day(world, "o")
    return SimpleNamespace(obs=obs, truth=truth)


def pod(obs, orbit, clock, hours=HOURS, manoeuvres=(), cfg=CFG):
    """Float POD of ``hours`` of the day (scripts/float_pod.py)."""
    data = arc_data(cfg, obs, orbit, clock)
    data.manoeuvres = tuple(manoeuvres)
    s = pod_settings(cfg["signals"], cfg["pod"], cfg["code_bias"])
    return run_arc(DAY, data, s["signals"], s["arc"], s["pod"], s["forces"], PCO,
                   limits=(at(hours[0]), at(hours[1])))


def error_cm(arc, truth, start=None, end=None) -> float:
    """3D RMS of the orbit minus the truth [cm] (ITRF, at the orbit's epochs)."""
    return 100 * rms_rtn(difference_rtn(arc.orbit, truth, start=start, end=end))["3D"]


def gate(arc, hours=HOURS):
    """The quality gate's verdict on a solution for ``hours`` of the day."""
    figures = pod_figures(arc.orbit, arc.residuals, arc.parameters,
                          (at(hours[0]), at(hours[1])), float(CFG["pod"]["sampling_s"]))
    return check(figures, GATE, converged=arc.result.converged)


def report(name, arc, truth, hours=HOURS) -> float:
    """Print the error of a solution against the truth, its rejections and the gate's verdict
    (``pytest -s``); return the error [cm]."""
    err, res = error_cm(arc, truth), arc.result
    print(f"\n{name}: 3D error {err:.2f} cm, rejected {int(res.code_rejected.sum())} code / "
          f"{int(res.phase_rejected.sum())} phase, gate {gate(arc, hours)}")
    return err


def busy_satellite(obs, epoch) -> str:
    """The GPS satellite tracked longest within ±15 min of ``epoch`` (a pass across it)."""
    near = np.abs(obs.time.values - epoch) <= np.timedelta64(15, "m")
    return str(obs.sv.values[np.argmax(np.isfinite(obs.L1C.values[near]).sum(axis=0))])


def survives(label, caplog, message, day, orbit, clock) -> None:
    """The POD of the observations and truth of ``day`` against ``orbit`` and ``clock``: an
    orbit within 5 cm of the truth, ``message`` (what was removed) in its log, an ok gate."""
    with caplog.at_level(logging.WARNING):
        arc = pod(day.obs, orbit, clock)
    assert report(label, arc, day.truth) < 5.0
    assert message in caplog.text
    assert gate(arc).status == "ok"


@pytest.fixture(scope="module")
def reference(world, nominal):
    """The fault-free solution: its 3D error [cm] and rejections."""
    arc = pod(nominal.obs, world.orbit, world.clock)
    err = report("no fault", arc, nominal.truth)
    assert err < 5.0 and gate(arc).status == "ok"
    return SimpleNamespace(error_cm=err, phase_rejected=int(arc.result.phase_rejected.sum()))


def test_hours_long_data_gap(world, nominal):
    # a 2-h gap used to crash the arc set-up (the a-priori orbit interpolated across it gave
    # heights of -400 km: leopod.dynamics.forces.tabulated_orbit)
    obs, hours = nominal.obs, (0.5, 5.5)
    keep = (obs.time.values < at(2.0)) | (obs.time.values >= at(4.0))
    arc = pod(obs.isel(time=keep), world.orbit, world.clock, hours=hours)
    assert report("2-h gap", arc, nominal.truth, hours) < 15.0
    assert error_cm(arc, nominal.truth, at(2.0), at(4.0)) < 20.0
    verdict = gate(arc, hours)        # the orbit across the gap is dynamics alone
    assert verdict.status == "suspect"
    assert any(r.startswith("position_sigma_cm") for r in verdict.reasons)


def test_receiver_clock_jump_of_1_ms(world, nominal, reference):
    sim = SimulationSettings.from_config(with_defaults("simulate", {
        **SECTION, "clocks": {"rx_jumps": [{"epoch": "2019-01-01T03:00:00", "size_s": 1e-3}]}}))
    obs, truth = leo_day(world, "jump", sim=sim)
    # the codes jump by c * 1 ms (plus the range change over the 1 ms less of flight)
    step = np.nanmedian(obs.C1C.values - nominal.obs.C1C.values, axis=1)
    late = obs.time.values >= at(3.0)
    assert np.abs(step[~late]).max() < 1e-6
    np.testing.assert_allclose(step[late], 1e-3 * C_LIGHT_M_S, rtol=0, atol=10.0)
    arc = pod(obs, world.orbit, world.clock)
    # one receiver clock per epoch absorbs the jump of code and phase alike
    assert abs(report("1-ms receiver clock jump", arc, truth) - reference.error_cm) < 0.3
    assert int(arc.result.phase_rejected.sum()) == reference.phase_rejected
    assert gate(arc).status == "ok"


def test_gnss_orbit_error_of_10_m(world, nominal, reference):
    sv = busy_satellite(nominal.obs, at(3.0))
    orbit = world.orbit.copy(deep=True)
    pos = orbit.pos_m.sel(sv=sv).values
    along = np.gradient(pos, axis=0)
    orbit.pos_m.loc[{"sv": sv}] = pos + 10.0 * along / np.linalg.norm(along, axis=1,
                                                                       keepdims=True)
    arc = pod(nominal.obs, orbit, world.clock)
    assert report(f"10-m orbit error of {sv}", arc, nominal.truth) < 5.0
    rejected = arc.residuals.phase_rejected.sel(sv=sv).values
    assert rejected.sum() > 100 + reference.phase_rejected    # the screening removed it
    assert gate(arc).status == "ok"


def test_gnss_clock_jump_in_the_products(world, nominal, reference):
    sv = busy_satellite(nominal.obs, at(3.0))
    clock = world.clock.copy(deep=True)
    late = clock.time.values >= at(3.0)
    clock.clk_s.loc[{"sv": sv}] = clock.clk_s.sel(sv=sv).values + np.where(late, 1e-8, 0.0)
    arc = pod(nominal.obs, world.orbit, clock)
    assert report(f"10-ns clock jump of {sv}", arc, nominal.truth) < 5.0
    after = arc.residuals.time.values >= at(3.0)
    res = arc.residuals.sel(sv=sv)
    assert res.phase_rejected.values[after].sum() > 0
    used = res.phase_residual_m.values[after & (res.phase_rejected.values == 0)]
    assert np.nanmax(np.abs(used)) < 0.05     # no 3-m step left in the phases used
    assert gate(arc).status == "ok"


def test_sp3_bad_value_markers(world, nominal, tmp_path, caplog):
    # SP3-d: 0.000000 positions and 999999.999999 clocks are "bad or absent"
    sv = busy_satellite(nominal.obs, at(3.0))
    orbit = world.orbit.copy(deep=True)
    bad = (orbit.time.values >= at(2.5)) & (orbit.time.values <= at(3.0))
    orbit.pos_m.loc[{"sv": sv}] = np.where(bad[:, None], np.nan, orbit.pos_m.sel(sv=sv).values)
    orbit.clk_s.loc[{"sv": sv}] = np.where(bad, np.nan, orbit.clk_s.sel(sv=sv).values)
    write_sp3(orbit, tmp_path / "bad.sp3")
    text = (tmp_path / "bad.sp3").read_text()
    assert text.count("999999.999999") == bad.sum() and "      0.000000      0.000000" in text
    read = read_sp3(tmp_path / "bad.sp3")
    assert np.isnan(read.pos_m.sel(sv=sv).values[bad]).all()
    survives(f"SP3 bad records of {sv}", caplog, "observations without GNSS orbit or clock "
             f"(missing or bad in the products) not used: {sv}", nominal, read, world.clock)


def test_sp3_manoeuvre_flag(world, nominal, tmp_path, caplog):
    # SP3-d: column 79 of a P record, "M": the satellite manoeuvres (orbit unreliable)
    sv = busy_satellite(nominal.obs, at(3.0))
    write_sp3(world.orbit, tmp_path / "g.sp3")
    lines = (tmp_path / "g.sp3").read_text().splitlines()
    times, k_epoch, flagged = world.orbit.time.values, -1, 0
    for k, line in enumerate(lines):
        k_epoch += line.startswith("*")
        if line.startswith(f"P{sv}") and at(2.5) <= times[k_epoch] <= at(3.0):
            lines[k] = line.ljust(78) + "M"
            flagged += 1
    (tmp_path / "g.sp3").write_text("\n".join(lines) + "\n")
    read = read_sp3(tmp_path / "g.sp3")
    assert int(read.manoeuvre_flag.sum()) == flagged == 3
    survives(f"SP3 manoeuvre flag of {sv}", caplog, "GNSS orbits: 3 records flagged "
             f"(manoeuvre, or accuracy worse than 1 m) not used: {sv} 3", nominal, read,
             world.clock)


def test_unannounced_manoeuvre_fails_the_day(world):
    burn = Manoeuvre(at(3.0), at(3.0) + np.timedelta64(60, "s"), (0.0, 0.05 / 60, 0.0))
    truth = simulate_truth(world.sim, SAT, DAY, DAY, manoeuvres=[burn])
    obs, truth_day = leo_day(world, "burn", truth=truth)
    arc = pod(obs, world.orbit, world.clock)
    report("unannounced 5-cm/s burn", arc, truth_day)
    verdict = gate(arc)
    assert verdict.status == "failed"
    assert any(r.startswith("phase_rms_mm") for r in verdict.reasons)
    # announced (the manoeuvre list and pod.forces.manoeuvre), the same burn is estimated
    cfg = copy.deepcopy(CFG)
    cfg["pod"]["forces"]["manoeuvre"] = {"enabled": True, "estimate": True, "sigma": None}
    arc = pod(obs, world.orbit, world.clock, manoeuvres=[burn], cfg=cfg)
    assert report("announced 5-cm/s burn", arc, truth_day) < 5.0
    assert gate(arc).status == "ok"


def test_half_a_day_of_data(world, nominal):
    obs, hours = nominal.obs, (0.0, 24.0)
    arc = pod(obs.isel(time=obs.time.values < at(12.0)), world.orbit, world.clock, hours=hours)
    assert report("half a day", arc, nominal.truth, hours) < 5.0
    # no orbit beyond the data but the output margin (pod.output_margin_s, default 60 s) that
    # lets a daily file whose data end a few epochs before 24:00 cover its day (issue 23)
    assert arc.orbit.time.values[-1] == at(12.0) - np.timedelta64(30, "s") + np.timedelta64(
        60, "s")
    # the epochs beyond the data are the dynamic orbit integrated on, as good as its last
    # data epochs (authority: the simulated truth; an error of sign or time there shows)
    beyond = error_cm(arc, nominal.truth, start=at(12.0))
    print(f"half a day: 3D error over the 60 s beyond the data {beyond:.2f} cm")
    assert beyond < 5.0
    verdict = gate(arc, hours)
    assert verdict.status == "suspect" and verdict.reasons[0].startswith("coverage_pct 49.9")


def test_epochs_with_three_satellites(world, nominal, caplog):
    obs = nominal.obs.copy(deep=True)
    few = np.flatnonzero((obs.time.values >= at(2.5)) & (obs.time.values < at(2.75)))
    for k in few:
        tracked = np.flatnonzero(np.isfinite(obs.L1C.values[k]))
        for name in ("L1C", "L2W", "C1C", "C1W", "C2W"):
            obs[name].values[k, tracked[3:]] = np.nan
    survives("3 satellites at 30 epochs", caplog, f"{few.size} epochs with observations but "
             "without a code-only position", SimpleNamespace(obs=obs, truth=nominal.truth),
             world.orbit, world.clock)


def test_damaged_netcdf_of_an_earlier_run(world, nominal, tmp_path):
    # an ingest file cut short (a run killed while copying, a full disk): the POD step names it
    good = tmp_path / "obs.nc"
    nominal.obs.to_netcdf(good)
    damaged = tmp_path / "damaged.nc"
    damaged.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    files = {"obs": [damaged], "quality": [damaged], "leo": [damaged],
             "orbit": [world.folder / "g.sp3"], "clock": [world.folder / "g_int.clk"]}
    with pytest.raises(FormatError, match="damaged.nc.*cannot read the ingest observation "
                                          "file.*delete it and run the step again"):
        ArcData.read(files)
    empty = tmp_path / "empty.nc"
    empty.write_bytes(b"")
    with pytest.raises(FormatError, match="empty.nc"):
        ArcData.read(files | {"obs": [empty]})
