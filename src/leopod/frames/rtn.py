"""The RTN frame of an orbit: radial, along-track (transverse), cross-track (normal) axes.

One definition for the whole package: ``e_R = r/|r|``, ``e_N = (r × v)/|r × v|``,
``e_T = e_N × e_R`` (Montenbruck & Gill 2000, sec. 3.7.4), computed from an *inertial*
velocity. Three entry points share it:

- :func:`rtn_matrix`, vectorised numpy, rows R, T, N (``x_rtn = M @ x``);
- :func:`rtn_basis` and :func:`rtn_vector_partials`, compiled (numba) for the force model and
  the integrator, columns R, T, N (``x = M @ x_rtn``, the transpose) and the partials of a
  vector of fixed RTN components w.r.t. position and velocity;
- :func:`rtn_axes`, the inertial RTN axes of Earth-fixed (ITRF) or GCRF states, expressed in
  the frame of the states, for orbit comparisons.

``tests/frames/test_rtn.py`` checks that the compiled and vectorised forms agree.
"""

from __future__ import annotations

import numba
import numpy as np

from leopod.frames.earth_rotation import gcrf_from_itrf_matrices

__all__ = ["RTN_AXES", "rtn_axes", "rtn_basis", "rtn_matrix", "rtn_vector_partials"]


def rtn_matrix(pos_m, vel_m_s) -> np.ndarray:
    """Rotation from GCRF to the RTN frame of the state(s).

    Parameters
    ----------
    pos_m, vel_m_s : array_like, shape (..., 3)
        Position [m] and velocity [m/s] (any inertial or Earth-fixed frame; the RTN axes are
        expressed in it).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Rows R, T, N (unit vectors): ``x_rtn = M @ x``.
    """
    r = np.asarray(pos_m, dtype=float)
    v = np.asarray(vel_m_s, dtype=float)
    e_r = r / np.linalg.norm(r, axis=-1, keepdims=True)
    h = np.cross(r, v)
    e_n = h / np.linalg.norm(h, axis=-1, keepdims=True)
    e_t = np.cross(e_n, e_r)
    return np.stack([e_r, e_t, e_n], axis=-2)


# --------------------------------------------------------------------------- axes and Helmert
def rtn_axes(times, pos_m, vel_m_s, *, frame: str = "itrf", eop=None) -> np.ndarray:
    """Inertial RTN axes of states, expressed in the frame of the states.

    For ITRF states the state is first rotated to the GCRF (``r_g = Q R W r``, ``v_g = Q R W v
    + d(QRW)/dt r``, IERS Conventions 2010 eq. 5.1, :func:`gcrf_from_itrf_matrices`); the
    radial axis is ``r/|r|``, cross-track ``r × v_g`` normalised, along-track completes the
    right-handed triad (:func:`leopod.frames.rtn.rtn_matrix`).

    Parameters
    ----------
    times : array_like of datetime64, shape (n,)
        GPS-time epochs (used for ``frame="itrf"``).
    pos_m, vel_m_s : array_like, shape (n, 3)
        Position [m] and velocity [m/s] in ``frame``.
    frame : {"itrf", "gcrf"}
    eop : EarthOrientation, optional
        EOP source for the ITRF → GCRF rotation (default: installed IERS data).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Rows R, T, N: ``d_rtn = M @ d`` for a difference vector ``d`` in ``frame``.
    """
    pos = np.asarray(pos_m, dtype=float)
    vel = np.asarray(vel_m_s, dtype=float)
    if frame == "gcrf":
        return rtn_matrix(pos, vel)
    if frame != "itrf":
        raise ValueError(f"frame must be 'itrf' or 'gcrf', not {frame!r}")
    rot, d_rot = gcrf_from_itrf_matrices(times, eop)
    pos_g = np.einsum("nij,nj->ni", rot, pos)
    vel_g = np.einsum("nij,nj->ni", rot, vel) + np.einsum("nij,nj->ni", d_rot, pos)
    return rtn_matrix(pos_g, vel_g) @ rot


#: Axis letters of the RTN frame, in the order of the columns of :func:`rtn_basis`.
RTN_AXES = ("R", "T", "N")


def rtn_basis(pos_m: np.ndarray, vel_m_s: np.ndarray) -> np.ndarray:
    """RTN unit vectors of a state, as the columns of a rotation matrix.

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (3,)
        Position [m] and velocity [m/s] in an inertial frame.

    Returns
    -------
    ndarray, shape (3, 3)
        Columns ``e_R``, ``e_T``, ``e_N``: ``x = M @ x_rtn``.
    """
    basis = np.empty((3, 3))
    _rtn_basis(np.ascontiguousarray(pos_m, dtype=float),
               np.ascontiguousarray(vel_m_s, dtype=float), basis)
    return basis


