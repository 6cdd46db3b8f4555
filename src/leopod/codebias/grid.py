"""Azimuth × elevation grid in the antenna frame with bilinear interpolation.

Nodes lie on rings of constant antenna elevation ``0, Δe, ..., 90° − Δe`` with ``360°/Δa``
azimuths each, plus one node at the zenith (boresight): for 5° × 5° that is 72 × 18 + 1 = 1297
nodes, the parameter count of Peng et al. (2021) (sec. II). Directions follow
:func:`leopod.frames.attitude.antenna_angles`: elevation above the antenna horizon, azimuth from
+X (flight direction) towards +Y, in degrees.

A value at a direction is the bilinear interpolation (Wang et al. 2024, eqs. (7)-(9)) of the four
nodes around it: along azimuth on the lower and the upper ring, then along elevation. Azimuth wraps
around at 360°; between the highest ring and the zenith both upper corners are the zenith node,
so the interpolation there is linear in elevation towards the zenith value. Elevations below 0°
are evaluated at 0°. The interpolation weights of one direction sum to one, so a constant added
to every node adds that constant to every interpolated value (the datum defect the map
estimation has to fix, :mod:`leopod.codebias.estimate`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["AntennaGrid"]


@dataclass(frozen=True)
class AntennaGrid:
    """Regular antenna-frame grid of ``az_step_deg`` × ``el_step_deg`` with a zenith node.

    Attributes
    ----------
    az_step_deg, el_step_deg : float
        Node spacing [deg]; must divide 360° and 90° respectively.
    """

    az_step_deg: float = 5.0
    el_step_deg: float = 5.0

    def __post_init__(self):
        for name, step, span in (("az_step_deg", self.az_step_deg, 360.0),
                                 ("el_step_deg", self.el_step_deg, 90.0)):
            n = span / step
            if step <= 0 or abs(n - round(n)) > 1e-9:
                raise ValueError(f"{name} = {step} does not divide {span:g} degrees")

    @property
    def n_az(self) -> int:
        """Azimuths per ring."""
        return round(360.0 / self.az_step_deg)

    @property
    def n_rings(self) -> int:
        """Elevation rings below the zenith (0° up to 90° − step)."""
        return round(90.0 / self.el_step_deg)

    @property
    def n_nodes(self) -> int:
        """Number of map parameters: rings × azimuths + the zenith node."""
        return self.n_rings * self.n_az + 1

    @property
    def azimuth_deg(self) -> np.ndarray:
        """Node azimuths (n_az,) [deg]."""
        return np.arange(self.n_az) * self.az_step_deg

    @property
    def elevation_deg(self) -> np.ndarray:
        """Ring elevations and the zenith (n_rings + 1,) [deg]."""
        return np.arange(self.n_rings + 1) * self.el_step_deg

    def weights(self, az_deg, el_deg) -> tuple[np.ndarray, np.ndarray]:
        """Nodes and bilinear weights of directions.

        Parameters
        ----------
        az_deg, el_deg : array_like, shape (n,)
            Antenna-frame azimuth and elevation [deg] (finite).

        Returns
        -------
        nodes : ndarray of int, shape (n, 4)
            Node indices: lower ring (az, az + step), upper ring (az, az + step); the upper
            pair is the zenith node on the highest ring.
        weights : ndarray, shape (n, 4)
            Interpolation weights, summing to 1 per direction.
        """
        az = np.mod(np.asarray(az_deg, dtype=float), 360.0) / self.az_step_deg
        el = np.clip(np.asarray(el_deg, dtype=float), 0.0, 90.0) / self.el_step_deg
        ia = np.minimum(np.floor(az).astype(np.int64), self.n_az - 1)
        u = az - ia
        ring = np.minimum(np.floor(el).astype(np.int64), self.n_rings - 1)
        t = el - ring
        ib = (ia + 1) % self.n_az
        zenith = self.n_nodes - 1
        up = ring + 1
        top = up == self.n_rings
        nodes = np.stack([ring * self.n_az + ia, ring * self.n_az + ib,
                          np.where(top, zenith, up * self.n_az + ia),
                          np.where(top, zenith, up * self.n_az + ib)], axis=1)
        w = np.stack([(1 - u) * (1 - t), u * (1 - t), (1 - u) * t, u * t], axis=1)
        return nodes, w

    def nearest(self, az_deg, el_deg) -> np.ndarray:
        """Node whose neighbourhood (± half a step in azimuth and elevation) holds each
        direction, shape (n,); −1 below −half an elevation step or not finite.

        The neighbourhood of the zenith node is the cap above the highest ring's upper half
        step: every azimuth there belongs to it (the residual method's cell of a node,
        :mod:`leopod.antenna.pcv`).
        """
        az = np.asarray(az_deg, dtype=float)
        el = np.asarray(el_deg, dtype=float)
        ok = np.isfinite(az) & np.isfinite(el) & (el >= -0.5 * self.el_step_deg)
        ring = np.clip(np.rint(np.where(ok, el, 0.0) / self.el_step_deg), 0, self.n_rings)
        ia = np.rint(np.mod(np.where(ok, az, 0.0), 360.0) / self.az_step_deg) % self.n_az
        node = np.where(ring == self.n_rings, self.n_nodes - 1, ring * self.n_az + ia)
        return np.where(ok, node, -1).astype(np.int64)

    def design(self, az_deg, el_deg) -> sp.csr_matrix:
        """Sparse interpolation matrix (n, n_nodes): ``values_at_directions = A @ node_values``."""
        nodes, w = self.weights(az_deg, el_deg)
        n = nodes.shape[0]
        rows = np.repeat(np.arange(n), 4)
        a = sp.csr_matrix((w.ravel(), (rows, nodes.ravel())), shape=(n, self.n_nodes))
        a.sum_duplicates()
        return a

    def interpolate(self, node_values, az_deg, el_deg) -> np.ndarray:
        """Bilinear values at directions (n,); NaN where a node with weight > 0 is NaN or the
        direction is not finite."""
        az, el = np.asarray(az_deg, dtype=float), np.asarray(el_deg, dtype=float)
        out = np.full(az.shape, np.nan)
        ok = np.isfinite(az) & np.isfinite(el)
        nodes, w = self.weights(az[ok], el[ok])
        v = np.asarray(node_values, dtype=float)[nodes]
        bad = (w > 0) & ~np.isfinite(v)
        val = np.sum(np.where(w > 0, w * np.nan_to_num(v), 0.0), axis=1)
        val[bad.any(axis=1)] = np.nan
        out[ok] = val
        return out

    def node_directions(self) -> tuple[np.ndarray, np.ndarray]:
        """Azimuth and elevation of every node (n_nodes,) [deg], in node order."""
        az = np.r_[np.tile(self.azimuth_deg, self.n_rings), 0.0]
        el = np.r_[np.repeat(self.elevation_deg[:-1], self.n_az), 90.0]
        return az, el

    def neighbour_pairs(self) -> np.ndarray:
        """Pairs of adjacent nodes (k, 2): along each ring, between rings, to the zenith."""
        idx = np.arange(self.n_rings * self.n_az).reshape(self.n_rings, self.n_az)
        along = np.stack([idx.ravel(), np.roll(idx, -1, axis=1).ravel()], axis=1)
        across = np.stack([idx[:-1].ravel(), idx[1:].ravel()], axis=1)
        zen = np.stack([idx[-1], np.full(self.n_az, self.n_nodes - 1)], axis=1)
        return np.concatenate([along, across, zen])

    def to_grid(self, node_values) -> np.ndarray:
        """Node vector (n_nodes, ...) → array (n_rings + 1, n_az, ...); zenith row repeated."""
        v = np.asarray(node_values)
        rings = v[:-1].reshape(self.n_rings, self.n_az, *v.shape[1:])
        zen = np.broadcast_to(v[-1], (1, self.n_az, *v.shape[1:]))
        return np.concatenate([rings, zen], axis=0)

    def from_grid(self, grid_values) -> np.ndarray:
        """Inverse of :meth:`to_grid` (the zenith value is taken from azimuth 0)."""
        g = np.asarray(grid_values)
        return np.concatenate([g[:-1].reshape(self.n_rings * self.n_az, *g.shape[2:]),
                               g[-1, :1]], axis=0)
