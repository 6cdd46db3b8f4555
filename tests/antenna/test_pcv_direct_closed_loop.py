"""Closed loop of the direct-method PCV (leopod.antenna.pcv_direct) on a simulated arc.

Authority: the simulation truth - orbit and the real AIUB GOCE pattern
(../shared/data/antex/GOCE_MAIN_0001.ATX, Jäggi et al. 2009) with which the observations were
simulated; the fixed POD runs without any PCV (tests/antenna/_pcv_fixed.py). The null
directions are derived in leopod.antenna.pcv_direct: the constant (receiver clock) exactly,
(PCO-Z = 1, PCV = −cos z) up to the bilinear interpolation of cos z; and the physics of a
reduced-dynamic orbit: a horizontal offset of the phase centre in the body frame (PCV patterns
cos e cos α, along-track, and cos e sin α, cross-track) is nearly an orbit offset.

Measured here (fixed POD of 1-5 h, 10° x 10°, 288 nodes with >= 5 phase observations, datum
mean and no horizontal-offset terms): orbit 3D RMS against the truth no PCV 27.6 mm, true PCV
15.3 mm, direct map 18.7 mm (with PCO-Z 18.9 mm, PCO-Z -6.8 mm); phase RMS 10.9, 7.8, 9.3 mm;
map RMS against the truth 9.3 mm, 0.81 times its formal sigmas. Scaled smallest eigenvalues of
the reduced normal matrix: 1e-15 (constant), 6e-6 (along-track offset), 1.5e-4 (cross-track
offset), then 0.08. A 4-h arc cannot meet the issue's criteria (whole days:
benchmarks/pcv_table.py). About 65 s on one core.
"""

from __future__ import annotations

import numpy as np
import pytest
from _pcv_fixed import (
    direct_map,
    fixed_pod_arc,
    goce_day,
    map_truth_rms_m,
    orbit_rms_rtn_m,
    pcv_settings,
    true_map,
)
from _simulated_arc import GOCE  # tests/estimation, on the path through _pcv_fixed

from leopod.antenna.pcv import estimated_antenna
from leopod.antenna.pcv_direct import arc_normals, day_normals

pytestmark = pytest.mark.skipif(not GOCE.exists(), reason="needs ../shared/data/antex")

HOURS = (1.0, 5.0)
#: Phase observations of a node in the map: a 4-h arc has ~13 per node on average.
MIN_COUNT = 5


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    world = goce_day(tmp_path_factory.mktemp("pcv_direct"))
    none = fixed_pod_arc(world, world.pco_only, HOURS)
    true = fixed_pod_arc(world, world.antenna, HOURS)
    out = {"world": world, "none": none, "orbit": {}, "phase": {}, "maps": {}, "neq": {}}
    for name, pod in (("none", none), ("true", true)):
        out["orbit"][name] = orbit_rms_rtn_m(pod.fixed.arc.orbit, world.truth_day)["3D"]
        out["phase"][name] = _phase_rms_m(pod)
    for pco_z in (False, True):
        settings = pcv_settings(10.0, MIN_COUNT, method="direct", estimate_pco_z=pco_z)
        est, neq = direct_map(none, settings)
        after = fixed_pod_arc(world, estimated_antenna(world.pco_only, est), HOURS)
        out["orbit"][pco_z] = orbit_rms_rtn_m(after.fixed.arc.orbit, world.truth_day)["3D"]
        out["phase"][pco_z] = _phase_rms_m(after)
        out["maps"][pco_z], out["neq"][pco_z] = est, neq
        out[f"settings_{pco_z}"] = settings
    return out


def _phase_rms_m(pod) -> float:
    """RMS of the used phase residuals of a fixed POD [m]."""
    res = pod.fixed.arc.residuals
    used = np.isfinite(res.phase_residual_m.values) & (res.phase_rejected.values == 0)
    return float(np.sqrt(np.mean(res.phase_residual_m.values[used] ** 2)))


def _scaled_eigen(neq, n_nodes):
    n = neq.normal_matrix.values
    keep = np.r_[np.flatnonzero(np.diag(n)[:n_nodes] > 0), np.arange(n_nodes, n.shape[0])]
    sub = n[np.ix_(keep, keep)]
    d = np.sqrt(np.diag(sub))
    w, v = np.linalg.eigh(sub / np.outer(d, d))
    return keep, d, w, v


def test_the_clock_and_pco_z_directions_are_the_null_space(loop):
    grid = loop["settings_False"].grid
    n = loop["neq"][False].normal_matrix.values
    observed = (np.diag(n) > 0).astype(float)
    # constant on every observed node: taken by the epoch clocks exactly
    assert np.linalg.norm(n @ observed) < 1e-12 * np.linalg.norm(n, 2) * np.linalg.norm(observed)
    n = loop["neq"][True].normal_matrix.values
    observed = np.diag(n)[:grid.n_nodes] > 0
    cos_z = np.sin(np.radians(grid.node_directions()[1]))
    ratio = {}
    for sign in (1.0, -1.0):        # PCO-Z = 1 (body +Z, towards nadir) with PCV = ±cos z
        v = np.r_[np.where(observed, sign * cos_z, 0.0), 1.0]
        ratio[sign] = np.linalg.norm(n @ v) / np.linalg.norm(n, 2) / np.linalg.norm(v)
    print(f"\n|N v| / |N||v|: PCV +cos z {ratio[1.0]:.2e}, -cos z {ratio[-1.0]:.2e}")
    # -cos z: zero up to the interpolation error of cos z (≤ Δz²/8 = 0.4 %); +cos z: not
    assert ratio[-1.0] < 4e-3 * ratio[1.0]


