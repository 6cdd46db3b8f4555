"""The files of a real GNSS product set for the simulated product world (a settings record).

Kept apart from :mod:`leopod.simulate.product_world` (which reads and models the products) so
that the workflow can list the files as rule inputs without importing the product machinery
at every Snakemake start.
"""

from __future__ import annotations

from dataclasses import dataclass

from leopod.settings import Settings

__all__ = ["ProductSet"]


@dataclass(frozen=True)
class ProductSet(Settings):
    """Files of a real GNSS product set (``simulate.gnss_products`` of the campaign schema).

    Attributes
    ----------
    orbit : tuple of str
        SP3 files covering the campaign (and the arcs' margins), in time order (one path may
        be given as a string).
    clock : tuple of str
        RINEX clock files of the campaign days (one path may be given as a string); empty
        (``None`` in the configuration): the clocks are simulated.
    osb : str
        Bias-SINEX file with the satellite code and phase OSBs.
    dcb_p1c1 : str or None
        CODE P1−C1 DCB file for C1C (None: C1C is not simulated with a satellite bias).
    """

    orbit: tuple[str, ...]
    clock: tuple[str, ...]
    osb: str
    dcb_p1c1: str | None

    def __post_init__(self):
        for name in ("orbit", "clock"):
            value = getattr(self, name)
            object.__setattr__(self, name, (value,) if isinstance(value, str)
                               else tuple(value or ()))

    @property
    def files(self) -> list[str]:
        """All files of the set (workflow inputs)."""
        return [*self.orbit, *self.clock, self.osb] + ([self.dcb_p1c1] if self.dcb_p1c1 else [])
