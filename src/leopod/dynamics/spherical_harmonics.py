"""Spherical-harmonic sums of the gravity field: potential, acceleration and its gradient.

Potential of a field with fully normalised coefficients ``C̄nm``, ``S̄nm`` (Heiskanen & Moritz
1967; Montenbruck & Gill 2000, eq. 3.13 and 3.29)::

    U(r) = GM/R Σ_{n=0..N} Σ_{m=0..n} (C̄nm V̄nm + S̄nm W̄nm) = GM/R Re Σ (C̄nm − i S̄nm) Ȳnm

with the normalised solid harmonics ``Ȳnm = V̄nm + i W̄nm = N̄nm (R/r)^(n+1) Pnm(sin φ) e^(i m λ)``
and ``N̄nm = sqrt((2 − δm0)(2n + 1)(n − m)!/(n + m)!)``. ``Ȳnm`` are computed in Cartesian
coordinates by the recursions of Cunningham (1970) (Montenbruck & Gill 2000, sec. 3.2.4,
eq. 3.31-3.32), rewritten for normalised functions: diagonal
``Ȳmm = c_m (x + i y) R/r² Ȳm-1,m-1`` (``c_1 = √3``, ``c_m = sqrt((2m + 1)/(2m))``) and column
``Ȳnm = a_nm z R/r² Ȳn-1,m − b_nm R²/r² Ȳn-2,m`` with the factors ``a_nm``, ``b_nm`` of the
standard forward-column recursion of normalised Legendre functions (Holmes & Featherstone 2002,
J. Geodesy 76, eq. 12-13). The recursion uses no 1/cos φ and is valid at the poles; columns
whose diagonal term underflows to zero (orders m ≳ 50 within ~1e-6 rad of the poles, or any
m ≥ 1 on the axis) contribute exactly zero and are skipped. At degree ≤ ~2000 the diagonal
terms cannot underflow where they matter, so no extended-range arithmetic is needed
(Holmes & Featherstone 2002, sec. 2.6).

Derivatives. The operators ``∂z``, ``∂± = ∂x ± i ∂y`` map solid harmonics of degree n onto
degree n + 1 (Cunningham 1970; Montenbruck & Gill 2000, eq. 3.33, from which)::

    ∂z Ynm = −(n − m + 1)/R Yn+1,m,   ∂+ Ynm = −Yn+1,m+1/R,
    ∂− Ynm = (n − m + 1)(n − m + 2)/R Yn+1,m−1  (m ≥ 1),   ∂− Yn0 = −conj(Yn+1,1)/R

(unnormalised). Any component of the acceleration ``a = ∇U`` and of the gradient
``∂a/∂r = ∇∇U`` is therefore again a sum ``Re Σ D̄nm Ȳnm``, of degree N + 1 and N + 2; its
coefficients ``D̄`` are derived once from ``C̄``, ``S̄`` (see :func:`_derivative_fields`), and one
evaluation of ``Ȳnm`` up to degree N + 2 gives all nine sums in O(N²) operations.


The coefficient algebra (numpy) and the compiled sums (numba) are used by
:class:`leopod.dynamics.gravity_field.GravityField` and by its force
:class:`leopod.dynamics.gravity_field.EarthGravity`.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["acceleration_sums", "acceleration_table", "field_sums", "recursion_tables"]

#: Index of each component in the nine sums of ``_ACC_GRAD_FIELDS``: a_x, a_y, a_z, then the
#: gradient's upper triangle xx, xy, xz, yy, yz, zz.
_GRAD_INDEX = np.array([[3, 4, 5], [4, 6, 7], [5, 7, 8]])


# ------------------------------------------------------------------------ coefficient algebra


def _degree_order(size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Degree n (shape (size, 1)), order m (shape (1, size)) and the mask m <= n (size, size)."""
    n = np.arange(size, dtype=float)[:, None]
    m = np.arange(size, dtype=float)[None, :]
    return n, m, m <= n