def test_the_next_weakest_directions_are_horizontal_antenna_offsets(loop):
    grid = loop["settings_False"].grid
    keep, d, w, v = _scaled_eigen(loop["neq"][False], grid.n_nodes)
    az, el = (np.radians(x)[keep] for x in grid.node_directions())
    basis = np.column_stack([np.ones(keep.size), np.cos(el) * np.cos(az),
                             np.cos(el) * np.sin(az)])
    print("\nsmallest scaled eigenvalues: " + ", ".join(f"{x:.1e}" for x in w[:4]))
    assert w[0] < 1e-12 and w[3] > 100 * w[2]
    for i, column in ((1, 1), (2, 2)):
        vec = v[:, i] / d
        fit = basis[:, [column]] @ np.linalg.lstsq(basis[:, [column]], vec, rcond=None)[0]
        assert np.sum(fit**2) / np.sum(vec**2) > 0.99


def test_the_map_is_within_its_formal_sigmas_of_the_truth(loop):
    est, settings = loop["maps"][False], loop["settings_False"]
    truth = true_map(loop["world"], loop["none"].fixed.arc.residuals, settings)
    well = np.isfinite(est.pcv_if_m.values)
    d = est.pcv_if_m.values[well] - truth.pcv_if_m.values[well]
    z = (d - d.mean()) / est.sigma_m.values[well]
    rms = map_truth_rms_m(loop["world"], est, loop["none"].fixed.arc.residuals, settings)
    print(f"\nmap RMS vs truth {rms * 1e3:.2f} mm, normalised RMS {np.sqrt(np.mean(z**2)):.2f}, "
          f"sigma0 {est.attrs['sigma0']:.3f}, nodes {int(well.sum())}")
    assert 0.3 < np.sqrt(np.mean(z**2)) < 3.0


def test_the_estimated_map_takes_the_pattern_out_of_the_residuals(loop):
    """The map applied through its ANTEX file (sign of the partials, ANTEX round trip):
    the phase residuals of the fixed POD shrink towards those with the true pattern."""
    phase, orbit = loop["phase"], loop["orbit"]
    print("\nfixed POD phase RMS [mm]: " + ", ".join(f"{k} {v * 1e3:.2f}"
                                                   for k, v in phase.items())
          + "; orbit 3D RMS vs truth [mm]: " + ", ".join(f"{k} {v * 1e3:.2f}"
                                                        for k, v in orbit.items())
          + f"; PCO-Z {loop['maps'][True].attrs['pco_z_m'] * 1e3:.2f} mm")
    assert orbit["true"] < orbit["none"] - 5e-3
    for case in (False, True):
        assert phase[case] < phase["none"] - 0.3 * (phase["none"] - phase["true"])
        assert orbit[case] < orbit["none"] - 5e-3


def test_the_float_path_gives_the_normal_equations_of_the_float_system(loop):
    """pcv.solution float_pod (no ambiguity table): arc_normals linearises at the float
    solution without constraints - the same normal equations as day_normals of the fixed
    POD's system without its constraints."""
    none, settings = loop["none"], loop["settings_False"]
    neq = arc_normals(*none.args, none.start, settings, satellite="x", limits=none.limits)
    ref = day_normals(none.fixed.pod, settings.grid, sigma0=1.0)
    assert neq.attrs["solution"] == "float_pod" and neq.attrs["n_ambiguity_constraints"] == 0
    np.testing.assert_allclose(neq.normal_matrix.values, ref.normal_matrix.values,
                               rtol=1e-9, atol=1e-9 * np.abs(ref.normal_matrix.values).max())
    fixed = loop["neq"][False]
    assert fixed.attrs["n_ambiguity_constraints"] > 0
    assert not np.allclose(fixed.normal_matrix.values, ref.normal_matrix.values)


@pytest.mark.xfail(strict=True, reason="issue 22 criterion not met on a 4-h arc: the map is "
                   "~9 mm RMS from the truth (within its formal sigmas: noise), the orbit ~3 mm "
                   "worse than with the truth (whole days: benchmarks/pcv_table.py)")
def test_the_issue_criteria(loop):
    rms = map_truth_rms_m(loop["world"], loop["maps"][False],
                          loop["none"].fixed.arc.residuals, loop["settings_False"])
    assert rms < 1e-3
    assert loop["orbit"][False] < loop["orbit"]["true"] + 1e-3
