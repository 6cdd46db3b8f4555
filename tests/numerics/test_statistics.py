"""finite_rms: RMS over the finite entries. Authority: the definition sqrt(mean(x²))."""

import numpy as np

from leopod.numerics.statistics import finite_rms


def test_finite_rms_skips_nan_and_gives_nan_for_nothing():
    x = np.array([[3.0, np.nan], [4.0, np.nan]])
    assert finite_rms(x) == np.sqrt(12.5)
    assert np.allclose(finite_rms(x, axis=0), [np.sqrt(12.5), np.nan], equal_nan=True)
    assert np.isnan(finite_rms(np.full(3, np.nan)))
    assert isinstance(finite_rms([1.0, np.inf]), float) and finite_rms([1.0, np.inf]) == 1.0
