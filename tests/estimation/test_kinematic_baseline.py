"""Kinematic baseline from receiver single differences (leopod.estimation.kinematic_baseline).

Authority: analytic truth of a synthetic formation. The leader A's observations are the model
at the truth orbit of a simulated arc plus a clock, one constant per pass and white noise; the
follower B's are the model at the same orbit displaced by a known constant GCRF vector, with its
own clock, pass constants and noise. The estimator must return that vector as the baseline,
the differential clock, and covariances that describe its errors (E[eᵀC⁻¹e] = 3); the true DDs
of the pass constants as constraints must improve it. Index logic (nodes, constraints) against
hand-made rows.
"""

import numpy as np
import pytest
import xarray as xr
from _simulated_arc import at_float_orbit, simulated_arc

from leopod.estimation.float_pod import PodObservations, elevation_sigma
from leopod.estimation.kinematic import KinematicModel, KinematicSettings, solve_kinematic
from leopod.estimation.kinematic_baseline import (
    KinematicBaseline,
    baseline_dataset,
    dd_node_constraints,
    receiver_differences,
)
from leopod.workflow.config import with_defaults

SETTINGS = KinematicSettings.from_config(with_defaults("kinematic", {}))
#: Follower minus leader, GCRF [m]: a few km, as a Lutan-1-like pair (Zhang et al. 2024)
BASELINE_M = np.array([1200.0, -2500.0, 800.0])


@pytest.fixture(scope="module")
def arc(tmp_path_factory):
    return at_float_orbit(simulated_arc(tmp_path_factory.mktemp("arc")))


def _shifted(orbit: xr.Dataset, offset_m) -> xr.Dataset:
    out = orbit.copy(deep=True)
    out["pos_gcrf_m"] = out.pos_gcrf_m + np.asarray(offset_m)
    return out


def _receiver(arc, orbit, clock_m, ambiguity, seed):
    """Observations of a receiver on ``orbit`` (model + clock + pass constant + noise)."""
    p, pod = arc.problem, arc.pod
    po = p.observations
    model, _ = KinematicModel(po, p.products, orbit, p.t_ref, None, p.antennas).model(
        np.zeros((po.times.size, 3)), clock_m)
    rng = np.random.default_rng(seed)
    el = model.el_deg
    code_sigma = elevation_sigma(el, pod.code_sigma_m, pod.weight_elevation_deg)
    phase_sigma = elevation_sigma(el, pod.phase_sigma_m, pod.weight_elevation_deg)
    out = type(po)(**{**po.__dict__})
    out.code_m = np.where(np.isfinite(po.code_m) & model.valid, model.code_m + clock_m[po.epoch]
                          + code_sigma * rng.standard_normal(el.size), np.nan)
    out.phase_m = np.where(np.isfinite(po.phase_m) & model.valid, model.phase_m
                           + clock_m[po.epoch] + ambiguity[np.maximum(po.pass_index, 0)]
                           + phase_sigma * rng.standard_normal(el.size), np.nan)
    out.clk_rx_m = clock_m.copy()
    return out


def _formation(arc):
    po = arc.problem.observations
    m, n_pass = po.times.size, int(po.pass_index.max()) + 1
    rng = np.random.default_rng(7)
    clock_a = 30.0 + rng.normal(scale=0.5, size=m)
    clock_b = clock_a + 12.0 + np.cumsum(rng.normal(scale=0.01, size=m))
    amb_a, amb_b = rng.uniform(-50, 50, n_pass), rng.uniform(-50, 50, n_pass)
    obs_a = _receiver(arc, arc.truth, clock_a, amb_a, seed=11)
    obs_b = _receiver(arc, _shifted(arc.truth, BASELINE_M), clock_b, amb_b, seed=12)
    return obs_a, obs_b, amb_b - amb_a, clock_b - clock_a


def _pair(arc, obs_a, obs_b):
    p = arc.problem
    # A held at its truth, B linearised 0.4 m off its true place
    return KinematicBaseline(obs_a, obs_b, p.products, arc.truth,
                             _shifted(arc.truth, BASELINE_M + [0.3, -0.2, 0.2]), p.t_ref,
                             arc.pod, SETTINGS, antennas_a=p.antennas, antennas_b=p.antennas)


def _errors(result, leader):
    ok = result.solved
    e = result.pos_gcrf_m[ok] - leader[ok, :3] - BASELINE_M
    chi2 = np.einsum("mi,mi->m", e, np.linalg.solve(result.cov_gcrf_m2[ok], e[:, :, None])[..., 0])
    return e, chi2