def _derivative_fields(d: np.ndarray, radius_m: float) -> tuple[np.ndarray, np.ndarray,
                                                                np.ndarray]:
    """Coefficients of ∂F/∂x, ∂F/∂y, ∂F/∂z for a field ``F = Re Σ d[n, m] Ȳnm``.

    Parameters
    ----------
    d : ndarray of complex, shape (L + 1, L + 1)
        Coefficients [unit of F]; only m <= n is used, and only the real part at m = 0.
    radius_m : float
        Reference radius R of the solid harmonics [m].

    Returns
    -------
    dx, dy, dz : ndarray of complex, shape (L + 2, L + 2)
        Coefficients of the three derivatives [unit of F / m] (imaginary part 0 at m = 0).

    Notes
    -----
    Normalised form of the operators of the module docstring, with ``∂x = (∂+ + ∂−)/2``,
    ``∂y = (∂+ − ∂−)/(2i)``. The ratios of normalisation factors are
    ``p = N̄nm/N̄n+1,m+1``, ``q = (n − m + 1)(n − m + 2) N̄nm/N̄n+1,m−1`` and
    ``s = (n − m + 1) N̄nm/N̄n+1,m``.
    """
    size = d.shape[0]
    n, m, valid = _degree_order(size)
    d = np.where(valid, d, 0.0)
    d[:, 0] = d[:, 0].real
    two_m0 = np.where(m == 0, 1.0, 2.0)          # 2 − δm0
    two_m1 = np.where(m == 1, 1.0, 2.0)          # 2 − δm−1,0
    p = np.sqrt(two_m0 * (2 * n + 1) * (n + m + 2) * (n + m + 1) / (2 * (2 * n + 3)))
    q = np.sqrt(np.where(valid, 2 * (2 * n + 1) * (n - m + 1) * (n - m + 2)
                         / (two_m1 * (2 * n + 3)), 0.0))
    s = np.sqrt(np.where(valid, (2 * n + 1) * (n + m + 1) * (n - m + 1) / (2 * n + 3), 0.0))

    dx, dy, dz = (np.zeros((size + 1, size + 1), dtype=complex) for _ in range(3))
    dz[1:, :size] = -s * d
    # sources m >= 1: ∂+ -> (n+1, m+1), ∂- -> (n+1, m-1)
    plus, minus = -p[:, 1:] * d[:, 1:], q[:, 1:] * d[:, 1:]
    dx[1:, 2:] += plus / 2
    dx[1:, :size - 1] += minus / 2
    dy[1:, 2:] += plus / 2j
    dy[1:, :size - 1] += -minus / 2j
    # sources m = 0 (real): ∂x -> −p Re Ȳn+1,1, ∂y -> −p Im Ȳn+1,1
    dx[1:, 1] += -p[:, 0] * d[:, 0].real
    dy[1:, 1] += 1j * p[:, 0] * d[:, 0].real
    for out in (dx, dy, dz):
        out /= radius_m
        out[:, 0] = out[:, 0].real
    return dx, dy, dz


def _acc_fields(c: np.ndarray, s: np.ndarray, gm_m3_s2: float, radius_m: float
                ) -> list[np.ndarray]:
    """Coefficients of U, a_x, a_y, a_z: four complex arrays of shape (N + 3, N + 3)
    (zero-padded), in that order."""
    size = c.shape[0] + 2
    u = np.zeros((size, size), dtype=complex)
    u[:size - 2, :size - 2] = gm_m3_s2 / radius_m * (c - 1j * s)
    return [u, *(f[:size, :size] for f in _derivative_fields(u[:size - 1, :size - 1],
                                                            radius_m))]


def _acc_grad_fields(c: np.ndarray, s: np.ndarray, gm_m3_s2: float, radius_m: float
                     ) -> list[np.ndarray]:
    """Coefficients of U, a_x, a_y, a_z, and of U_xx, U_xy, U_xz, U_yy, U_yz, U_zz.

    Returns ten complex arrays of shape (N + 3, N + 3) (zero-padded), in that order.
    """
    size = c.shape[0] + 2
    u, ax, ay, az = _acc_fields(c, s, gm_m3_s2, radius_m)
    axx, axy, axz = _derivative_fields(ax[:size - 1, :size - 1], radius_m)
    _, ayy, ayz = _derivative_fields(ay[:size - 1, :size - 1], radius_m)
    azz = _derivative_fields(az[:size - 1, :size - 1], radius_m)[2]
    return [u, ax, ay, az, axx, axy, axz, ayy, ayz, azz]


