"""ITRF -> GCRF matrices carried over sub-µs shifts of the reception times (float POD).

Authority: direct evaluation of :func:`leopod.frames.earth_rotation.gcrf_from_itrf_matrices`
at the shifted times; the tolerance is the ~3e-14 rad resolution of the Earth rotation angle
of ``erfa.era00`` in that direct evaluation (module docstring of earth_rotation): direct
evaluations 1 ns apart differ by up to 9e-14 where the rotation accounts for 7e-14.
"""

import numpy as np

from leopod.estimation.float_pod import _ReceptionRotation
from leopod.frames.earth_rotation import gcrf_from_itrf_matrices


def test_carried_matrices_equal_direct_evaluation():
    rng = np.random.default_rng(3)
    times = np.datetime64("2007-03-21T00:00", "ns") + np.arange(2880) * np.timedelta64(30, "s")
    times = times - rng.integers(-30_000, 30_000, times.size).astype("timedelta64[ns]")
    rotation = _ReceptionRotation(None)
    first = rotation(times)
    np.testing.assert_array_equal(first, gcrf_from_itrf_matrices(times)[0])
    for limit_ns in (3, 1000):
        shifted = times + rng.integers(-limit_ns, limit_ns + 1, times.size).astype(
            "timedelta64[ns]")
        carried = rotation(shifted)
        direct, _ = gcrf_from_itrf_matrices(shifted)
        assert np.abs(carried - direct).max() < 5e-14
        assert np.allclose(carried @ carried.transpose(0, 2, 1), np.eye(3), rtol=0, atol=1e-15)
    # beyond 1 µs: evaluated directly (and the reference of later shifts)
    far = times + np.timedelta64(1001, "ns")
    np.testing.assert_array_equal(rotation(far), gcrf_from_itrf_matrices(far)[0])
    assert rotation.times is far
