"""The integer convention of leopod's fixed ambiguities, written into the ambiguity output.

Fixed integers can be compared with those of other software only if the conventions agree;
these are leopod's (the same text is in the README, section "Ambiguity integers"):

Observations (metres; ``s`` satellite, ``r`` receiver, ``i`` signal, ``w`` wind-up [cycles])::

    P_i = ρ + c (dt_r − dt^s) + γ_i I + d_r,i + d^s_i
    L_i = ρ + c (dt_r − dt^s) − γ_i I + λ_i (N_i + β_r,i + β^s_i + w)

Biases enter with a plus sign (:mod:`leopod.simulate.biases`). Bias-SINEX OSBs are
"corrected = observed − OSB" (code OSB ``d^s_i``, phase OSB ``λ_i β^s_i`` [m]); the CNES/CLS
``WL`` record is ``μ^s = −w^s`` with ``HMW/λ_WL = N_WL + w_r + w^s``,
``w = β1 − β2 − (f1 d1 + f2 d2)/((f1 + f2) λ_WL)`` (:mod:`leopod.ambiguity.wide_lane`).

Integers of the table (single difference ``i − j`` of two passes of different satellites):

* ``wl_integer`` = ``ΔN_WL = (N1 − N2)_i − (N1 − N2)_j``, signal 1 minus signal 2 of the
  phase pair (Peng et al. 2021, eq. (6));
* ``nl_integer`` = ``ΔN1``, the single difference of the integer of signal 1 (Peng et al. 2021,
  eq. (8); Jiang et al. 2023: the narrow-lane ambiguity equals the B1C one);
* ``fixed_if_m`` = ``λ_NL (ΔN1 + f2/(f1 − f2) ΔN_WL) + Δb^s_IF`` [m], ``λ_NL = c/(f1 + f2)``:
  the value of the difference of the float ionosphere-free ambiguities of the POD.

Phase wind-up: the POD models it (Wu et al. 1993) continuous along each GNSS satellite over
the whole arc (:func:`leopod.gnss.corrections.unwrap_windup`): the first observation of a
satellite in the arc has a wind-up in (−0.5, 0.5] cycles, and each later pass of that
satellite starts within half a cycle of where the previous one ended (the step across a
tracking gap is taken in (−0.5, 0.5]), so it carries the whole cycles accumulated while the
satellite was tracked earlier in the arc. Software that restarts the wind-up at every pass
(first value in (−0.5, 0.5]) has ``N1`` and ``N2`` of that pass larger by those whole cycles
``k`` (a small integer: ±1 in the comparison of issue 19), so ``ΔN1`` and the NL integers
differ by ``k_i − k_j``; ``ΔN_WL`` does not change (the wind-up in cycles is
the same on both frequencies and cancels in HMW). The integers also depend on the arc (the
first pass of a satellite in the arc starts the count) and on the whole cycles of the
product's phase biases (defined modulo one cycle).
"""

from __future__ import annotations

__all__ = ["integer_convention_attrs"]


def integer_convention_attrs(phases, ar_product: str = "") -> dict:
    """Attributes stating the integer convention of an ambiguity table (module docstring).

    Parameters
    ----------
    phases : sequence of two str
        Phase signals of the pair (signal 1, signal 2), e.g. ``("L1C", "L2W")``.
    ar_product : str
        What product the integers refer to.

    Returns
    -------
    dict
        ``convention_*`` attributes (str).
    """
    p1, p2 = (str(p) for p in phases)
    if len(phases) != 2 or p1 == p2:
        raise ValueError(f"need two different phase signals, got {tuple(phases)}")
    return {
        "convention_observation": (
            "P_i = rho + c(dt_r - dt^s) + gamma_i I + d_r,i + d^s_i; L_i = rho + c(dt_r - dt^s)"
            " - gamma_i I + lambda_i (N_i + beta_r,i + beta^s_i + w) [m], biases with + sign"),
        "convention_wl_integer": (
            f"wl_integer = (N_{p1} - N_{p2})_i - (N_{p1} - N_{p2})_j, pass i minus pass j"),
        "convention_nl_integer": f"nl_integer = N_{p1},i - N_{p1},j (signal-1 integer)",
        "convention_fixed_if_m": (
            "fixed_if_m = lambda_NL (nl_integer + f2/(f1 - f2) wl_integer) + delta b^s_IF, "
            "lambda_NL = c/(f1 + f2): difference of the float IF ambiguities of the POD [m]"),
        "convention_wl_bias": (
            "HMW/lambda_WL = N_WL + w_r + w^s, w = beta1 - beta2 - (f1 d1 + f2 d2)/((f1 + f2) "
            "lambda_WL); wl_float_cyc = SD of HMW/lambda_WL minus SD of w^s; CNES/CLS WL "
            "record = -w^s"),
        "convention_osb": (
            "Bias-SINEX: corrected = observed - OSB; code OSB = d^s_i, phase OSB = "
            "lambda_i beta^s_i [m]; b^s_IF = IF combination of the phase OSBs (0 with "
            "integer-recovery clocks, which hold it)"),
        "convention_windup": (
            "wind-up continuous along each GNSS satellite over the whole arc (first "
            "observation of a satellite in (-0.5, 0.5] cycles; a later pass starts within half"
            " a cycle of the end of the previous one, carrying its whole cycles): N1, N2 and "
            "nl_integer differ by those whole cycles (typically +-1) from software restarting "
            "the wind-up per pass; wl_integer does not"),
        "convention_integers_refer_to": ar_product or "the AR product of the table",
    }
