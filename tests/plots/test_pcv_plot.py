"""Sky plot of a PCV map (leopod.plots.pcv): a PNG written, the same bytes twice, robust to
unestimated nodes and to a map of zeros. Authority: the map layout of leopod.antenna.pcv
(a map stacked from synthetic residuals) and the orientation of Wang et al. (2024), Fig. 6."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from leopod.antenna.pcv import PcvSettings, stack_residuals
from leopod.plots.pcv import plot_pcv_map
from leopod.workflow.config import with_defaults

pytestmark = pytest.mark.filterwarnings("error")


def _map(n: int = 20_000, **kw) -> xr.Dataset:
    rng = np.random.default_rng(2)
    az = rng.uniform(0, 360, n)
    el = np.degrees(np.arcsin(rng.uniform(0.2, 1, n)))       # nothing below ~11.5°
    r = 0.01 * np.sin(np.radians(az)) + rng.normal(0, 0.003, n)
    res = xr.Dataset({"phase_residual_m": (("time",), r), "el_deg": (("time",), el),
                      "az_deg": (("time",), az)})
    return stack_residuals([res], PcvSettings.from_config(with_defaults("pcv", kw)))


@pytest.mark.parametrize("step", [10.0, 5.0])
def test_map_figure_is_written_and_deterministic(tmp_path, step):
    m = _map(az_step_deg=step, zenith_step_deg=step, min_count=10)
    assert np.isnan(m.pcv_if_m.sel(zenith_deg=90.0)).all()        # unestimated rim
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    plot_pcv_map(m, a, title="test")
    plot_pcv_map(m, b, title="test")
    assert a.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and a.read_bytes() == b.read_bytes()


def test_map_of_zeros(tmp_path):
    m = _map()
    m["pcv_if_m"] = m.pcv_if_m * 0.0
    plot_pcv_map(m, tmp_path / "z.png")
    assert (tmp_path / "z.png").stat().st_size > 0
