"""One simulated campaign day written to a folder (shared by the tests of tests/simulate)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from leopod.simulate.campaign import (
    simulate_gnss_products,
    simulate_leo_day,
    simulate_truth,
    simulate_world_truth,
)
from leopod.simulate.settings import SimulationSettings
from leopod.workflow.config import with_defaults

DAY = "2019-001"
SAT = "hy2b-sim"
#: LEO antenna offsets per band in the body frame [m] (GPS L1/L2, BDS-3 B1C/B2a).
PCO = {"L1": [0.0, 0.0, -0.35], "L2": [0.0, 0.0, -0.37], "B1C": [0.0, 0.0, -0.35],
       "B2a": [0.0, 0.0, -0.37]}
#: The simulate section of the tests: the schema's defaults with a degree-30 truth field
#: (the observations do not depend on the degree; it halves the cost of the truth orbit).
SECTION = {"truth": {"gravity_degree": 30}}


def simulation(section: Mapping = SECTION) -> SimulationSettings:
    """Settings of a (partial) simulate section completed by the campaign schema."""
    return SimulationSettings.from_config(with_defaults("simulate", section))


SETTINGS = simulation()


@dataclass
class Day:
    """Paths and in-memory results of one simulated day."""

    folder: Path
    settings: SimulationSettings
    truth: xr.Dataset
    biases: xr.Dataset
    obs: xr.Dataset

    def path(self, name: str) -> Path:
        return self.folder / name


def write_products(folder: Path, settings: SimulationSettings, biases: xr.Dataset) -> None:
    simulate_gnss_products(DAY, settings, DAY, DAY, biases, orbit=folder / "g.sp3",
                           clock=folder / "g.clk", integer_clock=folder / "g_int.clk",
                           wl_bias=folder / "g.wsb", osb=folder / "g.bia")


def write_leo(folder: Path, settings: SimulationSettings, truth: xr.Dataset,
              biases: xr.Dataset) -> xr.Dataset:
    return simulate_leo_day(DAY, SAT, settings, DAY, DAY, truth, biases, PCO,
                            rinex3=folder / "o.rnx", rinex2=folder / "o.obs",
                            truth_sp3=folder / "t.sp3", truth_nc=folder / "t.nc",
                            crd=folder / "o.crd")


def simulate_day(folder: Path, settings: SimulationSettings = SETTINGS,
                 truth: xr.Dataset | None = None) -> Day:
    """Truth orbit, world truth, GNSS products and the LEO files of :data:`DAY`."""
    folder.mkdir(parents=True, exist_ok=True)
    truth = simulate_truth(settings, SAT, DAY, DAY) if truth is None else truth
    biases = simulate_world_truth(settings, [SAT], DAY, DAY, biases_path=folder / "b.nc",
                                  stations_path=folder / "s.snx")
    write_products(folder, settings, biases)
    obs = write_leo(folder, settings, truth, biases)
    return Day(folder=folder, settings=settings, truth=truth, biases=biases, obs=obs)
