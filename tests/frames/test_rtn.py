"""The RTN frame: one definition in its vectorised and compiled forms.

Authorities: the definition e_R = r/|r|, e_N = (r × v)/|r × v|, e_T = e_N × e_R (Montenbruck &
Gill 2000, sec. 3.7.4) and analytic geometry (a circular orbit, whose along-track axis is the
velocity direction); central finite differences for the partials.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.frames.earth_rotation import itrf_to_gcrf
from leopod.frames.rtn import rtn_axes, rtn_basis, rtn_matrix, rtn_vector_partials


@pytest.fixture
def states():
    rng = np.random.default_rng(20261125)
    pos = rng.normal(0.0, 7.0e6, (50, 3))
    vel = rng.normal(0.0, 7.5e3, (50, 3))
    return pos, vel


def test_circular_orbit_axes_are_radial_velocity_and_angular_momentum():
    # circular orbit in the x-y plane at u = 90°: r along +y, v along -x, h along +z
    m = rtn_matrix(np.array([0.0, 7.0e6, 0.0]), np.array([-7.5e3, 0.0, 0.0]))
    np.testing.assert_allclose(m, [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_axes_are_orthonormal_and_right_handed(states):
    m = rtn_matrix(*states)
    np.testing.assert_allclose(m @ np.swapaxes(m, -1, -2), np.broadcast_to(np.eye(3), m.shape),
                               atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(m), 1.0, atol=1e-14)


def test_compiled_basis_is_the_transpose_of_the_vectorised_matrix(states):
    for pos, vel in zip(*states, strict=True):
        np.testing.assert_allclose(rtn_basis(pos, vel), rtn_matrix(pos, vel).T, rtol=0,
                                   atol=1e-15)


def test_vector_partials_match_finite_differences(states):
    pos, vel = states[0][0], states[1][0]
    vec = np.array([1e-7, -2e-7, 3e-7])
    d_dr, d_dv = rtn_vector_partials(pos, vel, vec)
    h_r, h_v = 1.0, 1e-3
    for j in range(3):
        dr, dv = np.zeros(3), np.zeros(3)
        dr[j], dv[j] = h_r, h_v
        num_r = (rtn_basis(pos + dr, vel) @ vec - rtn_basis(pos - dr, vel) @ vec) / (2 * h_r)
        num_v = (rtn_basis(pos, vel + dv) @ vec - rtn_basis(pos, vel - dv) @ vec) / (2 * h_v)
        np.testing.assert_allclose(d_dr[:, j], num_r, rtol=1e-6, atol=1e-22)
        np.testing.assert_allclose(d_dv[:, j], num_v, rtol=1e-6, atol=1e-22)


def test_itrf_axes_are_the_inertial_axes_expressed_in_the_itrf():
    # an ITRF state rotated to the GCRF: the RTN of the inertial state, rotated back
    times = np.array(["2023-01-01T06:00"], dtype="datetime64[ns]")
    pos = np.array([[6.9e6, 1.0e5, 2.0e5]])
    vel = np.array([[0.0, 1.0e3, 7.5e3]])
    axes = rtn_axes(times, pos, vel, frame="itrf")
    pos_g, vel_g = itrf_to_gcrf(times, pos, vel)
    inertial = rtn_matrix(pos_g, vel_g)
    # rows are unit vectors in the ITRF; rotated to the GCRF they are the inertial axes
    rows_g = np.stack([itrf_to_gcrf(times, axes[0, i][None])[0][0] for i in range(3)])
    np.testing.assert_allclose(rows_g, inertial[0], atol=1e-12)
    assert not np.allclose(axes[0], rtn_matrix(pos, vel)[0], atol=1e-3)   # not Earth-fixed RTN
    with pytest.raises(ValueError, match="frame"):
        rtn_axes(times, pos, vel, frame="ecef")
