"""Tests of leopod.gnss.signal_bias: satellite OSBs/DCBs removed from the observations.

Authorities:
- the sign of Bias-SINEX 1.00 (Schaer 2016; comment block of CODE's .BIA files): "corrected
  observation = observation − bias", and DCB(P1−C1) = OSB(C1W) − OSB(C1C) (leopod.io.dcb);
- the IGS convention for C1 receivers (IGS p1c1bias.hist, "cc2noncc"): C1 → C1 + DCB(P1−C1)
  makes C1 "compatible with modern P1";
- the datum of the real clock products: the ionosphere-free combination of the
  clock-reference code OSBs (C1W/C2W) is zero in CODE's 2023-189 and WHU's 2008-279 files, so
  removing them leaves the ionosphere-free code (and the clock) unchanged.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest
import xarray as xr

from leopod.constants import C_LIGHT_M_S
from leopod.gnss.signal_bias import (
    SignalBiases,
    SignalBiasProduct,
    correct_signal_biases,
    signal_bias_mode,
    signal_corrections_m,
)
from leopod.signals import frequency_hz

F1, F2 = frequency_hz("G", "C1W"), frequency_hz("G", "C2W")
CODE_OSB = "products_2023-189_cod_osb/COD0OPSFIN_20231890000_01D_01D_OSB.BIA"
WHU_OSB = "products_2008-279_whu/WHU0IGSFIN_20082790000_01D_01D_ABS.BIA.Z"
P1C1 = "products_2008-279_whu/P1C10810_RINEX.DCB.Z"
SIGNALS = ["C1C", "C1W", "C2W", "L1C", "L2W"]


def _osb(day: str, values_m: dict, svs=("G01", "G02")) -> xr.Dataset:
    """A Bias-SINEX dataset (schema of read_bias_sinex) with one daily window per record;
    ``values_m``: signal -> list of OSB [m] per satellite."""
    start = np.datetime64(f"{day[:4]}-01-01", "ns") + np.timedelta64(int(day[5:]) - 1, "D")
    prn, obs1, value = [], [], []
    for signal, vals in values_m.items():
        for sv, v in zip(svs, vals, strict=True):
            prn.append(sv), obs1.append(signal), value.append(v)
    n = len(prn)
    return xr.Dataset(
        {"value_m": ("bias", np.array(value)), "value_s": ("bias", np.array(value) / C_LIGHT_M_S)},
        coords={"bias_type": ("bias", ["OSB"] * n), "prn": ("bias", prn),
                "station": ("bias", [""] * n), "obs1": ("bias", obs1),
                "start": ("bias", np.full(n, start)),
                "end": ("bias", np.full(n, start + np.timedelta64(1, "D")))},
        attrs={"bias_timing": "window",
               "satellite_clock_reference_observables_G": "C1W C2W"})


def _dcb(values_ns: dict) -> xr.Dataset:
    svs = sorted(values_ns)
    return xr.Dataset({"dcb_s": ("sv", [values_ns[s] * 1e-9 for s in svs])},
                      coords={"sv": svs}, attrs={"dcb_type": "P1-C1"})


def _obs(start: str, hours: float, svs=("G01", "G02"), step_s: float = 3600.0) -> xr.Dataset:
    times = np.datetime64(start, "ns") + np.arange(int(hours * 3600 / step_s)) * np.timedelta64(
        int(step_s), "s")
    base = np.full((times.size, len(svs)), 2.0e7)
    return xr.Dataset({s: (("time", "sv"), base.copy()) for s in SIGNALS},
                      coords={"time": times, "sv": list(svs)})


def test_mode_follows_the_ar_product():
    assert signal_bias_mode(wl_bias=False, osb=True) == "absolute"
    assert signal_bias_mode(wl_bias=True, osb=True) == "clock_reference"
    assert signal_bias_mode(wl_bias=False, osb=False) == "clock_reference"


def test_absolute_mode_subtracts_the_osb_of_every_code_and_phase():
    osb = {"C1C": [1.0, -2.0], "C1W": [0.5, 0.25], "C2W": [0.8, 0.4],
           "L1C": [0.03, -0.02], "L2W": [0.01, 0.05]}
    product = SignalBiasProduct("2020-153", osb=_osb("2020-153", osb))
    corr = signal_corrections_m(product, ["G01", "G02"], SIGNALS,
                                np.datetime64("2020-06-01T12:00"), mode="absolute")
    for signal, values in osb.items():
        np.testing.assert_array_equal(corr.sel(signal=signal).values, values)
    # Schaer (2016): corrected = observed - OSB
    obs = _obs("2020-06-01T00:00", 3)
    out, _ = correct_signal_biases(obs, SignalBiases({"2020-153": product}, "absolute",
                                                     "2020-153"), SIGNALS)
    np.testing.assert_allclose(out["C1C"].values - obs["C1C"].values,
                               -np.broadcast_to(osb["C1C"], (3, 2)), rtol=0, atol=1e-8)
    np.testing.assert_allclose(out["L2W"].values - obs["L2W"].values,
                               -np.broadcast_to(osb["L2W"], (3, 2)), rtol=0, atol=1e-8)


def test_clock_reference_mode_brings_codes_to_the_reference_and_leaves_phases():
    osb = {"C1C": [1.0, -2.0], "C1W": [0.5, 0.25], "C2W": [0.8, 0.4],
           "L1C": [0.03, -0.02], "L2W": [0.01, 0.05]}
    product = SignalBiasProduct("2020-153", osb=_osb("2020-153", osb))
    corr = signal_corrections_m(product, ["G01", "G02"], SIGNALS,
                                np.datetime64("2020-06-01T12:00"), mode="clock_reference")
    np.testing.assert_allclose(corr.sel(signal="C1C").values, [1.0 - 0.5, -2.0 - 0.25])
    for signal in ("C1W", "C2W", "L1C", "L2W"):
        np.testing.assert_array_equal(corr.sel(signal=signal).values, 0.0)


def test_p1c1_dcb_gives_the_igs_c1_correction():
    """IGS cc2noncc: C1 -> C1 + DCB(P1-C1); the reference codes are untouched."""
    dcb_ns = {"G01": -0.916, "G02": 1.5}
    product = SignalBiasProduct("2020-153", dcb=(_dcb(dcb_ns),))
    obs = _obs("2020-06-01T00:00", 2)
    out, summary = correct_signal_biases(
        obs, SignalBiases({"2020-153": product}, "clock_reference", "2020-153"), SIGNALS)
    added = out["C1C"].values - obs["C1C"].values
    np.testing.assert_allclose(added[0], [-0.916e-9 * C_LIGHT_M_S, 1.5e-9 * C_LIGHT_M_S],
                               rtol=0, atol=1e-8)
    for signal in ("C1W", "C2W", "L1C", "L2W"):
        np.testing.assert_array_equal(out[signal].values, obs[signal].values)
    assert summary["C1C"]["rms_m"] == pytest.approx(
        np.sqrt((0.916**2 + 1.5**2) / 2) * 1e-9 * C_LIGHT_M_S)


def test_satellite_missing_from_the_dcb_is_dropped_not_left_biased(caplog):
    product = SignalBiasProduct("2020-153", dcb=(_dcb({"G01": 1.0}),))
    obs = _obs("2020-06-01T00:00", 2)
    with caplog.at_level(logging.WARNING):
        out, summary = correct_signal_biases(
            obs, SignalBiases({"2020-153": product}, "clock_reference", "2020-153"), SIGNALS)
    assert np.isnan(out["C1C"].sel(sv="G02")).all()
    assert np.isfinite(out["C1C"].sel(sv="G01")).all()
    assert summary["C1C"]["dropped"] == 2
    assert "set to NaN" in caplog.text


def test_each_hour_uses_its_own_days_products_joined_at_midnight(caplog):
    """A 30-h arc (21:00 of the day before to 03:00 of the day after) with different biases
    on each day: every epoch is corrected with its own day's product."""
    days = {"2020-152": [0.1, 0.2], "2020-153": [0.3, 0.4], "2020-154": [0.5, 0.6]}
    products = {d: SignalBiasProduct(d, dcb=(_dcb({"G01": v[0], "G02": v[1]}),))
                for d, v in days.items()}
    obs = _obs("2020-05-31T21:00", 30)
    out, summary = correct_signal_biases(
        obs, SignalBiases(products, "clock_reference", "2020-153"), ["C1C"])
    added_ns = (out["C1C"] - obs["C1C"]).values / C_LIGHT_M_S * 1e9
    day = obs.time.dt.strftime("%Y-%j").values
    for d, v in days.items():
        np.testing.assert_allclose(added_ns[day == d], np.broadcast_to(v, ((day == d).sum(), 2)),
                                   rtol=0, atol=1e-6)
    assert summary["days"] == {"2020-152": "2020-152", "2020-153": "2020-153",
                               "2020-154": "2020-154"}
    # campaign end: the next day's product missing -> the central day's, with a warning
    del products["2020-154"]
    biases = SignalBiases(products, "clock_reference", "2020-153")
    with caplog.at_level(logging.WARNING):
        out, summary = correct_signal_biases(obs, biases, ["C1C"])
    added_ns = (out["C1C"] - obs["C1C"]).values / C_LIGHT_M_S * 1e9
    np.testing.assert_allclose(added_ns[day == "2020-154"],
                               np.broadcast_to(days["2020-153"], ((day == "2020-154").sum(), 2)),
                               rtol=0, atol=1e-6)
    assert summary["days"]["2020-154"] == "2020-153"
    assert biases.fallbacks == ["2020-154"]
    assert "no bias products for 2020-154" in caplog.text