def _true_dd_table(sd, sd_amb):
    """Every node against the one with most phase rows, with the true values, as the DD table
    of the baseline step would give them (node = (pass_a, pass_b))."""
    counts = np.bincount(sd.obs.pass_index[sd.obs.pass_index >= 0])
    ref = int(np.argmax(counts))
    others = np.flatnonzero((counts > 0) & (np.arange(counts.size) != ref))
    a, b = sd.nodes[:, 0], sd.nodes[:, 1]
    return xr.Dataset({
        "constrained": ("dd", np.ones(others.size, "i1")),
        "system": ("dd", np.full(others.size, "G")),
        "pass_a_i": ("dd", a[others]), "pass_b_i": ("dd", b[others]),
        "pass_a_j": ("dd", np.full(others.size, a[ref])),
        "pass_b_j": ("dd", np.full(others.size, b[ref])),
        "fixed_if_m": ("dd", sd_amb[b[others]] - sd_amb[b[ref]])})


def test_recovers_a_known_baseline_float_and_dd_fixed(arc):
    obs_a, obs_b, sd_amb, clock_diff = _formation(arc)
    pair = _pair(arc, obs_a, obs_b)
    leader = pair.leader_state
    result = pair.solve("G")
    e, chi2 = _errors(result, leader)
    assert result.converged and result.solved.mean() > 0.99
    # float: SD noise sqrt(2) x that of one receiver; the kinematic POD of this arc measures
    # 1.7 cm (tests/estimation/test_kinematic.py), so ~2.4 cm is expected (measured 2.55 cm)
    rms_float = float(np.sqrt(np.mean(np.sum(e**2, axis=1))))
    assert 0.005 < rms_float < 0.04
    assert 0.5 < chi2.mean() / 3 < 1.5
    # the differential clock is the simulated one (code-level, epochs solved)
    ok = result.solved
    assert np.sqrt(np.mean((result.clock_m[ok] - clock_diff[ok]) ** 2)) < 0.1
    # DD-fixed with the true DDs: better, at sqrt(2) x the kinematic fixed orbit of one
    # receiver (1.4 cm there: ~2.0 cm; measured 2.04 cm), still described by its covariance
    fixed = pair.solve("G", _true_dd_table(pair.differences("G"), sd_amb),
                       arc.ar.constraint_sigma_m)
    assert fixed.n_constraints > 20
    e_fixed, chi2_fixed = _errors(fixed, leader)
    rms_fixed = float(np.sqrt(np.mean(np.sum(e_fixed**2, axis=1))))
    assert rms_fixed < rms_float
    assert 0.01 < rms_fixed < 0.03
    assert 0.5 < chi2_fixed.mean() / 3 < 1.5
    # the dataset: baseline = truth vector in ITRF/RTN, sigmas from the covariance
    ds = baseline_dataset(fixed, leader)
    ok = ds.solved.values == 1
    assert np.allclose(np.linalg.norm(ds.baseline_itrf_m.values[ok], axis=1),
                       np.linalg.norm(BASELINE_M), atol=0.05)
    assert np.all(ds.sigma_rtn_m.values[ok] > 0)


def _rows(times, sv, epoch, sat, passes, clock):
    n = len(epoch)
    return PodObservations(times=times, sv=np.array(sv), epoch=np.array(epoch),
                           sat=np.array(sat), code_m=np.arange(n, dtype=float),
                           phase_m=np.arange(n, dtype=float) + 0.5,
                           pass_index=np.array(passes), clk_rx_m=np.array(clock),
                           nl_wavelength_m=0.1)


