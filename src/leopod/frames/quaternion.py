"""Attitude quaternions and a quaternion time series interpolated to any epoch.

**Convention** (that of the GRACE SCA1B star-camera product, Case et al. 2010, sec. 1.5.3 and
the SCA1B record, and of leopod's attitude files :mod:`leopod.io.attitude`): a unit quaternion
``q = (q0, q1, q2, q3)``, scalar first, ``q0 = cos(θ/2)``, ``(q1, q2, q3) = sin(θ/2) u``,
describes the rotation *from the inertial frame (GCRF/J2000) to the satellite body frame*: the
body axes are the inertial axes turned by θ about ``u``. With the rotation matrix

``R(q) = [[1−2(q2²+q3²), 2(q1q2−q0q3), 2(q1q3+q0q2)],
          [2(q1q2+q0q3), 1−2(q1²+q3²), 2(q2q3−q0q1)],
          [2(q1q3−q0q2), 2(q2q3+q0q1), 1−2(q1²+q2²)]]``

the columns of ``R(q)`` are the body axes X, Y, Z in inertial coordinates, so
``v_inertial = R(q) v_body`` and ``v_body = R(q)ᵀ v_inertial``. leopod's attitude matrices hold
the body axes as *rows* (:func:`leopod.frames.leo_attitude.leo_body_axes`), i.e. ``R(q)ᵀ``
(:func:`body_axes_from_quaternion`). The direction was checked on the data: with ``R(q)`` the
SCA1B +Z of GRACE-A/B on 2003-09-14 points within 1° of the geocentre and +X within 1° of
∓velocity of the GNV1B orbit; with ``R(q)ᵀ`` the angles are 40–70° (test
``tests/io/test_attitude_files.py``).

The GRACE inertial frame is that of J2000 (mean equator and equinox); it differs from the
GCRF by the frame bias, 23 mas (1.1e-7 rad), which moves an antenna 0.5 m from the centre of
mass by 0.05 µm: leopod takes the quaternions as GCRF -> body.

**Interpolation**: spherical linear interpolation (Shoemake 1985) between the two records that
bracket an epoch, ``q(f) = q_i ⊗ (q_i* ⊗ q_{i+1})^f`` with the sign of ``q_{i+1}`` chosen so
that the two are in the same hemisphere (``q`` and ``−q`` are the same rotation). It turns the
axes at a constant rate about a fixed axis between records; for an Earth-pointing satellite
whose frame turns at the orbit rate n with a small variation of the rate (eccentricity e) the
error is about ``e n² Δt² / 4`` (3e-8 rad for e = 0.001, n = 1.1e-3 rad/s, Δt = 10 s).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["AttitudeCoverageError", "QuaternionSeries", "body_axes_from_quaternion",
           "quaternion_from_body_axes", "quaternion_multiply", "slerp"]


class AttitudeCoverageError(ValueError):
    """An epoch is outside an attitude series or inside a gap longer than its limit."""


def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product ``a ⊗ b`` of scalar-first quaternions, shape (..., 4).

    ``R(a ⊗ b) = R(a) R(b)`` for the matrix of the module docstring.
    """
    a0, a1, a2, a3 = np.moveaxis(np.asarray(a, float), -1, 0)
    b0, b1, b2, b3 = np.moveaxis(np.asarray(b, float), -1, 0)
    return np.stack([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
                     a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
                     a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0], axis=-1)


def _conjugate(q: np.ndarray) -> np.ndarray:
    return np.asarray(q, float) * np.array([1.0, -1.0, -1.0, -1.0])


