"""Per-frequency antenna range terms (leopod.gnss.antenna_terms) against analytic truth.

Authorities: exact geometry (the range between displaced phase centres computed as a norm,
independently of the projection the module uses), the ANTEX 1.4 sign convention (mean phase
centre = reference point + PCO; observed range = geometric range + PCV), and the coefficients
of the HMW and MP combinations (Peng et al. 2021, eqs. (1), (3)) derived by hand.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from leopod.ambiguity.wide_lane import hmw_cycles
from leopod.frames.attitude import nominal_body_axes
from leopod.gnss.antenna_terms import antenna_range_m, antenna_terms, remove_antenna_terms
from leopod.gnss.attitude import gnss_body_axes
from leopod.gnss.combinations import multipath, wide_lane_wavelength_m
from leopod.io.antex import AntennaPattern, AntexFile
from leopod.signals import frequency_hz

F1, F2 = frequency_hz("G", "L1C"), frequency_hz("G", "L2W")
T0 = np.datetime64("2020-01-01T00:00", "ns")


def _geometry(seed: int = 1, n: int = 40, s: int = 6):
    """Random LEO states (polar-ish, 7 000 km) and GNSS positions (26 600 km) above it."""
    rng = np.random.default_rng(seed)
    leo = rng.normal(size=(n, 3))
    leo *= 7.0e6 / np.linalg.norm(leo, axis=1, keepdims=True)
    vel = np.cross(leo, rng.normal(size=3))
    vel *= 7.5e3 / np.linalg.norm(vel, axis=1, keepdims=True)
    sv = rng.normal(size=(n, s, 3)) + 2.0 * leo[:, None, :] / 7.0e6
    sv *= 2.66e7 / np.linalg.norm(sv, axis=2, keepdims=True)
    sun = np.tile([1.4e11, 3.0e10, 2.0e10], (n, 1))
    return leo, vel, sv, sun


def test_leo_pco_term_is_the_exact_range_change():
    """a = |s − (r + Rᵀp)| − |s − r| to 1 µm (linearisation error ~p²/ρ), and a satellite at
    the antenna zenith sees the range shortened by the height of an antenna on the −Z face."""
    leo, vel, sv, sun = _geometry()
    pco = np.array([0.10, -0.05, -0.35])
    term = antenna_range_m(leo, vel, sv, sun, pco)
    rot = nominal_body_axes(leo, vel)
    centre = leo + np.einsum("nij,i->nj", rot, pco)
    exact = (np.linalg.norm(sv - centre[:, None, :], axis=-1)
             - np.linalg.norm(sv - leo[:, None, :], axis=-1))
    np.testing.assert_allclose(term, exact, atol=1e-6)
    zenith = leo[:1, None, :] * (2.66e7 / 7.0e6)                   # straight above the LEO
    above = antenna_range_m(leo[:1], vel[:1], zenith, sun[:1], [0.0, 0.0, -0.35])
    np.testing.assert_allclose(above, -0.35, atol=1e-9)


def _pattern(prn: str, pco_by_freq: dict, pcv_slope_m_deg: dict) -> AntennaPattern:
    zen = np.arange(0.0, 18.0, 1.0)                                # covers LEO nadirs < 16°
    return AntennaPattern(
        kind="satellite", antenna_type="BLOCK TEST", serial=prn, svn="", cospar_id="",
        valid_from=np.datetime64("NaT", "ns"), valid_until=np.datetime64("NaT", "ns"),
        zenith_deg=zen, dazi_deg=0.0, frequencies=tuple(pco_by_freq),
        pco={f: np.asarray(v, float) for f, v in pco_by_freq.items()},
        noazi={f: pcv_slope_m_deg[f] * zen for f in pco_by_freq}, grid={}, meta={})


def test_satellite_pco_and_pcv_per_frequency():
    """Transmitter term = |(s + Aᵀp_b) − r| − |s − r| + PCV_b(nadir) per frequency (ANTEX),
    with the yaw-steering axes; a satellite without an entry gets NaN."""
    leo, vel, sv, sun = _geometry(seed=2, s=2)
    p1, p2 = [0.39, 0.01, 1.0], [0.39, 0.01, 1.2]
    slope = {"G01": 1e-3, "G02": -2e-3}                            # PCV [m] per degree of nadir
    pattern = _pattern("G01", {"G01": p1, "G02": p2}, slope)
    antex = AntexFile(path=Path("test.atx"), attrs={}, antennas=[pattern])
    leo_pco = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37]}
    terms = antenna_terms(np.array([T0] * leo.shape[0]), ["G01", "G02"], leo, vel, sv, sun,
                          {"G": ["1", "2"]}, leo_pco, antex=antex)
    axes = gnss_body_axes(sv[:, 0], sun)
    los = sv[:, 0] - leo
    rho = np.linalg.norm(los, axis=-1)
    nadir = np.degrees(np.arccos(np.sum(-los / rho[:, None] * axes[:, 2], axis=-1)))
    assert nadir.max() < 17.0                                       # inside the pattern
    for band, p, freq in (("1", p1, "G01"), ("2", p2, "G02")):
        leo_only = antenna_range_m(leo, vel, sv[:, :1], sun, leo_pco[f"L{band}"])[:, 0]
        moved = sv[:, 0] + np.einsum("nij,i->nj", axes, np.asarray(p))
        sat = np.linalg.norm(moved - leo, axis=-1) - rho + slope[freq] * nadir
        np.testing.assert_allclose(terms[f"antenna_range_{band}_m"].values[:, 0],
                                   leo_only + sat, atol=1e-6)
    assert np.isnan(terms.antenna_range_1_m.values[:, 1]).all()     # G02: no ANTEX entry
    assert terms.attrs["antenna_gnss"] == "ANTEX test.atx"


def test_leo_pcv_is_added_at_the_antenna_angles():
    """A LEO PCV callable of (el, az) is added (ANTEX: observed range = range + PCV)."""
    leo, vel, sv, sun = _geometry(seed=3)
    base = antenna_range_m(leo, vel, sv, sun, [0.0, 0.0, -0.3])
    with_pcv = antenna_range_m(leo, vel, sv, sun, [0.0, 0.0, -0.3],
                               leo_pcv_m=lambda el, az: 1e-3 * np.cos(np.radians(el)))
    rot = nominal_body_axes(leo, vel)
    los = sv - leo[:, None, :]
    los /= np.linalg.norm(los, axis=-1, keepdims=True)
    el = np.arcsin(-np.einsum("nj,nsj->ns", rot[:, 2], los))
    np.testing.assert_allclose(with_pcv - base, 1e-3 * np.cos(el), atol=1e-12)


def test_removal_takes_the_analytic_term_out_of_hmw_and_mp():
    """With terms a1, a2 on both codes and phases, raw HMW − corrected HMW equals
    2 f1 f2 (a1 − a2)/((f1² − f2²) λ_WL) and raw MP1 − corrected MP1 equals
    −2 f2² (a1 − a2)/(f1² − f2²) (hand derivation from Peng et al. 2021, eqs. (1), (3))."""
    rng = np.random.default_rng(4)
    shape = (50, 3)
    coords = {"time": T0 + np.arange(50) * np.timedelta64(10, "s"), "sv": ["G01", "G02", "G03"]}
    obs = xr.Dataset({k: (("time", "sv"), rng.normal(2.2e7, 10.0, shape))
                      for k in ("C1W", "C2W", "L1C", "L2W")}, coords=coords)
    a1, a2 = rng.normal(0.0, 0.3, shape), rng.normal(0.0, 0.3, shape)
    terms = xr.Dataset({"antenna_range_1_m": (("time", "sv"), a1),
                        "antenna_range_2_m": (("time", "sv"), a2)}, coords=coords)
    out = remove_antenna_terms(obs, terms, ["L1C", "L2W", "C1W", "C2W"])

    def hmw(o):
        return hmw_cycles(o.L1C.values, o.L2W.values, o.C1W.values, o.C2W.values, F1, F2)

    def mp1(o):
        return multipath(o.C1W.values, o.L1C.values, o.L2W.values, F1, F2)

    d = F1**2 - F2**2
    np.testing.assert_allclose(hmw(obs) - hmw(out), 2 * F1 * F2 * (a1 - a2)
                               / (d * wide_lane_wavelength_m(F1, F2)), atol=1e-6)
    np.testing.assert_allclose(mp1(obs) - mp1(out), -2 * F2**2 * (a1 - a2) / d, atol=1e-6)
    # 2 cm between the bands: 0.092 WL cycles, as issue 19 states ("up to ~0.1")
    assert 2 * F1 * F2 * 0.02 / (d * wide_lane_wavelength_m(F1, F2)) == pytest.approx(0.092,
                                                                                     abs=1e-3)


def test_bad_input_names_the_field():
    leo, vel, sv, sun = _geometry(s=1)
    times = np.array([T0] * leo.shape[0])
    with pytest.raises(ValueError, match="antenna_pco_body_m has no offset for band L2"):
        antenna_terms(times, ["G01"], leo, vel, sv, sun, {"G": ["1", "2"]},
                      {"L1": [0.0, 0.0, -0.35]})
    terms = antenna_terms(times, ["G01"], leo, vel, sv, sun, {"G": ["1"]}, None)
    obs = xr.Dataset({"L5Q": (("time", "sv"), np.zeros((times.size, 1)))},
                     coords={"time": times, "sv": ["G01"]})
    with pytest.raises(KeyError, match="antenna_range_5_m for L5Q"):
        remove_antenna_terms(obs, terms, ["L5Q"])
    np.testing.assert_array_equal(terms.antenna_range_1_m.values, 0.0)   # no PCO: zero term


def test_each_system_uses_the_offsets_of_its_own_bands():
    """BDS-3 digits 1/5 take the B1C/B2a offsets, GPS 1/2 the L1/L2 ones (signal table); a
    satellite at the antenna zenith sees exactly the offset of the band."""
    leo, vel, _, sun = _geometry(s=1)
    zenith = leo[:, None, :] * (2.66e7 / 7.0e6)
    sv = np.concatenate([zenith, zenith], axis=1)                  # one GPS, one BDS-3
    pco = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37],
           "B1C": [0.0, 0.0, -0.34], "B2a": [0.0, 0.0, -0.38]}
    terms = antenna_terms(np.array([T0] * leo.shape[0]), ["G01", "C20"], leo, vel, sv, sun,
                          {"G": ["1", "2"], "C": ["1", "5"]}, pco)
    np.testing.assert_allclose(terms.antenna_range_1_m.values, [[-0.35, -0.34]] * leo.shape[0],
                               atol=1e-9)
    np.testing.assert_allclose(terms.antenna_range_2_m.values[:, 0], -0.37, atol=1e-9)
    np.testing.assert_allclose(terms.antenna_range_5_m.values[:, 1], -0.38, atol=1e-9)
    assert np.isnan(terms.antenna_range_2_m.values[:, 1]).all()
    assert np.isnan(terms.antenna_range_5_m.values[:, 0]).all()


def test_gnss_pco_follows_the_yaw_law_of_the_block():
    """The GNSS PCO term rotated by the yaw law (leopod.gnss.attitude): the family 'nominal'
    gives the yaw-steering term; 'orbit_normal' (ψ = 0, Montenbruck et al. 2015) puts body X
    along track, so the term is −e·(x T + y (Z × T) + z Z) with the orbit frame built by hand
    (exact geometry of the projection)."""
    leo, vel, sv, sun = _geometry()
    n, s = sv.shape[:2]
    sv_vel = np.cross(np.broadcast_to([0.3, -0.2, 1.0], sv.shape), sv)
    sv_vel *= 3.9e3 / np.linalg.norm(sv_vel, axis=-1, keepdims=True)
    pco = np.tile([0.394, 0.0, 1.5], (s, 1))
    nominal = antenna_range_m(leo, vel, sv, sun, np.zeros(3), sat_pco_body_m=pco)
    same = antenna_range_m(leo, vel, sv, sun, np.zeros(3), sat_pco_body_m=pco,
                           sat_family=np.full(s, "nominal"), sv_vel_m_s=sv_vel)
    np.testing.assert_allclose(same, nominal, atol=1e-9)
    normal = antenna_range_m(leo, vel, sv, sun, np.zeros(3), sat_pco_body_m=pco,
                             sat_family=np.full(s, "orbit_normal"), sv_vel_m_s=sv_vel)
    r_hat = sv / np.linalg.norm(sv, axis=-1, keepdims=True)
    h = np.cross(sv, sv_vel)
    t_hat = np.cross(h / np.linalg.norm(h, axis=-1, keepdims=True), r_hat)
    z = -r_hat
    centre = sv + 0.394 * t_hat + 1.5 * z                            # Y offset zero
    exact = (np.linalg.norm(centre - leo[:, None, :], axis=-1)
             - np.linalg.norm(sv - leo[:, None, :], axis=-1))
    np.testing.assert_allclose(normal, exact, atol=1e-6)
    assert np.abs(normal - nominal).max() > 0.1                      # the law matters
