"""The documented integer convention (leopod.ambiguity.convention) holds in the code.

Authority: analytic constructions. Wind-up ``w`` [cycles] enters both phases as ``λ_i w``
(Wu et al. 1993), so it cancels in the HMW combination (``(f1 λ1 − f2 λ2) w/(f1 − f2) = 0``)
and enters the ionosphere-free phase as ``λ_NL w``; the POD's unwrapping
(leopod.gnss.corrections.unwrap_windup, as the observation model calls it: one track per GNSS
satellite over the whole arc) starts a later pass within half a cycle of the end of the
previous one, i.e. it carries whole cycles that a per-pass restart would not.
"""

from __future__ import annotations

import numpy as np
import pytest

from leopod.ambiguity.convention import integer_convention_attrs
from leopod.ambiguity.wide_lane import hmw_cycles
from leopod.constants import C_LIGHT_M_S
from leopod.gnss.combinations import ionosphere_free
from leopod.gnss.corrections import unwrap_windup
from leopod.signals import frequency_hz

F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")


def test_windup_carries_whole_cycles_from_one_pass_to_the_next():
    # one satellite: pass 1 at epochs 0..9, pass 2 at 20..29; true wind-up 0.3 cycles/epoch
    epochs = np.r_[np.arange(10), np.arange(20, 30)]
    true = 0.3 * epochs
    wrapped = true - np.round(true)
    out = unwrap_windup(wrapped, np.zeros(epochs.size, int), epochs)
    np.testing.assert_allclose(out[:10], true[:10], atol=1e-12)   # first value in (-0.5, 0.5]
    # pass 2 starts within half a cycle of the end of pass 1 (2.7 -> 3.0), not at the
    # true 6.0 and not restarted at wrap(6.0) = 0.0 as per-pass software would
    assert out[10] == pytest.approx(3.0)
    # the difference to the restarted wind-up is a whole number of cycles over the pass:
    # N1 and N2 of pass 2 differ by exactly k = 3 between the two conventions
    restarted = unwrap_windup(wrapped[10:], np.zeros(10, int), epochs[10:])
    assert restarted[0] == pytest.approx(0.0)
    k = out[10:] - restarted
    np.testing.assert_allclose(k, 3.0, atol=1e-12)


def test_windup_cancels_in_hmw_and_enters_if_as_narrow_lane():
    rng = np.random.default_rng(1)
    p1, p2, c1, c2 = rng.normal(2e7, 1e3, (4, 50))
    w = rng.uniform(-3, 3, 50)   # cycles, equal on both frequencies
    l1w, l2w = p1 + C_LIGHT_M_S / F1 * w, p2 + C_LIGHT_M_S / F2 * w
    np.testing.assert_allclose(hmw_cycles(l1w, l2w, c1, c2, F1, F2),
                               hmw_cycles(p1, p2, c1, c2, F1, F2), rtol=0, atol=1e-6)
    np.testing.assert_allclose(ionosphere_free(l1w, l2w, F1, F2) - ionosphere_free(p1, p2, F1, F2),
                               C_LIGHT_M_S / (F1 + F2) * w, rtol=0, atol=1e-6)


def test_convention_attributes_name_the_signals():
    attrs = integer_convention_attrs(("L1P", "L5P"), "OSB file x.bia")
    assert attrs["convention_nl_integer"] == "nl_integer = N_L1P,i - N_L1P,j (signal-1 integer)"
    assert attrs["convention_integers_refer_to"] == "OSB file x.bia"
    assert all(isinstance(v, str) for v in attrs.values())
    with pytest.raises(ValueError, match="two different phase signals"):
        integer_convention_attrs(("L1C", "L1C"))