def body_axes_from_quaternion(q: np.ndarray) -> np.ndarray:
    """Body axes (rows X, Y, Z) of inertial -> body quaternions: ``R(q)ᵀ``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Scalar-first quaternions (normalised here).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Rows are the body axes in inertial coordinates: ``v_body = M @ v_inertial``.
    """
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    rot = np.stack([
        np.stack([1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3),
                  2 * (q1 * q3 + q0 * q2)], axis=-1),
        np.stack([2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3),
                  2 * (q2 * q3 - q0 * q1)], axis=-1),
        np.stack([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1),
                  1 - 2 * (q1 * q1 + q2 * q2)], axis=-1)], axis=-2)      # R(q)
    return np.swapaxes(rot, -1, -2)


def quaternion_from_body_axes(axes: np.ndarray) -> np.ndarray:
    """Inverse of :func:`body_axes_from_quaternion`: the quaternion with ``q0 >= 0``.

    Parameters
    ----------
    axes : array_like, shape (..., 3, 3)
        Rows X, Y, Z of the body frame in inertial coordinates (a rotation matrix).

    Returns
    -------
    ndarray, shape (..., 4)
        Unit scalar-first quaternions (Shepperd's method: the largest of the four squared
        components is taken from the diagonal, the others from off-diagonal sums, so no
        component is computed from a difference of nearly equal numbers).
    """
    r = np.swapaxes(np.asarray(axes, dtype=float), -1, -2)               # R(q)
    tr = r[..., 0, 0] + r[..., 1, 1] + r[..., 2, 2]
    cand = np.stack([tr, r[..., 0, 0], r[..., 1, 1], r[..., 2, 2]], axis=-1)
    k = np.argmax(cand, axis=-1)
    q = np.empty(r.shape[:-2] + (4,))
    d = {0: 1 + tr, 1: 1 + 2 * r[..., 0, 0] - tr, 2: 1 + 2 * r[..., 1, 1] - tr,
         3: 1 + 2 * r[..., 2, 2] - tr}
    s21, s02, s10 = r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], \
        r[..., 1, 0] - r[..., 0, 1]
    a01, a02, a12 = r[..., 0, 1] + r[..., 1, 0], r[..., 0, 2] + r[..., 2, 0], \
        r[..., 1, 2] + r[..., 2, 1]
    rows = {0: (None, s21, s02, s10), 1: (s21, None, a01, a02), 2: (s02, a01, None, a12),
            3: (s10, a02, a12, None)}
    for j in range(4):
        m = k == j
        if not np.any(m):
            continue
        h = np.sqrt(np.maximum(d[j][m], 0.0))                            # 2 |q_j|
        for i, num in enumerate(rows[j]):
            q[m, i] = h / 2 if num is None else num[m] / (2 * h)
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def slerp(q_a: np.ndarray, q_b: np.ndarray, frac: np.ndarray) -> np.ndarray:
    """Spherical linear interpolation ``q_a ⊗ (q_a* ⊗ q_b)^f`` (Shoemake 1985), shape (n, 4).

    ``q_b`` is taken with the sign that puts it in ``q_a``'s hemisphere; ``frac`` outside
    [0, 1] extrapolates at the same rate about the same axis.
    """
    q_a, q_b = np.asarray(q_a, float), np.asarray(q_b, float)
    q_b = np.where(np.sum(q_a * q_b, axis=-1, keepdims=True) < 0, -q_b, q_b)
    d = quaternion_multiply(_conjugate(q_a), q_b)
    vec = d[..., 1:]
    s = np.linalg.norm(vec, axis=-1)
    half = np.arctan2(s, d[..., 0])                                      # θ/2 of the step
    f = np.asarray(frac, float)
    # unit axis (any axis when the step is zero: the rotation is then the identity)
    axis = np.where(s[..., None] > 0, vec / np.where(s > 0, s, 1.0)[..., None], 0.0)
    step = np.concatenate([np.cos(f * half)[..., None], np.sin(f * half)[..., None] * axis],
                          axis=-1)
    return quaternion_multiply(q_a, step)


