"""Antenna grid: node layout of Peng et al. (2021) and bilinear interpolation (Wang et al. 2024,
eqs. 7-9)."""

import numpy as np
import pytest

from leopod.codebias.grid import AntennaGrid


def test_five_degree_grid_has_the_1297_parameters_of_peng2021():
    # Peng et al. (2021) sec. II: "5° x 5° resolution, so there were 1297 grid points"
    g = AntennaGrid(5.0, 5.0)
    assert g.n_nodes == 1297
    assert g.elevation_deg[-1] == 90.0 and g.azimuth_deg[-1] == 355.0


def test_steps_must_divide_the_sphere():
    with pytest.raises(ValueError, match="does not divide"):
        AntennaGrid(7.0, 5.0)


def test_bilinear_interpolation_is_exact_for_bilinear_functions():
    # analytic truth: inside a cell, bilinear interpolation reproduces a + b u + c t + d u t
    g = AntennaGrid(5.0, 5.0)
    rng = np.random.default_rng(1)
    az = rng.uniform(0, 360, 500)
    el = rng.uniform(0, 84.9, 500)
    _, w = g.weights(az, el)
    assert np.allclose(w.sum(axis=1), 1.0)
    assert (w >= 0).all()
    # a function linear in elevation only is reproduced everywhere (rings are exact)
    _, node_el = g.node_directions()
    assert np.allclose(g.interpolate(3.0 + 0.02 * node_el, az, el), 3.0 + 0.02 * el)


def test_azimuth_wraps_and_zenith_is_one_node():
    g = AntennaGrid(5.0, 5.0)
    values = np.zeros(g.n_nodes)
    values[0] = 1.0  # ring 0, azimuth 0
    # 357.5 deg lies half-way between the nodes at 355 and 0 (=360) deg
    assert g.interpolate(values, [357.5], [0.0])[0] == pytest.approx(0.5)
    values[:] = 0.0
    values[-1] = 2.0  # zenith
    # from the highest ring (85 deg) linearly to the zenith, at any azimuth
    assert np.allclose(g.interpolate(values, [0.0, 123.0, 250.0], [87.5] * 3), 1.0)
    assert g.interpolate(values, [10.0], [90.0])[0] == pytest.approx(2.0)


def test_below_horizon_is_evaluated_at_zero_and_nan_nodes_propagate():
    g = AntennaGrid(10.0, 10.0)
    v = np.arange(g.n_nodes, dtype=float)
    assert g.interpolate(v, [20.0], [-5.0])[0] == g.interpolate(v, [20.0], [0.0])[0]
    v[1] = np.nan  # ring 0, azimuth 10
    out = g.interpolate(v, [5.0, 25.0, 10.0], [0.0, 0.0, 0.0])
    assert np.isnan(out[0]) and np.isfinite(out[1])
    assert np.isnan(out[2])  # weight 1 on the NaN node
    assert np.isnan(g.interpolate(v, [np.nan, 20.0], [10.0, np.nan])).all()  # no direction


def test_node_directions_are_the_nodes():
    # analytic truth: interpolating a one-hot node vector at that node's direction gives 1
    g = AntennaGrid(10.0, 10.0)
    az, el = g.node_directions()
    eye = np.eye(g.n_nodes)
    for k in (0, 5, g.n_az + 3, g.n_nodes - 2, g.n_nodes - 1):
        values = g.interpolate(eye[k], az, el)
        assert values[k] == pytest.approx(1.0) and np.sum(values) == pytest.approx(1.0)


def test_grid_round_trip_and_neighbours():
    g = AntennaGrid(5.0, 5.0)
    v = np.arange(g.n_nodes, dtype=float)
    grid = g.to_grid(v)
    assert grid.shape == (19, 72)
    assert (grid[-1] == v[-1]).all()
    assert np.array_equal(g.from_grid(grid), v)
    pairs = g.neighbour_pairs()
    # 18 rings x 72 along-ring + 17 x 72 between rings + 72 to the zenith
    assert pairs.shape == (18 * 72 + 17 * 72 + 72, 2)
    design = g.design([12.5], [33.0]).toarray()
    assert design.sum() == pytest.approx(1.0) and (design > 0).sum() == 4