@numba.njit(cache=True)
def _unit_vectors(pos, vel, e_r, e_t, e_n):  # pragma: no cover - numba
    """RTN unit vectors into e_r, e_t, e_n; returns |r| and |r × v|."""
    h0 = pos[1] * vel[2] - pos[2] * vel[1]
    h1 = pos[2] * vel[0] - pos[0] * vel[2]
    h2 = pos[0] * vel[1] - pos[1] * vel[0]
    r = np.sqrt(pos[0] ** 2 + pos[1] ** 2 + pos[2] ** 2)
    hn = np.sqrt(h0 * h0 + h1 * h1 + h2 * h2)
    for i in range(3):
        e_r[i] = pos[i] / r
    e_n[0], e_n[1], e_n[2] = h0 / hn, h1 / hn, h2 / hn
    e_t[0] = e_n[1] * e_r[2] - e_n[2] * e_r[1]
    e_t[1] = e_n[2] * e_r[0] - e_n[0] * e_r[2]
    e_t[2] = e_n[0] * e_r[1] - e_n[1] * e_r[0]
    return r, hn


@numba.njit(cache=True)
def _rtn_basis(pos, vel, out):  # pragma: no cover - numba
    e_r, e_t, e_n = np.empty(3), np.empty(3), np.empty(3)
    _unit_vectors(pos, vel, e_r, e_t, e_n)
    for i in range(3):
        out[i, 0] = e_r[i]
        out[i, 1] = e_t[i]
        out[i, 2] = e_n[i]


@numba.njit(cache=True)
def _skew_times(x, m, out):  # pragma: no cover - numba
    """``out = [x]× m`` for a 3×3 matrix m (``[x]× y = x × y``)."""
    for j in range(3):
        out[0, j] = x[1] * m[2, j] - x[2] * m[1, j]
        out[1, j] = x[2] * m[0, j] - x[0] * m[2, j]
        out[2, j] = x[0] * m[1, j] - x[1] * m[0, j]


@numba.njit(cache=True)
def _skew_element(x, i, j):  # pragma: no cover - numba
    """Element (i, j) of ``[x]×``."""
    if i == j:
        return 0.0
    if i == 0:
        return -x[2] if j == 1 else x[1]
    if i == 1:
        return x[2] if j == 0 else -x[0]
    return -x[1] if j == 0 else x[0]


@numba.njit(cache=True)
def _rtn_partials(pos, vel, vec, d_dr, d_dv):  # pragma: no cover - numba
    e_r, e_t, e_n = np.empty(3), np.empty(3), np.empty(3)
    r, hn = _unit_vectors(pos, vel, e_r, e_t, e_n)
    der_dr = np.empty((3, 3))
    den_dr = np.empty((3, 3))
    den_dv = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            delta = 1.0 if i == j else 0.0
            der_dr[i, j] = (delta - e_r[i] * e_r[j]) / r
            # ∂e_N/∂r = (I − e_N e_Nᵀ)/|h| (−[v]×), ∂e_N/∂v = (I − e_N e_Nᵀ)/|h| [r]×
            p_ij = 0.0
            q_ij = 0.0
            for k in range(3):
                proj = ((1.0 if i == k else 0.0) - e_n[i] * e_n[k]) / hn
                p_ij -= proj * _skew_element(vel, k, j)
                q_ij += proj * _skew_element(pos, k, j)
            den_dr[i, j] = p_ij
            den_dv[i, j] = q_ij
    a = np.empty((3, 3))
    b = np.empty((3, 3))
    _skew_times(e_n, der_dr, a)
    _skew_times(e_r, den_dr, b)
    det_dr = a - b
    _skew_times(e_r, den_dv, b)
    for i in range(3):
        for j in range(3):
            d_dr[i, j] = vec[0] * der_dr[i, j] + vec[1] * det_dr[i, j] + vec[2] * den_dr[i, j]
            d_dv[i, j] = -vec[1] * b[i, j] + vec[2] * den_dv[i, j]


def rtn_vector_partials(pos_m: np.ndarray, vel_m_s: np.ndarray,
                        vec_rtn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Partials of ``x = M(r, v) @ x_rtn`` (fixed RTN components) w.r.t. position and velocity.

    From ``∂e_R/∂r = (I − e_R e_Rᵀ)/|r|``; with ``h = r × v``: ``∂h/∂r = −[v]×``,
    ``∂h/∂v = [r]×``, ``∂e_N/∂h = (I − e_N e_Nᵀ)/|h|``; and
    ``∂e_T = [e_N]× ∂e_R − [e_R]× ∂e_N`` (product rule on ``e_T = e_N × e_R``).

    Parameters
    ----------
    pos_m, vel_m_s : ndarray, shape (3,)
        Position [m] and velocity [m/s].
    vec_rtn : ndarray, shape (3,)
        RTN components of the vector (any unit u).

    Returns
    -------
    dx_dr : ndarray, shape (3, 3)
        ``∂x/∂r`` [u/m].
    dx_dv : ndarray, shape (3, 3)
        ``∂x/∂v`` [u/(m/s)].
    """
    d_dr = np.empty((3, 3))
    d_dv = np.empty((3, 3))
    _rtn_partials(np.ascontiguousarray(pos_m, dtype=float),
                  np.ascontiguousarray(vel_m_s, dtype=float),
                  np.ascontiguousarray(vec_rtn, dtype=float), d_dr, d_dv)
    return d_dr, d_dv
