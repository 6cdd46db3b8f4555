"""Deliberately wrong ambiguity-resolution products, to check that leopod refuses them.

The simulator's products (:func:`leopod.simulate.biases.ar_products`) fit its observations
exactly. Two faults seen with real products can be switched on
(``simulate.products.ar_fault``):

``"flipped_sign"``
    The bias files carry the opposite sign: every Bias-SINEX OSB (code and phase) and every
    CNES/CLS ``WL`` record is negated, as when a product written "observed − OSB" is read as
    "observed + OSB" (issue 19: the independent check that flipped the OSB sign). The
    integer-recovery clocks stay right. The SD wide lanes then carry ``2 Δw^s``, uniform modulo
    one cycle for biases uniform over a cycle.
``"other_centre"``
    The bias product and the integer-recovery clocks come from another realisation of the
    satellite phase biases, as when the clocks of one analysis centre are combined with the
    biases of another: each satellite's two phase biases are shifted by the same draw
    ``δ^s`` uniform in [−0.5, 0.5) cycles. The wide-lane biases ``w^s`` do not change (the
    shift cancels in ``β1 − β2``), the ionosphere-free phase bias changes by ``λ_NL δ^s``
    (:func:`leopod.simulate.biases.if_phase_bias_m` of equal shifts): the NL is no longer
    integer.

``"none"`` gives the consistent products. The truth (``ArProducts.truth``) always holds the
biases of the observations.
"""

from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

import numpy as np

from leopod.simulate.biases import ArProducts, SimulatedBiases, ar_products, truth_dataset

__all__ = ["AR_FAULTS", "FaultyProducts", "faulty_products"]

#: The faults :func:`faulty_products` knows.
AR_FAULTS = ("none", "flipped_sign", "other_centre")


class FaultyProducts(NamedTuple):
    """Products of one day with a fault, and the biases their clocks are made from."""

    products: ArProducts
    """OSB and WL datasets as written to the files; ``truth`` of the observations."""
    clock_biases: SimulatedBiases
    """Biases for :func:`leopod.simulate.biases.integer_clock_s` of this product."""


def faulty_products(biases: SimulatedBiases, fault: str, rng: np.random.Generator,
                    **kwargs) -> FaultyProducts:
    """The AR products of ``biases`` with ``fault`` (module docstring).

    Parameters
    ----------
    biases : SimulatedBiases
        The true biases of the day.
    fault : str
        One of :data:`AR_FAULTS`.
    rng : numpy.random.Generator
        Source of the other centre's shifts (not used by the other faults).
    **kwargs
        Passed to :func:`leopod.simulate.biases.ar_products` (``window_s``, ``agency``).

    Returns
    -------
    FaultyProducts

    Raises
    ------
    ValueError
        If ``fault`` is unknown.
    """
    if fault not in AR_FAULTS:
        raise ValueError(f"unknown AR product fault {fault!r} (one of {', '.join(AR_FAULTS)})")
    if fault == "other_centre":
        shift = rng.uniform(-0.5, 0.5, biases.phase_sat_cyc.sizes["sv"])
        other = replace(biases, phase_sat_cyc=biases.phase_sat_cyc + shift[:, None])
        products = ar_products(other, **kwargs)._replace(truth=truth_dataset(biases))
        return FaultyProducts(products, other)
    products = ar_products(biases, **kwargs)
    if fault == "flipped_sign":
        osb = products.osb.copy()
        osb["value_s"] = -osb["value_s"]
        wl = products.wl.copy()
        wl["wl_bias_cyc"] = -wl["wl_bias_cyc"]
        products = products._replace(osb=osb, wl=wl)
    return FaultyProducts(products, biases)
