"""The closed loop of the residual-method PCV (leopod.antenna.pcv) on a simulated arc.

Observations simulated WITH the real GOCE pattern (../shared/data/antex/GOCE_MAIN_0001.ATX,
Jäggi et al. 2009: ionosphere-free values filled in for both frequencies, -3 to +1 cm) and the
default HY-2B-like day of tests/estimation/_simulated_arc.py; float POD WITHOUT any PCV (its
PCO as the body-frame table), the residual map stacked, the POD repeated with the estimated
ANTEX antenna (PCO + map), ``iterations`` times (Wang et al. 2024: three).

The truth of a map at a resolution is the true ionosphere-free PCV at the directions of the
residuals stacked as the residuals are (cell means, or the bilinear fit: what a perfect POD
would give); the true pattern sampled at the nodes is reported beside it (the GOCE pattern
varies within a 10° cell by several mm).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "estimation"))

from _bds3_arc import orbit_rms_3d_m  # noqa: E402
from _simulated_arc import DAY, SAT, float_pod_arc, goce_world  # noqa: E402

from leopod.antenna.pcv import (  # noqa: E402
    PcvSettings,
    estimated_antenna,
    map_rms_m,
    stack_residuals,
)
from leopod.gnss.leo_antenna import receiver_pcv_if  # noqa: E402
from leopod.simulate.campaign import simulate_leo_day  # noqa: E402
from leopod.workflow.config import with_defaults  # noqa: E402

PAIR = ("L1C", "L2W")


def _if_pcv(antenna):
    f = receiver_pcv_if(antenna, "G", PAIR)
    return f if f is not None else (lambda el, az: np.zeros(np.shape(el)))


def _truth_cell_means(residuals: xr.Dataset, goce, settings: PcvSettings) -> xr.Dataset:
    """The true IF PCV stacked as residuals at the directions of the used residuals."""
    res = residuals.copy()
    used = np.isfinite(res.phase_residual_m.values)
    true = np.full(used.shape, np.nan)
    true[used] = _if_pcv(goce)(res.el_deg.values[used], res.az_deg.values[used])
    res["phase_residual_m"] = (("time", "sv"), true)
    return stack_residuals([res], settings)


def pcv_loop(folder: Path, *, hours=(1.0, 5.0), steps=(10.0, 10.0), min_count: int = 30,
             iterations: int = 3, estimator: str = "bilinear") -> dict:
    """Run the loop; figures in a dict (module docstring): ``orbit_3d_m`` per case
    (``none``, ``true``, ``estimated_<k>``), ``map_rms_m``, ``map_rms_nodes_m`` and
    ``map_rms_pco_z_m`` (a PCO-Z-like cos z removed too) per iteration, ``maps``,
    ``truth_map``, ``seconds``."""
    clock = time.perf_counter()
    world = goce_world(folder)
    cfg, goce, pco_only, sim = world.cfg, world.antenna, world.pco_only, world.sim
    truth, biases = world.truth, world.biases
    simulate_leo_day(DAY, SAT, sim, DAY, DAY, truth, biases, goce, rinex3=folder / "pcv.rnx",
                     truth_sp3=folder / "pcv.sp3", truth_nc=folder / "pcv.nc")
    with xr.open_dataset(folder / "pcv.nc") as f:
        truth_day = f.load()
    settings = PcvSettings.from_config(with_defaults("pcv", {
        "az_step_deg": steps[0], "zenith_step_deg": steps[1], "min_count": min_count,
        "estimator": estimator}))
    out = {"orbit_3d_m": {}, "map_rms_m": [], "map_rms_nodes_m": [], "map_rms_pco_z_m": [],
           "maps": []}
    arc = float_pod_arc(folder, cfg, "pcv.rnx", goce, hours)
    out["orbit_3d_m"]["true"] = orbit_rms_3d_m(arc.orbit, truth_day)
    antenna = pco_only
    arc = float_pod_arc(folder, cfg, "pcv.rnx", antenna, hours)
    out["orbit_3d_m"]["none"] = orbit_rms_3d_m(arc.orbit, truth_day)
    truth_map = _truth_cell_means(arc.residuals, goce, settings)
    zz, aa = np.meshgrid(truth_map.zenith_deg.values, truth_map.azimuth_deg.values)
    truth_nodes = _if_pcv(goce)(90.0 - zz, aa)
    for k in range(1, iterations + 1):
        delta = stack_residuals([arc.residuals], settings, satellite=SAT, period=DAY,
                                solution="float_pod")
        antenna = estimated_antenna(antenna, delta)
        total = delta.copy()
        total["pcv_if_m"] = (delta.pcv_if_m.dims, _if_pcv(antenna)(90.0 - zz, aa))
        total["count"] = truth_map["count"]
        out["maps"].append(total)
        out["map_rms_m"].append(map_rms_m(total, truth_map.pcv_if_m.values,
                                          min_count=min_count))
        out["map_rms_nodes_m"].append(map_rms_m(total, truth_nodes, min_count=min_count))
        out["map_rms_pco_z_m"].append(map_rms_m(total, truth_map.pcv_if_m.values,
                                                min_count=min_count, pco_z=True))
        arc = float_pod_arc(folder, cfg, "pcv.rnx", antenna, hours)
        out["orbit_3d_m"][f"estimated_{k}"] = orbit_rms_3d_m(arc.orbit, truth_day)
    out["truth_map"] = truth_map
    out["seconds"] = time.perf_counter() - clock
    return out
