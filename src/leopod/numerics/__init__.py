"""Numerical foundation: interpolation of tabulated series."""
