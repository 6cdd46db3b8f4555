"""Astronomical foundation: Sun and Moon positions, fundamental and Doodson arguments."""
