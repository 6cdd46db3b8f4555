"""BDS-3 B1C/B2a through the same code path as GPS (signals are data).

A synthetic RINEX-3-schema pass of one BDS-3 satellite (codes C1P/C5P, phases L1P/L5P) is
built from geometry, ionosphere, integer ambiguities, a known code multipath on C1P and white
code noise; canonical observations must convert phases with the B1C/B2a wavelengths
(BDS-SIS-ICD: 1575.42 / 1176.45 MHz) and the quality step must recover the multipath RMS and
the noise level (analytic truth).
"""

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.gnss.quality import QualitySettings, assess_quality
from leopod.ingest import canonical_observations
from leopod.signals import signal_settings
from leopod.workflow.config import section_defaults

F1, F5 = 1575.42e6, 1176.45e6
CFG = signal_settings({"C": {"phase": ["L1P", "L5P"], "code": ["C1P", "C5P"],
                             "pod_code": ["C1P", "C5P"]}})


@pytest.fixture
def bds_pass():
    rng = np.random.default_rng(7)
    n = 400                                                   # 400 epochs of 10 s
    t = np.datetime64("2023-01-01T00:00:00", "ns") + np.arange(n) * np.timedelta64(10, "s")
    x = np.arange(n) * 10.0
    rho = 2.4e7 + 1500.0 * x - 0.3 * x**2
    iono1 = 4.0 + np.sin(x / 1200.0)
    iono5 = iono1 * (F1 / F5) ** 2
    mp1 = 0.20 * np.sin(2 * np.pi * x / 600.0)                # RMS 0.20/sqrt(2) = 0.1414 m
    sigma = 0.05
    c1 = rho + iono1 + mp1 + rng.normal(0, sigma, n)
    c5 = rho + iono5 + rng.normal(0, 0.01, n)
    l1 = (rho - iono1) / (C_LIGHT_M_S / F1) + 1234
    l5 = (rho - iono5) / (C_LIGHT_M_S / F5) - 777
    col = lambda v: (("time", "sv"), v[:, None])  # noqa: E731
    raw = xr.Dataset({"C1P": col(c1), "C5P": col(c5), "L1P": col(l1), "L5P": col(l5),
                      "L1P_lli": col(np.zeros(n, np.int8)), "L5P_lli": col(np.zeros(n, np.int8))},
                     coords={"time": t, "sv": ["C23"]},
                     attrs={"rinex_version": 3.04, "interval_s": 10.0, "filename": "synthetic"})
    return raw, mp1, sigma


def test_bds3_phases_in_metres_and_quality(bds_pass):
    raw, mp1, sigma = bds_pass
    obs = canonical_observations(raw, CFG)
    assert obs.L5P.attrs["wavelength_m"] == pytest.approx(C_LIGHT_M_S / F5)
    n = obs.sizes["time"]
    el = np.full((n, 1), 45.0)
    q = assess_quality(obs, el, np.zeros((n, 1)), "C", CFG["C"].phase, CFG["C"].code,
                       CFG["C"].pod_code, QualitySettings.from_config(section_defaults("quality")))
    assert int(q.C_n_passes) == 1 and int(q.C_n_slips) == 0
    # MP of C1P: injected multipath (zero mean over whole periods) plus noise of the
    # combination (C1P noise and the phases' 0 noise): sqrt(0.1414^2 + 0.05^2) = 0.150 m
    assert float(q.C_mp_rms_C1P_m) == pytest.approx(np.hypot(0.2 / np.sqrt(2), sigma), rel=0.05)
    # code noise: STD of epoch differences of white noise = sqrt(2) sigma
    assert float(q.C_noise_C1P_median_m) == pytest.approx(np.sqrt(2) * sigma, rel=0.15)
    assert float(q.C_noise_C5P_median_m) == pytest.approx(np.sqrt(2) * 0.01, rel=0.15)


def test_missing_configured_signal_is_named(bds_pass):
    raw, _, _ = bds_pass
    with pytest.raises(ValueError, match="C7I"):
        canonical_observations(raw, signal_settings({"C": {"phase": ["L1P", "L5P"],
                                                           "code": ["C7I"],
                                                           "pod_code": ["C1P", "C5P"]}}))


def test_merged_systems_sum_the_satellites_tracked_per_epoch():
    # two systems tracked over overlapping epochs: the merged count is the sum of both
    # (satellite ids are unique across systems), the per-satellite series are concatenated
    import numpy as np
    import xarray as xr

    from leopod.gnss.quality import merge_systems

    def part(system, svs, times, counts):
        return xr.Dataset(
            {"n_sv_tracked": (("time",), np.array(counts, np.int16)),
             "mp_C1_m": (("time", "sv"), np.zeros((len(times), len(svs)))),
             f"{system}_mp_rms_C1_m": ((), 0.3)},
            coords={"time": np.array(times, "datetime64[s]"), "sv": svs},
            attrs={"system": system, "codes": "C1" if system == "G" else "C1P",
                   "phase_pair": "L1 L2", "pod_code": "C1 C2", "interval_s": 30.0})

    g = part("G", ["G01", "G02"], ["2019-01-01T00:00:00", "2019-01-01T00:00:30"], [2, 1])
    c = part("C", ["C20"], ["2019-01-01T00:00:30", "2019-01-01T00:01:00"], [1, 1])
    merged = merge_systems([g, c])
    assert merged.n_sv_tracked.values.tolist() == [2, 2, 1]
    assert merged.sizes["sv"] == 3 and merged.attrs["systems"] == "G C"
    assert {"G_mp_rms_C1_m", "C_mp_rms_C1_m"} <= set(merged.data_vars)
    # the code-bias maps find every system's codes (leopod.codebias.period)
    assert merged.attrs["codes"].split() == ["C1", "C1P"]
    assert merged.attrs["interval_s"] == 30.0 and merged.attrs["C_pod_code"] == "C1 C2"