def test_unknown_mode_is_refused():
    with pytest.raises(ValueError, match="unknown signal-bias mode"):
        signal_corrections_m(SignalBiasProduct("2020-153"), ["G01"], ["C1C"],
                             np.datetime64("2020-06-01"), mode="relative")


@pytest.mark.shared
@pytest.mark.parametrize("path, day", [(CODE_OSB, "2023-189"), (WHU_OSB, "2008-279")])
def test_real_products_leave_the_if_reference_code_unchanged(shared_data, path, day):
    """Removing the full C1W/C2W OSBs of a real product changes the IF code by < 1 mm
    (the clock datum), while the codes themselves move by metres."""
    product = SignalBiasProduct.read(day, shared_data / path)
    svs = [f"G{i:02d}" for i in range(1, 33)]
    epoch = product.start + np.timedelta64(12, "h")
    corr = signal_corrections_m(product, svs, ["C1W", "C2W"], epoch, mode="absolute")
    ok = np.isfinite(corr.values).all(axis=1)
    assert ok.sum() >= 28
    c1, c2 = corr.sel(signal="C1W").values[ok], corr.sel(signal="C2W").values[ok]
    assert np.abs(c1).max() > 1.0
    np.testing.assert_allclose((F1**2 * c1 - F2**2 * c2) / (F1**2 - F2**2), 0.0, atol=1e-3)
    assert product.reference_codes("G") == ("C1W", "C2W")


