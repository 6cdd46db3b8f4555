"""The direct-method PCV (leopod.antenna.pcv_direct): reduction, datum and recovery.

Authorities: linear algebra (the Schur complement of a partitioned system gives the same
solution for the kept unknowns as the full system); the observation equations of the direct
method (Wang et al. 2024, eqs. 7-11: bilinear node weights, one receiver clock per epoch, a
PCO-Z along body +Z) evaluated on synthetic directions with a known pattern - noise-free data
must give back the pattern exactly once the datum conditions hold for it, and the constant
(clock) is an exact null direction of the normal matrix.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import xarray as xr

from leopod.antenna.pcv import PcvSettings, apriori_pattern, estimated_pattern, pco_shift_neu
from leopod.antenna.pcv_direct import datum_conditions, reduce_normals, solve_normals
from leopod.codebias.grid import AntennaGrid
from leopod.gnss.leo_antenna import LeoAntenna
from leopod.workflow.config import with_defaults


def test_schur_complement_gives_the_kept_part_of_the_full_solution():
    rng = np.random.default_rng(1)
    h = rng.normal(size=(60, 12))
    n, b = h.T @ h, h.T @ rng.normal(size=60)
    full = np.linalg.solve(n, b)
    matrix, rhs = reduce_normals(n, b, 4)
    np.testing.assert_allclose(np.linalg.solve(matrix, rhs), full[-4:], rtol=1e-10)
    # its inverse is the kept block of the full inverse
    np.testing.assert_allclose(np.linalg.inv(matrix), np.linalg.inv(n)[-4:, -4:], rtol=1e-9)


def _day(grid: AntennaGrid, pattern: np.ndarray, pco_z_m: float, *, pco_z: bool, seed=0,
         epochs=3000, per_epoch=8):
    """Day normal equations of noise-free IF observations of ``pattern`` (node values [m])
    and a PCO-Z error: rows of bilinear weights (and the PCO-Z partial cos z, antenna
    boresight = body −Z, here interpolated from the nodes, so that (δ = 1, p = −cos z) is an
    exact null direction as the constant is), one free clock per epoch eliminated (projection
    onto the complement of the epoch means), a constant horizontal receiver offset (the part
    of an orbit that a horizontal antenna offset mimics: partials cos e cos α, cos e sin α,
    interpolated from the nodes, exact null directions too) reduced out as the arc
    parameters are, weights 1/(5 mm)²."""
    rng = np.random.default_rng(seed)
    n = epochs * per_epoch
    az = rng.uniform(0.0, 360.0, n)
    el = np.degrees(np.arcsin(rng.uniform(0.0, 1.0, n)))
    epoch = np.repeat(np.arange(epochs), per_epoch)
    a = grid.design(az, el).toarray()
    node_az, node_el = (np.radians(v) for v in grid.node_directions())
    cos_z = a @ np.sin(node_el)
    offset = a @ np.column_stack([np.cos(node_el) * np.cos(node_az),
                                  np.cos(node_el) * np.sin(node_az)])
    if pco_z:
        a = np.column_stack([a, cos_z])
    a = np.column_stack([offset, a])
    clock = rng.normal(0.0, 100.0, epochs)
    l = grid.design(az, el) @ pattern + pco_z_m * cos_z + clock[epoch]
    # eliminate the clocks: every column and the observations minus their epoch mean
    mean = sp.csr_matrix((np.full(n, 1.0 / per_epoch), (epoch, np.arange(n))),
                         shape=(epochs, n))
    a_c = a - (mean @ a)[epoch]
    l_c = l - (mean @ l)[epoch]
    w = 1.0 / 0.005**2
    node = grid.nearest(az, el)
    k = a.shape[1] - 2
    matrix, rhs = reduce_normals(w * a_c.T @ a_c, w * a_c.T @ l_c, k)
    return xr.Dataset(
        {"normal_matrix": (("parameter", "parameter_2"), matrix),
         "rhs": ("parameter", rhs),
         "count": ("node", np.bincount(node, minlength=grid.n_nodes))},
        coords={"parameter": np.arange(k), "parameter_2": np.arange(k)},
        attrs={"az_step_deg": grid.az_step_deg, "zenith_step_deg": grid.el_step_deg,
               "pco_z": int(pco_z), "pod_pco_z": 0, "vtpv": 0.0, "dof": n - epochs - k,
               "n_rows": n, "date": "synthetic"})


def _pattern(grid: AntennaGrid) -> np.ndarray:
    """A ±1 cm pattern on the nodes (cross-track asymmetry and an elevation term) [m]."""
    az, el = (np.radians(v) for v in grid.node_directions())
    return 0.01 * np.sin(az) * np.cos(el) + 0.004 * np.cos(2 * (np.pi / 2 - el)) \
        + 0.002 * np.cos(3 * az) * np.sin(2 * el)


@pytest.mark.parametrize("pco_z", [False, True])
def test_noise_free_pattern_and_pco_z_are_recovered_under_the_datum(pco_z):
    grid = AntennaGrid(30.0, 15.0)
    truth = _pattern(grid)
    day = _day(grid, truth, 0.012 if pco_z else 0.0, pco_z=pco_z)
    n = day.normal_matrix.values
    # the constant is an exact null direction (clock), and with a PCO-Z so is
    # (δ = 1, p = -cos z) (the synthetic rows use the node cos z)
    one = np.r_[np.ones(grid.n_nodes), np.zeros(int(pco_z))]
    assert np.linalg.norm(n @ one) < 1e-9 * np.linalg.norm(n)
    if pco_z:
        v = np.r_[-np.sin(np.radians(grid.node_directions()[1])), 1.0]
        assert np.linalg.norm(n @ v) < 1e-9 * np.linalg.norm(n)
    # the horizontal-offset patterns, taken by the reduced receiver offset
    az, el = (np.radians(v) for v in grid.node_directions())
    for term in (np.cos(el) * np.cos(az), np.cos(el) * np.sin(az)):
        v = np.r_[term, np.zeros(int(pco_z))]
        assert np.linalg.norm(n @ v) < 1e-9 * np.linalg.norm(n) * np.linalg.norm(v)
    settings = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": 30.0, "zenith_step_deg": 15.0, "min_count": 30, "method": "direct",
        "estimate_pco_z": pco_z}))
    # the truth with the datum's part moved out: the mean, the horizontal-offset terms
    # (no_horizontal_offset, the default) and with a PCO-Z the cos z-like term (into it)
    assert settings.no_horizontal_offset
    well = day["count"].values >= 30
    assert well.all()
    c = datum_conditions(grid, well, "mean", pco_z, grid.n_nodes + int(pco_z),
                         horizontal=settings.no_horizontal_offset)
    az, el = (np.radians(v) for v in grid.node_directions())
    basis = np.column_stack([np.ones(grid.n_nodes)] + ([np.sin(el)] if pco_z else [])
                            + [np.cos(el) * np.cos(az), np.cos(el) * np.sin(az)])
    coef = np.linalg.solve(c[:, :grid.n_nodes] @ basis, c[:, :grid.n_nodes] @ truth)
    expected = truth - basis @ coef
    est = solve_normals([day], settings)
    got = grid.from_grid(est.pcv_if_m.values.T[::-1])
    # the weak pull (σ 5 cm) against ~100 observations of σ 5 mm per node: < 1e-5 relative
    np.testing.assert_allclose(got, expected, atol=2e-6)
    if pco_z:
        # the PCO-Z takes the cos z-like part of the pattern: δ_est = δ + coef_cos z
        assert est.attrs["pco_z_m"] == pytest.approx(0.012 + coef[1], abs=2e-6)
    else:
        assert np.isnan(est.attrs["pco_z_m"])


def test_unobserved_nodes_and_grid_mismatch_are_handled():
    grid = AntennaGrid(30.0, 15.0)
    day = _day(grid, _pattern(grid), 0.0, pco_z=False, epochs=1000, per_epoch=3)
    settings = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": 30.0, "zenith_step_deg": 15.0, "min_count": 30, "method": "direct"}))
    est = solve_normals([day], settings)
    few = est["count"].values < 30
    assert few.any() and np.isnan(est.pcv_if_m.values[few]).all()
    assert np.isfinite(est.pcv_if_m.values[~few]).all()
    other = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": 10.0, "zenith_step_deg": 10.0, "method": "direct"}))
    with pytest.raises(ValueError, match="grid"):
        solve_normals([day], other)
    with pytest.raises(ValueError, match="needs pcv.method: direct"):
        PcvSettings.from_config(with_defaults("pcv", {"estimate_pco_z": True}))


def test_the_pco_z_correction_enters_the_antex_pco_in_the_antenna_frame():
    """A PCO-Z correction along body +Z is −δ in Up of the default antenna frame (north +X,
    up −Z, leopod.gnss.leo_antenna) and +δ in North of an antenna whose north is body +Z; the
    written pattern's PCO moves by it on every frequency."""
    table = {"L1": [0.1, 0.0, -0.5], "L2": [0.1, 0.0, -0.48]}
    grid = AntennaGrid(30.0, 15.0)
    day = _day(grid, _pattern(grid), 0.004, pco_z=True, epochs=1000)
    settings = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": 30.0, "zenith_step_deg": 15.0, "min_count": 30, "method": "direct",
        "estimate_pco_z": True}))
    est = solve_normals(iter([day]), settings)
    dz = est.attrs["pco_z_m"]
    np.testing.assert_allclose(pco_shift_neu(table, est), [0.0, 0.0, -dz], atol=1e-15)
    pattern, _ = apriori_pattern(table)
    sideways = LeoAntenna(pattern, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0))
    np.testing.assert_allclose(pco_shift_neu(sideways, est), [dz, 0.0, 0.0], atol=1e-15)
    new = estimated_pattern(pattern, est, pco_shift_neu_m=pco_shift_neu(table, est))
    for f in pattern.frequencies:
        np.testing.assert_allclose(new.pco_m(f) - pattern.pco_m(f), [0.0, 0.0, -dz])
    assert new.meta["calibration_method"] == "DIRECT"