@dataclass(frozen=True)
class QuaternionSeries:
    """Inertial -> body quaternions at increasing epochs, interpolated to any epoch.

    Attributes
    ----------
    times : ndarray of datetime64[ns], shape (n,)
        Strictly increasing epochs (GPS time).
    quat : ndarray, shape (n, 4)
        Scalar-first unit quaternions, inertial (GCRF/J2000) -> body (module docstring).
    max_gap_s : float
        Records farther apart than this are not interpolated between (a data gap) [s]; an
        epoch may lie up to half of it before the first or after the last record
        (extrapolated at the rate of the end interval) [s].
    source : str
        What the series was read from (file names), for messages and provenance.
    """

    times: np.ndarray
    quat: np.ndarray
    max_gap_s: float
    source: str = ""

    def __post_init__(self):
        t = np.asarray(self.times, dtype="datetime64[ns]")
        q = np.asarray(self.quat, dtype=float)
        if t.ndim != 1 or q.shape != (t.size, 4) or t.size < 2:
            raise ValueError(f"attitude series {self.source}: need (n,) epochs and (n, 4) "
                             f"quaternions with n >= 2, got {t.shape} and {q.shape}")
        if np.any(np.diff(t.astype("int64")) <= 0):
            raise ValueError(f"attitude series {self.source}: epochs are not strictly "
                             "increasing")
        norm = np.linalg.norm(q, axis=1)
        if not np.all(np.isfinite(norm)) or np.any(np.abs(norm - 1.0) > 1e-3):
            i = int(np.flatnonzero(~(np.abs(norm - 1.0) <= 1e-3))[0])
            raise ValueError(f"attitude series {self.source}: quaternion at {t[i]} has norm "
                             f"{norm[i]:.6g}, not 1")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "quat", q / norm[:, None])

    def _locate(self, times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Interval index, fraction and coverage of each epoch."""
        t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]")).astype("int64")
        ts = self.times.astype("int64")
        i = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, ts.size - 2)
        span = (ts[i + 1] - ts[i]).astype(float)
        frac = (t - ts[i]).astype(float) / span
        gap_ns = self.max_gap_s * 1e9
        on_record = (t == ts[i]) | (t == ts[i + 1])
        inside = (t >= ts[0]) & (t <= ts[-1]) & ((span <= gap_ns) | on_record)
        edge = ((t < ts[0]) & (ts[0] - t <= gap_ns / 2) & (span <= gap_ns)) | \
            ((t > ts[-1]) & (t - ts[-1] <= gap_ns / 2) & (span <= gap_ns))
        return i, frac, inside | edge

    def covered(self, times) -> np.ndarray:
        """True where an epoch can be interpolated (shape (m,) bool)."""
        return self._locate(times)[2]

    def quaternions(self, times, *, allow_uncovered: bool = False) -> np.ndarray:
        """Interpolated quaternions, shape (m, 4) (NaN where uncovered, if allowed).

        Raises
        ------
        AttitudeCoverageError
            For an epoch outside the series or in a gap longer than ``max_gap_s``, naming
            the first such epoch, unless ``allow_uncovered``.
        """
        t = np.atleast_1d(np.asarray(times, dtype="datetime64[ns]"))
        i, frac, ok = self._locate(t)
        if not allow_uncovered and not ok.all():
            bad = t[~ok]
            raise AttitudeCoverageError(
                f"attitude {self.source or 'series'}: {bad.size} epoch(s) not covered, first "
                f"{bad[0]} (records {self.times[0]} to {self.times[-1]}, gaps longer than "
                f"{self.max_gap_s:g} s are not interpolated)")
        q = slerp(self.quat[i], self.quat[i + 1], frac)
        q[~ok] = np.nan
        return q

    def body_axes(self, times, *, allow_uncovered: bool = False) -> np.ndarray:
        """Inertial -> body rotations (rows X, Y, Z), shape (m, 3, 3), at the epochs."""
        return body_axes_from_quaternion(self.quaternions(times,
                                                          allow_uncovered=allow_uncovered))
