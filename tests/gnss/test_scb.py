"""BDS-2 satellite-induced code bias: the Wanninger & Beer (2015) table and its argument.

Authorities: the published table (Wanninger L, Beer S 2015, GPS Solutions 19:639-648, Table 2:
corrections [m] at 0°, 10°, ..., 90° elevation, linear interpolation between the nodes, as
the BDS SCB-AR paper applies it), transcribed below independently of the module; and plane
geometry for the nadir angle of a ground receiver, sin η = (R / r) cos e.
"""

import numpy as np
import pytest

from leopod.gnss.scb import (
    BDS2_ORBIT_TYPE,
    bds2_scb_m,
    equivalent_elevation_deg,
    nadir_angle_deg,
    scb_band,
    scb_correction_m,
)

#: Wanninger & Beer (2015), Table 2, rows per satellite type and frequency [m].
PUBLISHED = {
    ("IGSO", "B1"): [-0.55, -0.40, -0.34, -0.23, -0.15, -0.04, 0.09, 0.19, 0.27, 0.35],
    ("IGSO", "B2"): [-0.71, -0.36, -0.33, -0.19, -0.14, -0.03, 0.08, 0.17, 0.24, 0.33],
    ("IGSO", "B3"): [-0.27, -0.23, -0.21, -0.15, -0.11, -0.04, 0.05, 0.14, 0.19, 0.32],
    ("MEO", "B1"): [-0.47, -0.38, -0.32, -0.23, -0.11, 0.06, 0.34, 0.69, 0.97, 1.05],
    ("MEO", "B2"): [-0.40, -0.31, -0.26, -0.18, -0.06, 0.09, 0.28, 0.48, 0.64, 0.69],
    ("MEO", "B3"): [-0.22, -0.15, -0.13, -0.10, -0.04, 0.05, 0.14, 0.27, 0.36, 0.47],
}
NODES = np.arange(0.0, 91.0, 10.0)
R_EARTH = 6_371_008.8


@pytest.mark.parametrize("key", sorted(PUBLISHED), ids=lambda k: "-".join(k))
def test_model_reproduces_the_published_table_at_the_nodes(key):
    np.testing.assert_allclose(scb_correction_m(*key, NODES), PUBLISHED[key], atol=1e-12)


@pytest.mark.parametrize("key", sorted(PUBLISHED), ids=lambda k: "-".join(k))
def test_model_interpolates_linearly_between_the_nodes(key):
    table = np.array(PUBLISHED[key])
    # a quarter and the middle of every interval: (3 v_k + v_k+1)/4 and (v_k + v_k+1)/2
    quarter = NODES[:-1] + 2.5
    middle = NODES[:-1] + 5.0
    np.testing.assert_allclose(scb_correction_m(*key, quarter),
                               0.75 * table[:-1] + 0.25 * table[1:], atol=1e-12)
    np.testing.assert_allclose(scb_correction_m(*key, middle),
                               0.5 * (table[:-1] + table[1:]), atol=1e-12)
    # below the horizon the 0° value; NaN stays NaN
    out = scb_correction_m(*key, [-5.0, np.nan])
    assert out[0] == table[0] and np.isnan(out[1])


def test_bad_table_arguments_are_named():
    with pytest.raises(ValueError, match="GEO"):
        scb_correction_m("GEO", "B1", 30.0)
    with pytest.raises(ValueError, match="B1C"):
        scb_correction_m("MEO", "B1C", 30.0)
    with pytest.raises(ValueError, match="elevation outside"):
        scb_correction_m("MEO", "B1", 95.0)
    with pytest.raises(ValueError, match="RINEX 3"):
        scb_band("C2")
    with pytest.raises(ValueError, match="nadir angle outside"):
        equivalent_elevation_deg(-1.0, 27.9e6)
    with pytest.raises(ValueError, match="radius"):
        equivalent_elevation_deg(5.0, 6.0e6)


@pytest.mark.parametrize("r_sv", [27_906e3, 42_164e3])
@pytest.mark.parametrize("el_deg", [0.0, 7.0, 25.0, 48.0, 71.0, 90.0])
def test_ground_receiver_nadir_angle_maps_back_to_its_elevation(r_sv, el_deg):
    """A receiver on the sphere of radius R sees a satellite at elevation e: the nadir angle
    at the satellite, computed from the two positions, maps back to e (sin η = R/r cos e)."""
    rx = np.array([R_EARTH, 0.0, 0.0])
    # the satellite along the direction of elevation e in the x-y plane, at radius r_sv
    e = np.radians(el_deg)
    up, horizon = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    u = np.cos(e) * horizon + np.sin(e) * up
    dist = -R_EARTH * np.sin(e) + np.sqrt(r_sv**2 - (R_EARTH * np.cos(e)) ** 2)
    sv = rx + dist * u
    assert np.linalg.norm(sv) == pytest.approx(r_sv, rel=1e-12)
    eta = nadir_angle_deg(sv, rx)
    assert np.sin(np.radians(eta)) == pytest.approx(R_EARTH / r_sv * np.cos(e), abs=1e-12)
    assert equivalent_elevation_deg(eta, r_sv) == pytest.approx(el_deg, abs=1e-6)


def test_leo_beyond_the_limb_takes_the_zero_node():
    """A LEO at 500 km seen from a MEO at more than the limb's nadir angle: e* = 0."""
    r_sv = 27_906e3
    limb = np.degrees(np.arcsin(R_EARTH / r_sv))
    leo_edge = np.degrees(np.arcsin((R_EARTH + 500e3) / r_sv))
    assert equivalent_elevation_deg([limb + 0.5 * (leo_edge - limb)], r_sv)[0] == 0.0
    assert scb_correction_m("MEO", "B1", equivalent_elevation_deg(leo_edge, r_sv)) == \
        pytest.approx(PUBLISHED["MEO", "B1"][0])


def test_only_bds2_igso_meo_codes_on_b1i_b2i_b3i_are_corrected():
    svs = ["C01", "C06", "C11", "C23", "G05"]           # GEO, IGSO, MEO, BDS-3, GPS
    nadir = np.full((2, len(svs)), 0.0)                 # nadir 0: e* = 90° (zenith node)
    for code, band in (("C2I", "B1"), ("C7I", "B2"), ("C6I", "B3")):
        out = bds2_scb_m(svs, code, nadir)
        np.testing.assert_allclose(out[:, 1], PUBLISHED["IGSO", band][-1])
        np.testing.assert_allclose(out[:, 2], PUBLISHED["MEO", band][-1])
        assert not out[:, [0, 3, 4]].any()
    assert not bds2_scb_m(svs, "C1P", nadir).any()       # B1C: not a BDS-2 signal
    assert {BDS2_ORBIT_TYPE[s] for s in ("C13", "C16", "C14")} == {"IGSO", "MEO"}
    with pytest.raises(ValueError, match="columns"):
        bds2_scb_m(svs, "C2I", nadir[:, :2])
