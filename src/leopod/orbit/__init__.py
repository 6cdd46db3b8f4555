"""Orbit tables: interpolation of tabulated orbits and clocks."""
