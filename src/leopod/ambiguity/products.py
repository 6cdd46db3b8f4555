"""Satellite wide-lane and phase biases from the campaign's AR product (CNES/CLS or OSB)."""

from __future__ import annotations

import logging

import numpy as np

from leopod.ambiguity.narrow_lane import sat_if_phase_bias_osb
from leopod.ambiguity.wide_lane import sat_wl_bias_cnes, sat_wl_bias_osb
from leopod.io.bias_sinex import read_bias_sinex
from leopod.io.wlbias import read_wl_bias

__all__ = ["ArProduct", "ar_product"]

log = logging.getLogger(__name__)


class ArProduct:
    """Satellite biases for the ambiguity resolution of one day.

    Attributes
    ----------
    wl_sat_cyc : xarray.DataArray or None
        ``w^s`` [WL cycles] per satellite (None: no product, no fixing).
    if_phase_bias_m : xarray.DataArray or None
        Satellite ionosphere-free phase bias [m] per satellite (OSB with ordinary clocks);
        None with integer-recovery clocks (CNES/CLS).
    label : str
        What the product is, for logs and the table.
    """

    def __init__(self, wl_sat_cyc, if_phase_bias_m, label):
        self.wl_sat_cyc, self.if_phase_bias_m, self.label = wl_sat_cyc, if_phase_bias_m, label

    def per_ambiguity(self, sv) -> np.ndarray | None:
        """Ionosphere-free phase bias of each ambiguity's satellite [m] (None if not needed)."""
        if self.if_phase_bias_m is None:
            return None
        return self.if_phase_bias_m.reindex(sv=np.asarray(sv).astype(str)).values


def ar_product(epoch, svs, phases, codes, *, wl_bias_path=None, osb_path=None,
               osb_applied: bool = False) -> ArProduct:
    """Read the AR product of a day: CNES/CLS WL records, else Bias-SINEX OSB, else none.

    Parameters
    ----------
    epoch : datetime64
        Epoch at which the biases are taken (e.g. noon of the day).
    svs : sequence of str
        Satellites (repetitions allowed).
    phases, codes : sequence of two str
        Signals of the ionosphere-free pair.
    wl_bias_path, osb_path : str, optional
        Product files (CNES/CLS clock file with WL records / Bias-SINEX).
    osb_applied : bool
        The Bias-SINEX code and phase OSBs were already removed from the observations (every
        hour with its own day's file, :mod:`leopod.gnss.signal_bias`, ``absolute`` mode):
        ``w^s`` and ``b^s_IF`` are then zero (NaN where the file lacks a satellite's phase
        OSBs; its codes lacking OSBs were set to NaN by the correction),
        so that the OSBs are not applied twice. Ignored with a CNES/CLS product.
    """
    svs = sorted({str(s) for s in svs})
    if wl_bias_path:
        ws = sat_wl_bias_cnes(read_wl_bias(wl_bias_path), epoch)
        return ArProduct(ws.reindex(sv=list(svs)), None,
                         f"CNES/CLS wide-lane biases + integer clocks ({wl_bias_path})")
    if osb_path:
        ds = read_bias_sinex(osb_path)
        ws = sat_wl_bias_osb(ds, svs, epoch, phase=tuple(phases), code=tuple(codes))
        ifb = sat_if_phase_bias_osb(ds, svs, epoch, phase=tuple(phases))
        if osb_applied:   # zero where the satellite has phase OSBs, NaN where it has not
            zero = ifb * 0.0
            return ArProduct(zero.assign_attrs(ws.attrs), zero.assign_attrs(ifb.attrs),
                             f"Bias-SINEX OSB ({osb_path}), applied to the observations")
        return ArProduct(ws, ifb, f"Bias-SINEX OSB ({osb_path})")
    log.warning("no AR product (products.wl_bias / products.osb): ambiguities are not fixed")
    return ArProduct(None, None, "none")

