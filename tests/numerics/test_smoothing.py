"""Savitzky–Golay smoothing against SciPy (independent implementation) and polynomials."""

import numpy as np
import pytest
from scipy.signal import savgol_filter

from leopod.numerics.smoothing import savitzky_golay


@pytest.mark.parametrize("deriv", [0, 1, 2])
@pytest.mark.parametrize(("window", "order"), [(11, 5), (21, 3), (7, 6)])
def test_matches_scipy_savgol_filter(window, order, deriv):
    # authority: scipy.signal.savgol_filter (mode "interp", the default), an independent
    # implementation of the same least-squares definition
    rng = np.random.default_rng(1)
    y = np.cumsum(rng.normal(size=(200, 3)), axis=0)
    got = savitzky_golay(y, window, order, deriv=deriv, delta=30.0)
    want = savgol_filter(y, window, order, deriv=deriv, delta=30.0, axis=0)
    assert np.allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())


def test_reproduces_a_polynomial_of_its_degree_and_its_derivative():
    # analytic truth: a least-squares fit of degree p reproduces any polynomial of degree p
    t = np.arange(50) * 10.0
    y = 3.0 - 2e-2 * t + 4e-5 * t**2 - 1e-8 * t**3
    dy = -2e-2 + 8e-5 * t - 3e-8 * t**2
    assert np.allclose(savitzky_golay(y, 11, 3), y, atol=1e-10)
    assert np.allclose(savitzky_golay(y, 11, 3, deriv=1, delta=10.0), dy, atol=1e-12)


def test_refuses_an_even_or_too_long_window():
    with pytest.raises(ValueError, match="odd window"):
        savitzky_golay(np.zeros(20), 10, 3)
    with pytest.raises(ValueError, match="series length"):
        savitzky_golay(np.zeros(9), 11, 3)
