"""Signal table and dual-frequency combinations.

Authorities: carrier frequencies from IS-GPS-200 (L1 = 154 f0, L2 = 120 f0), IS-GPS-705
(L5 = 115 f0), BDS-SIS-ICD B1C/B2a/B1I/B3I; combinations checked against analytic truth on
synthetic observations built from geometry, ionosphere, ambiguities and multipath.
"""

import numpy as np
import pytest

from leopod import signals
from leopod.constants import C_LIGHT_M_S
from leopod.gnss.combinations import (
    geometry_free,
    ionosphere_free,
    ionosphere_l1_m,
    melbourne_wuebbena,
    multipath,
    narrow_lane_wavelength_m,
    wide_lane_wavelength_m,
)


@pytest.mark.parametrize("system,key,f_mhz", [
    ("G", "C1C", 1575.42), ("G", "L2W", 1227.60), ("G", "L5", 1176.45),
    ("C", "C1P", 1575.42), ("C", "B2a", 1176.45), ("C", "C2I", 1561.098), ("C", "C6I", 1268.52),
    ("E", "C5Q", 1176.45), ("E", "E5b", 1207.14),
])
def test_frequencies_from_icds(system, key, f_mhz):
    assert signals.frequency_hz(system, key) == pytest.approx(f_mhz * 1e6, abs=1e-3)


def test_rinex2_mapping_and_unknown_band():
    assert signals.rinex3_code("G", "P1") == "C1W"
    assert signals.rinex3_code("G", "L2") == "L2W"
    assert signals.rinex3_code("G", "C1C") == "C1C"
    with pytest.raises(KeyError, match="unknown band '9'"):
        signals.band("G", "9")
    with pytest.raises(KeyError, match="RINEX 2 observation 'Q7'"):
        signals.rinex3_code("G", "Q7")


def test_wavelengths_gps():
    # analytic: c/(f1-f2) = 0.8619 m, c/(f1+f2) = 0.1070 m for GPS L1/L2
    f1, f2 = signals.frequency_hz("G", "1"), signals.frequency_hz("G", "2")
    assert wide_lane_wavelength_m(f1, f2) == pytest.approx(C_LIGHT_M_S / (347.82e6), rel=1e-12)
    assert wide_lane_wavelength_m(f1, f2) == pytest.approx(0.8619, abs=1e-4)
    assert narrow_lane_wavelength_m(f1, f2) == pytest.approx(0.1070, abs=1e-4)


@pytest.fixture
def synthetic():
    """Observations from geometry, L1 ionosphere, integer ambiguities and code multipath."""
    rng = np.random.default_rng(1)
    f1, f2 = signals.frequency_hz("C", "B1C"), signals.frequency_hz("C", "B2a")
    lam1, lam2 = C_LIGHT_M_S / f1, C_LIGHT_M_S / f2
    n = 200
    rho = 2.2e7 + np.cumsum(rng.normal(0, 50, n))
    iono1 = 3.0 + np.linspace(0, 2, n)
    iono2 = iono1 * (f1 / f2) ** 2
    n1, n2 = 123456, -98765
    mp1 = 0.3 * np.sin(np.linspace(0, 6, n))
    code1 = rho + iono1 + mp1
    code2 = rho + iono2
    phase1 = rho - iono1 + lam1 * n1
    phase2 = rho - iono2 + lam2 * n2
    return dict(f1=f1, f2=f2, lam1=lam1, lam2=lam2, rho=rho, iono1=iono1, n1=n1, n2=n2,
                mp1=mp1, code1=code1, code2=code2, phase1=phase1, phase2=phase2)


def test_ionosphere_free_removes_ionosphere(synthetic):
    s = synthetic
    code_if = ionosphere_free(s["code1"] - s["mp1"], s["code2"], s["f1"], s["f2"])
    assert np.max(np.abs(code_if - s["rho"])) < 1e-6


def test_melbourne_wuebbena_is_wide_lane_ambiguity(synthetic):
    s = synthetic
    mw = melbourne_wuebbena(s["phase1"], s["phase2"], s["code1"] - s["mp1"], s["code2"],
                            s["f1"], s["f2"])
    # analytic: MW = lambda_WL * (N1 - N2) when code is free of errors
    lam_wl = wide_lane_wavelength_m(s["f1"], s["f2"])
    assert np.allclose(mw / lam_wl, s["n1"] - s["n2"], atol=1e-6)


def test_multipath_recovers_code_error_up_to_a_constant(synthetic):
    s = synthetic
    mp = multipath(s["code1"], s["phase1"], s["phase2"], s["f1"], s["f2"])
    d = mp - s["mp1"]
    assert np.ptp(d) < 1e-6   # constant: ambiguity terms only (Peng et al. 2021, eq. 1)


def test_ionosphere_rate_sign_and_scale(synthetic):
    s = synthetic
    ion = ionosphere_l1_m(s["phase1"], s["phase2"], s["f1"], s["f2"])
    # time variation equals that of the true L1 delay (ambiguities are constant)
    assert np.allclose(np.diff(ion), np.diff(s["iono1"]), atol=1e-7)
    assert np.allclose(geometry_free(s["phase1"], s["phase2"]) - (s["phase1"] - s["phase2"]), 0)


def test_system_of_reads_the_rinex3_letter_of_any_shape():
    # RINEX 3.05 sec. 3.5: the satellite id is the system letter followed by the PRN
    from leopod.signals import system_of

    assert system_of(["G07", "C19", "E11"]).tolist() == ["G", "C", "E"]
    assert system_of(np.array([["G01"], ["C45"]])).tolist() == ["G", "C"]
    assert system_of("G05").tolist() == ["G"]
