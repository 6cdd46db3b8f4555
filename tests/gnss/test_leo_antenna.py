"""The LEO receiver antenna model (leopod.gnss.leo_antenna, leopod.frames.attitude antenna frame).

Authorities:
- the real ANTEX file ../shared/data/antex/GOCE_MAIN_0001.ATX (AIUB residual-method PCV of
  GOCE, Jäggi et al. 2009), values read back at grid nodes with the file's line numbers;
- ANTEX 1.4 (Rothacher & Schmid 2010), sec. 3: mean phase centre = ARP + PCO (north, east,
  up); observed range = range to the mean phase centre + PCV; receiver azimuth clockwise from
  north towards east;
- right-handed north/east/up: E = N × U (so E × N = U); exact geometry of lines of sight.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from leopod.estimation.inputs import receiver_antenna
from leopod.frames.attitude import (
    DEFAULT_ANTENNA_FRAME,
    antenna_angles,
    antenna_el_az,
    antenna_frame,
    nominal_body_axes,
)
from leopod.gnss.antenna_terms import antenna_terms
from leopod.gnss.leo_antenna import (
    LeoAntenna,
    LeoAntennaSettings,
    antex_frequency,
    leo_antenna,
    receiver_pcv_if,
)
from leopod.signals import SystemSignals

GOCE = Path(__file__).resolve().parents[3] / "shared" / "data" / "antex" / "GOCE_MAIN_0001.ATX"
needs_goce = pytest.mark.skipif(not GOCE.exists(), reason="needs ../shared/data/antex")
MM = 1e-3


@pytest.fixture(scope="module")
def goce() -> LeoAntenna:
    return leo_antenna(None, {"antex": str(GOCE), "type": "GOCE"})


# ------------------------------------------------------------------------- the antenna frame
def test_default_frame_is_north_x_up_minus_z_and_east_plus_y():
    """Defaults north = +X, up = −Z: E = N × U = X × (−Z) = +Y (right-handed NEU)."""
    frame = antenna_frame([1, 0, 0], [0, 0, -1])
    np.testing.assert_array_equal(frame, DEFAULT_ANTENNA_FRAME)
    np.testing.assert_allclose(np.cross(frame[1], frame[0]), frame[2])     # E × N = U
    assert LeoAntennaSettings.from_config({}).north_body == (1.0, 0.0, 0.0)
    assert LeoAntennaSettings.from_config({}).up_body == (0.0, 0.0, -1.0)


def test_frame_axes_must_be_orthogonal():
    with pytest.raises(ValueError, match="not orthogonal"):
        antenna_frame([1, 0, 0], [1, 0, -1])


@pytest.mark.parametrize("frame_axes", [((1, 0, 0), (0, 0, -1)), ((0, 1, 0), (1, 0, 0))])
def test_analytic_angles_in_the_antenna_frame(frame_axes):
    """A GNSS satellite straight above the boresight: zenith 0 (elevation 90); along north:
    azimuth 0; along east: azimuth 90 — for the default frame (north +X, east +Y) and a
    tilted one (north +Y, up +X: east = Y × X = −Z)."""
    frame = antenna_frame(*frame_axes)
    north, east, up = frame
    el, _ = antenna_el_az(up, frame)
    assert el == pytest.approx(90.0)
    el, az = antenna_el_az(np.stack([north, east, -north, -east]), frame)
    np.testing.assert_allclose(el, 0.0, atol=1e-12)
    np.testing.assert_allclose(az, [0.0, 90.0, 180.0, 270.0], atol=1e-12)
    # 30 deg above the horizon towards north-east
    los = np.cos(np.radians(30)) * (north + east) / np.sqrt(2) + np.sin(np.radians(30)) * up
    el, az = antenna_el_az(los, frame)
    assert el == pytest.approx(30.0) and az == pytest.approx(45.0)


def test_default_frame_angles_are_the_body_angles_bit_for_bit():
    """The default frame gives the former body-frame angles exactly (elevation above the body
    X-Y plane towards -Z, azimuth from +X towards +Y): existing outputs do not change."""
    rng = np.random.default_rng(1)
    pos = rng.normal(size=(5, 3)) * 7e6
    vel = np.cross(pos, [0.0, 0.0, 1.0])
    los = rng.normal(size=(5, 4, 3))
    rot = nominal_body_axes(pos, vel)
    el, az = antenna_angles(rot, los)
    unit = los / np.linalg.norm(los, axis=-1, keepdims=True)
    body = np.einsum("nij,nsj->nsi", rot, unit)
    np.testing.assert_array_equal(el, np.degrees(np.arcsin(np.clip(-body[..., 2], -1, 1))))
    np.testing.assert_array_equal(az, np.degrees(np.arctan2(body[..., 1], body[..., 0])) % 360)
    el2, az2 = antenna_angles(rot, los, antenna_frame([1, 0, 0], [0, 0, -1]))
    np.testing.assert_allclose(el2, el, atol=1e-12)
    np.testing.assert_allclose(az2, az, atol=1e-12)


# ----------------------------------------------------------------------- the ANTEX antenna
def test_frequency_codes_of_the_bands():
    assert [antex_frequency(b) for b in ("L1", "L2", "B1C", "B2a")] == \
        ["G01", "G02", "C01", "C05"]


@needs_goce
def test_goce_values_at_grid_nodes(goce):
    """GOCE_MAIN_0001.ATX: line 27 G01 NORTH/EAST/UP -0.18 3.51 81.11 mm; line 392 G02
    -1.22 -1.00 84.18 mm; line 29 (azimuth 0) zenith 0, 1, 2: 0.25, 1.95, -2.74 mm;
    line 30 (azimuth 1) zenith 1, 2: 2.08, 2.65 mm; line 119 (azimuth 90) zenith 1: -1.89 mm."""
    np.testing.assert_allclose(goce.pco_neu_m("L1"), [-0.18 * MM, 3.51 * MM, 81.11 * MM])
    np.testing.assert_allclose(goce.pco_neu_m("L2"), [-1.22 * MM, -1.00 * MM, 84.18 * MM])
    np.testing.assert_allclose(goce.pcv_m("L1", [0.0, 1.0, 2.0], 0.0),
                               [0.25 * MM, 1.95 * MM, -2.74 * MM], atol=1e-12)
    np.testing.assert_allclose(goce.pcv_m("L1", [1.0, 2.0], 1.0), [2.08 * MM, 2.65 * MM],
                               atol=1e-12)
    assert goce.pcv_m("L1", 1.0, 90.0) == pytest.approx(-1.89 * MM, abs=1e-12)
    # bilinear between nodes (paper 001 eqs. 7-9): the mean of the four corners at the centre
    assert goce.pcv_m("L1", 1.5, 0.5) == pytest.approx(
        (1.95 + 2.08 - 2.74 + 2.65) / 4 * MM, abs=1e-12)
    assert sorted(goce) == ["L1", "L2"]
    assert "B1C" not in goce
    with pytest.raises(KeyError, match="C01"):
        goce.pcv_m("B1C", 0.0, 0.0)


@needs_goce
def test_phase_centre_in_the_body_frame_is_arp_plus_rotated_pco():
    """Phase centre = ARP + R_ant PCO(N, E, U): default frame (N, E, U) -> body (N, E, −U);
    flying backwards (north −X, up −Z, so east = −X × −Z = −Y) -> body (−N, −E, −U)."""
    arp = [0.1, -0.2, -0.5]
    neu = np.array([-0.18, 3.51, 81.11]) * MM
    ant = leo_antenna(None, {"antex": str(GOCE), "type": "GOCE", "arp_body_m": arp})
    np.testing.assert_allclose(ant["L1"], np.add(arp, [neu[0], neu[1], -neu[2]]), atol=1e-15)
    back = leo_antenna(None, {"antex": str(GOCE), "type": "GOCE", "arp_body_m": arp,
                              "north_body": [-1, 0, 0]})
    np.testing.assert_allclose(back.pco_body_m("L1"), np.add(arp, -neu), atol=1e-15)


@needs_goce
def test_both_antenna_definitions_are_refused():
    with pytest.raises(ValueError, match="either antenna_pco_body_m"):
        leo_antenna({"L1": [0, 0, -0.3], "L2": [0, 0, -0.3]},
                    {"antex": str(GOCE), "type": "GOCE"})
    with pytest.raises(ValueError, match="needs the antenna 'type'"):
        leo_antenna(None, {"antex": str(GOCE)})
    # without antex the PCO table is the antenna, as before
    table = {"L1": [0, 0, -0.3]}
    assert leo_antenna(table, {}) is table


@needs_goce
def test_ionosphere_free_pcv(goce):
    """(f1² PCV1 − f2² PCV2)/(f1² − f2²): the GOCE file fills both frequencies with the same
    ionosphere-free values (its header), so the combination gives them back."""
    f = receiver_pcv_if(goce, "G", ("L1C", "L2W"))
    el, az = np.array([90.0, 60.0, 20.0]), np.array([0.0, 123.0, 271.0])
    np.testing.assert_allclose(f(el, az), goce.pcv_m("L1", 90.0 - el, az), atol=1e-12)
    sig = SystemSignals.from_config({"phase": ["L1C", "L2W"], "code": ["C1W", "C2W"],
                                     "pod_code": ["C1W", "C2W"]})
    model = receiver_antenna(goce, ["G01", "G02"], {"G": sig})
    np.testing.assert_allclose(model.pcv_if_m(np.array([0, 1, 1]), el, az), f(el, az))
    assert receiver_antenna({"L1": [0, 0, 0]}, ["G01"], {"G": sig}) is None


@needs_goce
def test_per_frequency_terms_add_the_pcv_at_the_antenna_angles(goce):
    """antenna_terms with the ANTEX antenna = with its PCO table + PCV_b(zenith, azimuth)
    (ANTEX 1.4: observed range = range to the mean phase centre + PCV)."""
    rng = np.random.default_rng(3)
    n, s = 20, 5
    leo = rng.normal(size=(n, 3))
    leo *= 7.0e6 / np.linalg.norm(leo, axis=1, keepdims=True)
    vel = np.cross(leo, [0.3, 0.2, 1.0])
    vel *= 7.5e3 / np.linalg.norm(vel, axis=1, keepdims=True)
    sv = rng.normal(size=(n, s, 3)) + 2.0 * leo[:, None, :] / 7.0e6
    sv *= 2.66e7 / np.linalg.norm(sv, axis=2, keepdims=True)
    sun = np.tile([1.4e11, 3.0e10, 2.0e10], (n, 1))
    times = np.datetime64("2020-01-01", "ns") + np.arange(n) * np.timedelta64(10, "s")
    svs = [f"G{j + 1:02d}" for j in range(s)]
    bands = {"G": ["1", "2"]}
    with_pcv = antenna_terms(times, svs, leo, vel, sv, sun, bands, goce)
    pco_only = antenna_terms(times, svs, leo, vel, sv, sun, bands, dict(goce))
    el, az = antenna_angles(nominal_body_axes(leo, vel), sv - leo[:, None, :])
    np.testing.assert_allclose(
        with_pcv.antenna_range_1_m.values - pco_only.antenna_range_1_m.values,
        goce.pcv_m("L1", 90.0 - el, az), atol=1e-12)
    assert "GOCE" in with_pcv.attrs["antenna_leo_antex"]