@pytest.mark.shared
def test_whu_c1c_from_the_code_p1c1_dcb(shared_data):
    """WHU's 2008 file has no C1C OSB: OSB(C1C) = OSB(C1W) - DCB(P1-C1) with CODE's monthly
    file (P1C10810_RINEX.DCB line 8: "G01 ... -0.916"); in clock_reference mode the C1C
    correction is -DCB."""
    product = SignalBiasProduct.read("2008-279", shared_data / WHU_OSB, [shared_data / P1C1])
    epoch = product.start + np.timedelta64(12, "h")
    absolute = signal_corrections_m(product, ["G01"], ["C1C", "C1W"], epoch, mode="absolute")
    assert (absolute.sel(signal="C1C") - absolute.sel(signal="C1W")).item() == pytest.approx(
        0.916e-9 * C_LIGHT_M_S, abs=1e-9)
    relative = signal_corrections_m(product, ["G01"], ["C1C", "C1W"], epoch,
                                    mode="clock_reference")
    assert relative.sel(signal="C1C").item() == pytest.approx(0.916e-9 * C_LIGHT_M_S, abs=1e-9)
    assert relative.sel(signal="C1W").item() == 0.0


def test_a_code_no_satellite_of_a_system_observes_is_not_warned_about(caplog):
    """A combined GPS + BDS dataset holds every system's codes, the other systems' empty: the
    product missing BDS C1C (a GPS code) is no news; a code a BDS satellite does observe
    without any OSB is (the correction is left out: the user must know)."""
    svs = ("G01", "C19")
    osb = _osb("2020-153", {"C1C": [0.3, np.nan], "C1W": [0.1, np.nan],
                            "C2W": [0.2, np.nan], "L1C": [0.01, np.nan],
                            "L2W": [0.02, np.nan]}, svs=svs)
    osb = osb.isel(bias=np.flatnonzero(np.isfinite(osb.value_m.values)))
    product = SignalBiasProduct("2020-153", osb=osb)
    obs = _obs("2020-06-01T00:00", 2, svs=svs)
    for s in SIGNALS:
        obs[s].loc[{"sv": "C19"}] = np.nan          # BDS observes none of the GPS codes
    biases = SignalBiases({"2020-153": product}, "absolute", "2020-153")
    with caplog.at_level(logging.WARNING):
        correct_signal_biases(obs, biases, SIGNALS)
    assert "no OSB (nor DCB) of C" not in caplog.text
    obs["C1C"].loc[{"sv": "C19"}] = 2.0e7            # now a BDS satellite reports C1C
    caplog.clear()
    with caplog.at_level(logging.WARNING):
        correct_signal_biases(obs, biases, SIGNALS)
    assert "no OSB (nor DCB) of C C1C" in caplog.text
