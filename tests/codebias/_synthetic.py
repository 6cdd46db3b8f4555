"""Synthetic multipath passes across the antenna sky (closed-loop truth for the map tests)."""

import numpy as np


def smooth_map(az_deg, el_deg):
    """A smooth antenna-frame pattern [m]: stronger near the horizon, azimuth-dependent."""
    az, el = np.radians(az_deg), np.radians(el_deg)
    return 0.4 * np.cos(el) ** 2 * (1 + np.cos(az - 2.0)) + 0.1 * np.sin(2 * az) * np.cos(el)


def synthetic_passes(n_passes=600, step_s=30.0, seed=7, noise_m=0.05):
    """Passes rising and setting along random straight tracks through the polar sky plot.

    Returns az, el [deg], multipath [m] (map + pass offset + elevation-dependent noise),
    pass keys, the noise-free map values and the noise sigmas.
    """
    rng = np.random.default_rng(seed)
    az, el, key = [], [], []
    for p in range(n_passes):
        # a chord of the unit disc (r = 1 - el/90) at random direction and distance
        phi, d = rng.uniform(0, 2 * np.pi), rng.uniform(0, 0.95)
        half = np.sqrt(1 - d**2)
        n = max(int(rng.uniform(20, 60) * 60 / step_s), 10)
        s = np.linspace(-half, half, n)
        x = d * np.cos(phi) - s * np.sin(phi)
        y = d * np.sin(phi) + s * np.cos(phi)
        r = np.minimum(np.hypot(x, y), 1.0)
        az.append(np.degrees(np.arctan2(y, x)) % 360)
        el.append(90.0 * (1 - r))
        key.append(np.full(n, p))
    az, el, key = np.concatenate(az), np.concatenate(el), np.concatenate(key)
    sigma = noise_m * (1 + 3 * np.exp(-el / 10.0))
    truth = smooth_map(az, el)
    offsets = rng.uniform(-20, 20, n_passes)
    mp = truth + offsets[key] + sigma * rng.standard_normal(az.size)
    return az, el, mp, key, truth, sigma

