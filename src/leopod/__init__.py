"""leopod: precise orbit determination of low-Earth-orbit satellites from onboard GNSS."""

__version__ = "0.1.0"
