"""Tests of leopod.dynamics.plates: macro models from the campaign and their attitude.

Authorities: the GRACE macro model of the GRACE Product Specification Document (Bettadpur
2012) as repeated, for the identical GRACE-FO geometry, by Siemes et al. (2023, J. Space
Weather Space Clim. 13, 16, Table A3: areas, normals, visible absorption 1 − ρs − ρd and
infrared absorption ε); the attitude law evaluated directly
(:func:`leopod.frames.leo_attitude.leo_body_axes`) for the tabulated attitude; the campaign
schema for the configuration.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from leopod.constants import GM_EARTH_M3_S2
from leopod.dynamics.environment import ArcEnvironment
from leopod.dynamics.plates import (
    GRACE_PLATES,
    Plates,
    grace_macro_model,
    macro_model_from_config,
)
from leopod.frames.leo_attitude import LeoAttitude, leo_body_axes
from leopod.workflow.config import validated

RADIUS_M = 6858e3
CONFIG = Path(__file__).resolve().parents[2] / "config" / "grace-a-2007.yaml"


def test_grace_macro_model_against_the_published_table():
    """Areas, normals and absorptions of Siemes et al. (2023, Table A3) for the body, the
    nadir and zenith panels and the horn; the outer arrays carry the GRACE coefficients
    (0.65 / 0.81; that table's GRACE-FO arrays differ)."""
    m = grace_macro_model(480.0)
    assert m.area_m2.size == 12 and m.mass_kg == 480.0
    np.testing.assert_allclose(np.linalg.norm(m.normal_body, axis=1), 1.0, atol=1e-6)
    published = {  # area, normal, visible absorption, infrared absorption
        "front": (0.9551567, (1, 0, 0), 0.34, 0.62),
        "rear": (0.9551567, (-1, 0, 0), 0.34, 0.62),
        "nadir": (6.0711120, (0, 0, 1), 0.12, 0.75),
        "zenith": (2.1673620, (0, 0, -1), 0.65, 0.81),
        "port inner": (0.2282913, (0, 0.766044, 0.642787), 0.34, 0.62),
        "starboard inner": (0.2282913, (0, -0.766044, 0.642787), 0.34, 0.62),
        "horn front": (0.0461901, (1, 0, 0), 0.34, 0.62),
    }
    names = [p[0] for p in GRACE_PLATES]
    for name, (area, normal, vis, ir) in published.items():
        i = names.index(name)
        assert m.area_m2[i] == area
        np.testing.assert_allclose(m.normal_body[i], normal, atol=1e-6)
        assert 1.0 - m.specular[i] - m.diffuse[i] == pytest.approx(vis, abs=1e-12)
        assert 1.0 - m.specular_ir[i] - m.diffuse_ir[i] == pytest.approx(ir, abs=1e-12)
    # infrared reflectance split as in the visible (module docstring)
    i = names.index("front")
    assert m.specular_ir[i] / m.diffuse_ir[i] == pytest.approx(0.40 / 0.26)


def test_macro_model_from_config_and_its_errors():
    """Plates of a campaign: emissivity null = grey; errors name the plate and the field."""
    section = {"mass_kg": 100.0, "plates": [
        {"normal_body": [1, 0, 0], "area_m2": 1.0, "specular": 0.2, "diffuse": 0.3},
        {"normal_body": [0, 2, 0], "area_m2": 2.0, "specular": 0.0, "diffuse": 0.5,
         "emissivity": 0.8, "drag_coefficient": 2.0, "sun_tracking": 1}]}
    m = macro_model_from_config(section)
    np.testing.assert_allclose(m.normal_body[1], [0, 1, 0])
    np.testing.assert_allclose(m.specular_ir, [0.2, 0.0])
    np.testing.assert_allclose(m.diffuse_ir, [0.3, 0.2])
    np.testing.assert_allclose(m.drag_coefficient, [2.3, 2.0])
    np.testing.assert_array_equal(m.panel, [0, 1])
    assert macro_model_from_config(None) is None
    bad = {"mass_kg": 100.0, "plates": [section["plates"][0],
                                         {"normal_body": [1, 0, 0], "area_m2": 1.0,
                                          "specular": 0.7, "diffuse": 0.5}]}
    with pytest.raises(ValueError, match=r"macro_model\.plates\[1\].*specular \+ diffuse"):
        macro_model_from_config(bad)
    with pytest.raises(ValueError, match=r"plates\[0\].*area_m2"):
        macro_model_from_config({"mass_kg": 1.0, "plates": [{"normal_body": [1, 0, 0],
                                                               "specular": 0, "diffuse": 0}]})
    with pytest.raises(ValueError, match="either builtin or plates"):
        macro_model_from_config({"mass_kg": 1.0, "builtin": "grace", **section})
    with pytest.raises(ValueError, match="mass_kg"):
        macro_model_from_config({"builtin": "grace"})


def test_schema_accepts_the_macro_model():
    """satellites.<sat>.macro_model defaults to null; a built-in model and the plates flags
    of pod.forces validate, with their defaults filled (the schema is the only source)."""
    cfg = yaml.safe_load(CONFIG.read_text())
    assert validated(cfg)["satellites"]["grace-a"]["macro_model"] is None
    cfg["satellites"]["grace-a"]["macro_model"] = {"builtin": "grace", "mass_kg": 480.0}
    cfg["pod"]["forces"]["srp"]["plates"] = True
    cfg["pod"]["forces"]["earth_radiation"] = {"plates": True}
    out = validated(cfg)
    assert out["satellites"]["grace-a"]["macro_model"]["drag_coefficient"] == 2.3
    assert out["pod"]["forces"]["earth_radiation"]["rings"] == 2
    assert out["pod"]["forces"]["drag"]["plates"] is False


def _circular(t_s):
    n = np.sqrt(GM_EARTH_M3_S2 / RADIUS_M**3)
    u = n * np.atleast_1d(np.asarray(t_s, dtype=float))
    inc = np.radians(89.0)
    return RADIUS_M * np.column_stack([np.cos(u), np.sin(u) * np.cos(inc),
                                       np.sin(u) * np.sin(inc)])


@pytest.mark.parametrize("offset", [{}, {"yaw_deg": 180.0, "pitch_deg": -0.9}])
def test_tabulated_attitude_equals_the_law(offset):
    """Plate normals from the 10-s attitude table equal those of the law on the reference
    orbit: at the nodes to 1e-14, between them to 1e-10 (degree-7 interpolation of the
    smooth nominal rotation)."""
    env = ArcEnvironment(np.datetime64("2007-03-21T00:00", "ns"), 0.0, 7200.0)
    law = LeoAttitude.of({"attitude_offset": offset})
    model = grace_macro_model(480.0)
    plates = Plates(model, law, env)
    assert not plates.ready
    plates.follow(_circular)
    for t, tol in ((1000.0, 1e-14), (1234.567, 1e-10), (7195.0, 1e-10)):
        pos = _circular(t)[0]
        vel = (_circular(t + 1.0)[0] - _circular(t - 1.0)[0]) / 2.0
        axes = leo_body_axes(law, pos[None], vel[None], env.sun_m(t))[0]
        got = plates.normals(t, pos, env.sun_m(t)[0])
        np.testing.assert_allclose(got, model.normal_body @ axes, atol=tol)
    # nominal: the nadir plate (+Z) points to the geocentre
    if not offset:
        nadir = plates.normals(500.0, _circular(500.0)[0], env.sun_m(500.0)[0])[6]
        np.testing.assert_allclose(nadir, -_circular(500.0)[0] / RADIUS_M, atol=1e-9)
