"""Numerical foundation: interpolation, smoothing and finite-value statistics of series."""