def test_single_differences_nodes_and_constraints():
    # hand-made rows: A misses epoch 2, tracks G05 (not seen by B) and a C satellite; a slip
    # of B on G02 at epoch 2 ends its pass 1 and starts pass 3
    t = np.datetime64("2022-07-14T00:00", "ns") + np.arange(4) * np.timedelta64(30, "s")
    a = _rows(t[[0, 1, 3]], ["C20", "G02", "G05", "G07"],
              epoch=[0, 0, 0, 1, 1, 2, 2], sat=[1, 3, 2, 1, 3, 1, 0],
              passes=[4, 6, 5, 4, 6, 4, 7], clock=[1.0, 2.0, 4.0])
    b = _rows(t, ["G02", "G07"], epoch=[0, 0, 1, 1, 2, 3, 3], sat=[0, 1, 0, 1, 0, 0, 1],
              passes=[1, 2, 1, 2, 3, 3, 2], clock=[11.0, 12.0, 13.0, 14.0])
    sd = receiver_differences(a, b, "G")
    # common (epoch, satellite): (0,G02) (0,G07) (1,G02) (1,G07) (3,G02); B's epoch 2 has no A
    assert sd.rows_b.tolist() == [0, 1, 2, 3, 5]
    assert sd.rows_a.tolist() == [0, 1, 3, 4, 5]
    assert np.allclose(sd.obs.code_m, b.code_m[sd.rows_b] - a.code_m[sd.rows_a])
    nodes = {tuple(n) for n in sd.nodes.tolist()}
    assert nodes == {(4, 1), (6, 2), (4, 3)}
    node = [tuple(sd.nodes[k]) for k in sd.obs.pass_index]
    assert node == [(4, 1), (6, 2), (4, 1), (6, 2), (4, 3)]
    # differential a-priori clocks on B's epochs (0 where A has no epoch)
    assert np.allclose(sd.obs.clk_rx_m, [10.0, 10.0, 13.0, 10.0])
    table = xr.Dataset({
        "constrained": ("dd", [1, 1, 0, 1]), "system": ("dd", ["G", "G", "G", "C"]),
        "pass_a_i": ("dd", [6, 4, 6, 4]), "pass_b_i": ("dd", [2, 3, 2, 3]),
        "pass_a_j": ("dd", [4, 9, 4, 4]), "pass_b_j": ("dd", [1, 9, 1, 1]),
        "fixed_if_m": ("dd", [0.25, 1.0, 2.0, 3.0])})
    ni, nj, value, sigma = dd_node_constraints(table, sd.nodes, "G", 1e-3)
    # the second DD has a node not present here, the third is not constrained, the fourth
    # is of another system
    assert [tuple(sd.nodes[i]) for i in ni] == [(6, 2)]
    assert [tuple(sd.nodes[j]) for j in nj] == [(4, 1)]
    assert value.tolist() == [0.25] and sigma.tolist() == [1e-3]


def test_inter_system_code_bias_of_a_combined_solution(arc):
    # analytic truth: the satellites with an odd PRN relabelled as a second system "C" whose
    # code carries a bias of 2.75 m (the size of the simulated LT-1 B − A one); the rows'
    # model stays that of their real satellites. The solution must return the bias and the
    # positions of the bias-free single-system solution.
    p, pod = arc.problem, arc.pod
    obs, _ = _receiver_pair_rows(arc)
    lin = KinematicModel(p.observations, p.products, arc.truth, p.t_ref, None, p.antennas)
    two = type(obs)(**{**obs.__dict__})
    odd = np.array([int(s[1:]) % 2 == 1 for s in obs.sv])
    two.sv = np.array([("C" if o else "G") + s[1:] for s, o in zip(obs.sv, odd)])
    two.systems = ("G", "C")
    biased = odd[obs.sat] & np.isfinite(obs.code_m)
    two.code_m = np.where(biased, obs.code_m + 2.75, obs.code_m)
    clock0 = np.asarray(obs.clk_rx_m, dtype=float)
    one = solve_kinematic(obs, lin.model, lin.reference_at, clock0, pod, SETTINGS)
    both = solve_kinematic(two, lin.model, lin.reference_at, clock0, pod, SETTINGS)
    assert one.isb_m.size == 0 and both.isb_m.size == 1
    # the bias rests on thousands of code rows of 0.3 m, whose epochs share it with the
    # clock: mm to cm (measured 2.7564 m; positions within 0.7 mm of the one-system solution)
    assert abs(both.isb_m[0] - 2.75) < 0.01
    ok = one.solved & both.solved
    assert ok.mean() > 0.99
    assert np.max(np.abs(both.pos_gcrf_m[ok] - one.pos_gcrf_m[ok])) < 0.005


def _receiver_pair_rows(arc):
    """One receiver's synthetic rows (model at the truth + clock + pass constants + noise)."""
    po = arc.problem.observations
    rng = np.random.default_rng(5)
    clock = 20.0 + rng.normal(scale=0.5, size=po.times.size)
    amb = rng.uniform(-50, 50, int(po.pass_index.max()) + 1)
    return _receiver(arc, arc.truth, clock, amb, seed=21), amb