def recursion_tables(degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Packed factors of the normalised Cunningham recursion up to ``degree``.

    Packing: index ``k = offsets[m] + n − m`` runs order by order (m outer, n inner).

    Returns
    -------
    offsets : ndarray of int64, shape (degree + 2,)
    rec_a, rec_b : ndarray, shape (K,)
        ``a_nm = sqrt((2n − 1)(2n + 1)/((n − m)(n + m)))`` and
        ``b_nm = sqrt((2n + 1)(n + m − 1)(n − m − 1)/((n − m)(n + m)(2n − 3)))`` (0 where
        unused), Holmes & Featherstone (2002) eq. 12-13.
    diag : ndarray, shape (degree + 1,)
        ``c_m`` of the diagonal step (c_0 unused).
    """
    lengths = degree + 1 - np.arange(degree + 1)
    offsets = np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64)
    n, m, valid = _degree_order(degree + 1)
    above = valid & (n > m)
    nm = np.where(above, (n - m) * (n + m), 1.0)
    rec_a = np.sqrt(np.where(above, (2 * n - 1) * (2 * n + 1) / nm, 0.0))
    rec_b = np.sqrt(np.where(above & (n > m + 1), (2 * n + 1) * (n + m - 1) * (n - m - 1)
                             / (nm * np.maximum(2 * n - 3, 1.0)), 0.0))
    diag = np.sqrt((2 * np.arange(degree + 1) + 1) / np.maximum(2 * np.arange(degree + 1), 1))
    if degree >= 1:
        diag[1] = np.sqrt(3.0)
    return offsets, _pack(rec_a, offsets), _pack(rec_b, offsets), diag


def _pack(grid: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Pack the m <= n part of a (L+1, L+1) grid order by order (index offsets[m] + n − m)."""
    size = grid.shape[0]
    return np.concatenate([grid[m:, m] for m in range(size)]) if size else np.zeros(0)


def acceleration_table(c: np.ndarray, s: np.ndarray, gm_m3_s2: float, radius_m: float,
                       offsets: np.ndarray) -> np.ndarray:
    """Packed acceleration-sum table (K, 6) of a coefficient set, for :func:`acceleration_sums`.

    Parameters
    ----------
    c, s : ndarray, shape (N+1, N+1)
        Fully normalised coefficients (e.g. tidal corrections ΔC̄, ΔS̄).
    gm_m3_s2, radius_m : float
        GM and reference radius the coefficients refer to.
    offsets : ndarray of int64
        Packing offsets from :func:`recursion_tables` of degree ≥ N + 2.

    Returns
    -------
    ndarray, shape (K, 6)
        The table is linear in (c, s), so tables at two epochs may be interpolated.
    """
    return _field_table(_acc_fields(c, s, gm_m3_s2, radius_m)[1:], offsets)


def _field_table(fields: list[np.ndarray], offsets: np.ndarray) -> np.ndarray:
    """Table (K, 2 f) of the packed coefficients: [Re D, −Im D] of each field side by side.

    With this sign, ``Re(D Ȳ) = Re D V̄ − Im D W̄`` becomes a plain sum of products.
    """
    cols = []
    for f in fields:
        packed = _pack(f, offsets)
        cols += [packed.real, -packed.imag]
    return np.ascontiguousarray(np.stack(cols, axis=1))


# ------------------------------------------------------------------------------- kernels


@numba.njit(cache=True)
def field_sums(pos_m, radius_m, degree, offsets, rec_a, rec_b, diag, table, out):
    """Sums ``Re Σ_{n<=degree} D̄nm Ȳnm(pos)`` of several fields at one position (in place).

    Parameters
    ----------
    pos_m : ndarray, shape (3,)
        Earth-fixed position [m], not the origin.
    radius_m : float
        Reference radius R [m].
    degree : int
        Highest degree summed (<= the degree of the tables).
    offsets, rec_a, rec_b, diag : ndarray
        Recursion tables of :func:`recursion_tables`.
    table : ndarray, shape (K, 2 f)
        Packed field coefficients (:func:`_field_table`).
    out : ndarray, shape (f,)
        Receives the f sums.
    """
    nf = out.shape[0]
    x, y, z = pos_m[0], pos_m[1], pos_m[2]
    r2 = x * x + y * y + z * z
    scale = radius_m / r2
    xs, ys, zs, rs = x * scale, y * scale, z * scale, radius_m * scale
    for j in range(nf):
        out[j] = 0.0
    v_mm = radius_m / np.sqrt(r2)
    w_mm = 0.0
    for m in range(degree + 1):
        if m > 0:
            v_new = diag[m] * (xs * v_mm - ys * w_mm)
            w_mm = diag[m] * (xs * w_mm + ys * v_mm)
            v_mm = v_new
            if v_mm == 0.0 and w_mm == 0.0:
                break  # underflow (or on the axis): all higher orders are exactly zero
        k = offsets[m]
        for j in range(nf):
            out[j] += table[k, 2 * j] * v_mm + table[k, 2 * j + 1] * w_mm
        v1, w1, v2, w2 = v_mm, w_mm, 0.0, 0.0
        for _ in range(m + 1, degree + 1):
            k += 1
            v = rec_a[k] * zs * v1 - rec_b[k] * rs * v2
            w = rec_a[k] * zs * w1 - rec_b[k] * rs * w2
            for j in range(nf):
                out[j] += table[k, 2 * j] * v + table[k, 2 * j + 1] * w
            v2, w2, v1, w1 = v1, w1, v, w


@numba.njit(cache=True)
def acceleration_sums(pos_m, radius_m, degree, offsets, rec_a, rec_b, diag, table, out):
    """:func:`field_sums` specialised to three fields (the acceleration), ~1.6 times faster.

    Same arguments as :func:`field_sums` with ``table`` of shape (K, 6) and ``out`` (3,).
    """
    x, y, z = pos_m[0], pos_m[1], pos_m[2]
    r2 = x * x + y * y + z * z
    scale = radius_m / r2
    xs, ys, zs, rs = x * scale, y * scale, z * scale, radius_m * scale
    ax = ay = az = 0.0
    v_mm = radius_m / np.sqrt(r2)
    w_mm = 0.0
    for m in range(degree + 1):
        if m > 0:
            v_new = diag[m] * (xs * v_mm - ys * w_mm)
            w_mm = diag[m] * (xs * w_mm + ys * v_mm)
            v_mm = v_new
            if v_mm == 0.0 and w_mm == 0.0:
                break
        k = offsets[m]
        v, w, v1, w1, v2, w2 = v_mm, w_mm, v_mm, w_mm, 0.0, 0.0
        for n in range(m, degree + 1):
            if n > m:
                k += 1
                v = rec_a[k] * zs * v1 - rec_b[k] * rs * v2
                w = rec_a[k] * zs * w1 - rec_b[k] * rs * w2
                v2, w2, v1, w1 = v1, w1, v, w
            ax += table[k, 0] * v + table[k, 1] * w
            ay += table[k, 2] * v + table[k, 3] * w
            az += table[k, 4] * v + table[k, 5] * w
    out[0], out[1], out[2] = ax, ay, az


@numba.njit(cache=True)
def _sums_many(pos_m, radius_m, degree, offsets, rec_a, rec_b, diag, table, out):
    """Sums for positions (n, 3) into out (n, f); False if a position is the origin."""
    for i in range(pos_m.shape[0]):
        if pos_m[i, 0] == 0.0 and pos_m[i, 1] == 0.0 and pos_m[i, 2] == 0.0:
            return False
        if out.shape[1] == 3:
            acceleration_sums(pos_m[i], radius_m, degree, offsets, rec_a, rec_b, diag, table,
                              out[i])
        else:
            field_sums(pos_m[i], radius_m, degree, offsets, rec_a, rec_b, diag, table, out[i])
    return True


@numba.njit(cache=True)
def _acc_grad_many(pos_m, radius_m, degree, offsets, rec_a, rec_b, diag, table, acc, grad):
    """Acceleration (n, 3) and gradient (n, 3, 3) from the nine sums; False if a position is 0."""
    sums = np.empty(9)
    for i in range(pos_m.shape[0]):
        if pos_m[i, 0] == 0.0 and pos_m[i, 1] == 0.0 and pos_m[i, 2] == 0.0:
            return False
        field_sums(pos_m[i], radius_m, degree, offsets, rec_a, rec_b, diag, table, sums)
        for a in range(3):
            acc[i, a] = sums[a]
            grad[i, a, a] = sums[_GRAD_INDEX[a, a]]
            for b in range(a + 1, 3):
                grad[i, a, b] = sums[_GRAD_INDEX[a, b]]
                grad[i, b, a] = grad[i, a, b]
    return True
