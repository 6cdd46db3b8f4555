# Configuration check and small input helpers; the logic lives in leopod.workflow.campaign (tested).
import re
from pathlib import Path

from snakemake.utils import validate

from leopod.workflow.downloads import (destination_template, load_catalogue, resolve_downloads,
    uses_downloads)
from leopod.simulate.product_world import ProductSet

from leopod.workflow.campaign import (applied_code_bias_period, arc_days, campaign_days,
    code_bias_periods, expand_template, locate_inputs, located_source, period_days, satellite_ids,
    script_library_files)


validate(config, "../schemas/config.schema.yaml", set_default=True)

DEFAULT_CATALOGUE = f"{workflow.basedir}/config/catalogue.yaml"
if uses_downloads(config):
    CATALOGUE = load_catalogue(config["download"], DEFAULT_CATALOGUE)
    _resolved, DOWNLOADS = resolve_downloads(config, CATALOGUE)
    config.update(_resolved)
else:
    CATALOGUE, DOWNLOADS = None, []
_resolved, LOCATED = locate_inputs(config)
config.update(_resolved)

DAYS = campaign_days(config)
SATS = satellite_ids(config)


wildcard_constraints:
    sat="|".join(SATS),
    entry="|".join(re.escape(e) for e in LOCATED) or "no-located-input",
    date=r"\d{4}-\d{3}",
    period=r"\d{4}-\d{2}|campaign",
    solution="float_pod|fixed_pod",


def library_code(script):
    """leopod source files that scripts/<script>.py imports; as inputs of a step they make a
    library change rerun exactly the steps that run the changed code."""
    return script_library_files(f"{workflow.basedir}/scripts/{script}.py")


def locate_source(wildcards):
    """The file a located input stands for (path from the config, relative to the workdir)."""
    return located_source(LOCATED, wildcards.entry, wildcards.path)


def existing_locate_source(wildcards):
    """The located file as input if it exists; else none, so that the locate job itself
    fails with a clear message instead of the whole campaign stopping on a missing input."""
    source = locate_source(wildcards)
    return [source] if Path(source).is_file() else []


def download_log(family):
    """Log file (template) of a download_<family> job, beside its destination's name."""
    name = Path(destination_template(CATALOGUE.family(family))).name
    return f"logs/download/{family}/{name}.log"


def sat_simulation(wildcards):
    """The simulate section with the satellite's orbit keys (satellites.<sat>.simulate_orbit)."""
    section = dict(config["simulate"])
    section["orbit"] = {**section["orbit"], **sat_config(wildcards)["simulate_orbit"]}
    return section


def sat_config(wildcards):
    """The config block of the satellite of a job."""
    return config["satellites"][wildcards.sat]


def ingest_inputs(wildcards):
    """Observation, GNSS product and optional a-priori orbit files of one satellite-day."""
    sat = sat_config(wildcards)
    files = {
        "obs": expand_template(sat["observations"], wildcards.date, wildcards.sat),
        "orbit": expand_template(config["products"]["gnss_orbit"], wildcards.date, wildcards.sat),
    }
    if config["products"].get("gnss_clock"):
        files["clock"] = expand_template(
            config["products"]["gnss_clock"], wildcards.date, wildcards.sat
        )
    if sat.get("apriori_orbit"):
        files["apriori"] = expand_template(sat["apriori_orbit"], wildcards.date, wildcards.sat)
    if config["products"].get("antex"):
        files["antex"] = expand_template(config["products"]["antex"], wildcards.date, wildcards.sat)
    return files


def simulated(wildcards):
    """True if the satellite's files are written by the simulate rule."""
    return sat_config(wildcards).get("source", "files") == "simulate"


PERIODS = code_bias_periods(config)


def simulation_product_files(wildcards):
    """The real GNSS product set the simulator uses (simulate.gnss_products), if any."""
    products = config["simulate"]["gnss_products"]
    return [] if products is None else ProductSet.from_config(products).files


def solutions():
    """POD solutions of the campaign: float, and fixed when ambiguities are resolved."""
    if not config["products"].get("gnss_clock"):
        return []
    return ["float_pod"] + (["fixed_pod"] if config["ambiguity"]["enabled"] else [])


def overlap_inputs(wildcards):
    """The arcs of a day and of the next campaign day."""
    later = DAYS[DAYS.index(wildcards.date) + 1]
    base = f"results/{wildcards.solution}/{wildcards.sat}"
    return {"a": f"{base}/{wildcards.date}_orbit.nc", "b": f"{base}/{later}_orbit.nc"}


def reference_template(sat):
    """Path template of the satellite's reference orbit (simulated: the truth), or None."""
    block = config["satellites"][sat]
    if block.get("reference_orbit"):
        return block["reference_orbit"]
    if block.get("source") == "simulate":
        return "resources/simulate/{sat}/{date}_truth.sp3"
    return None


def reference_files(wildcards):
    """Reference-orbit file(s) of a satellite-day."""
    return [expand_template(reference_template(wildcards.sat), wildcards.date, wildcards.sat)]


def slr_template(sat):
    """Path template of the satellite's CRD normal points (simulated: written beside the
    observations), or None."""
    block = config["satellites"][sat]
    if block.get("slr_normal_points"):
        return block["slr_normal_points"]
    if block.get("source") == "simulate":
        return "resources/simulate/{sat}/{date}.crd"
    return None


def slr_inputs(wildcards):
    """Orbit, normal points, station coordinates and eccentricities of an SLR validation."""
    sat = wildcards.sat
    simulated = config["satellites"][sat].get("source") == "simulate"
    files = {
        "orbit": f"results/{wildcards.solution}/{sat}/{wildcards.date}_orbit.nc",
        "normal_points": expand_template(slr_template(sat), wildcards.date, sat),
    }
    products = config["products"]
    stations = products.get("slr_stations") or (
        "resources/simulate/slr_stations.snx" if simulated else None
    )
    if stations is None:
        raise ValueError("SLR validation needs products.slr_stations (SINEX)")
    files["stations"] = expand_template(stations, wildcards.date, sat)
    ecc = products.get("slr_eccentricities") or (
        "resources/simulate/slr_eccentricities.snx" if simulated else None
    )
    if ecc:
        files["eccentricities"] = expand_template(ecc, wildcards.date, sat)
    if config["validation"]["slr"].get("ocean_loading_blq"):
        files["ocean_loading"] = config["validation"]["slr"]["ocean_loading_blq"]
    return files


def retro_offset(wildcards):
    """Retro-reflector offset from the centre of mass in the body frame [m]."""
    block = sat_config(wildcards)
    if block["retro_offset_body_m"] is not None:
        return block["retro_offset_body_m"]
    return list(config["simulate"]["slr"]["retro_offset_body_m"])


def per_day_validation(pattern):
    """``{solution: [files of every day]}`` of a per-day validation product of a satellite."""

    def inputs(wildcards):
        days = DAYS[:-1] if "overlap" in pattern else DAYS
        return {
            s: expand(pattern, sat=wildcards.sat, solution=s, date=days) for s in solutions()
        }

    return inputs


def summary_files(sat):
    """``{solution: {product: {date: file}}}`` of the campaign summary of a satellite."""
    files = {}
    for solution in solutions():
        f = {"residuals": {d: f"results/{solution}/{sat}/{d}_residuals.nc" for d in DAYS}}
        if config["ambiguity"]["enabled"]:
            f["ambiguity"] = {d: f"results/ambiguity/{sat}/{d}.nc" for d in DAYS}
        f["overlap"] = {d: f"results/overlap/{sat}/{solution}/{d}.nc" for d in DAYS[:-1]}
        if reference_template(sat):
            f["reference"] = {d: f"results/reference_orbit/{sat}/{solution}/{d}.nc" for d in DAYS}
        if slr_template(sat):
            f["slr"] = {d: f"results/slr/{sat}/{solution}/{d}.nc" for d in DAYS}
        files[solution] = f
    return files


def summary_inputs(wildcards):
    """Every file the campaign summary of a satellite reads."""
    return sorted(
        {
            path
            for per_solution in summary_files(wildcards.sat).values()
            for per_day in per_solution.values()
            for path in per_day.values()
        }
    )


def sat_name(wildcards):
    """Full name of the satellite, for titles."""
    return sat_config(wildcards).get("name", wildcards.sat)


def all_targets():
    """Final products of every satellite-day and code-bias period of the campaign."""
    per_day = ["results/quality/{sat}/{date}.nc", "results/quality/{sat}/{date}_summary.html"]
    if config["products"].get("gnss_clock"):  # POD needs a clock product (schema)
        per_day.append("results/float_pod/{sat}/{date}.sp3")
        if config["ambiguity"]["enabled"]:
            per_day += ["results/ambiguity/{sat}/{date}.nc", "results/fixed_pod/{sat}/{date}.sp3"]
    targets = expand(per_day, sat=SATS, date=DAYS)
    targets += expand("results/code_bias/{sat}/{period}.nc", sat=SATS, period=PERIODS)
    if len(PERIODS) > 1:
        targets += expand("results/code_bias/{sat}/stack.nc", sat=SATS)
    if solutions():
        if len(DAYS) > 1:
            targets += expand("results/overlap/{sat}/summary.nc", sat=SATS)
        targets += expand(
            "results/reference_orbit/{sat}/summary.nc",
            sat=[s for s in SATS if reference_template(s)],
        )
        targets += expand(
            "results/slr/{sat}/summary.nc", sat=[s for s in SATS if slr_template(s)]
        )
        targets += expand("results/summary/{sat}.nc", sat=SATS)
    return targets


def sat_pco(wildcards):
    """Antenna phase-centre offsets in the body frame [m] per band of the satellite."""
    return sat_config(wildcards).get("antenna_pco_body_m", {})


def sat_sp3_id(wildcards):
    """Id of the LEO inside its a-priori SP3 file (None: the only one)."""
    return sat_config(wildcards).get("sp3_id")


def sat_title(wildcards):
    """Title of a satellite-day for figures."""
    return f"{sat_config(wildcards).get('name', wildcards.sat)} {wildcards.date}"


def float_pod_inputs(wildcards):
    """Ingest/quality outputs and GNSS products of the days of the arc of a satellite-day."""
    if not config["products"].get("gnss_clock"):
        raise ValueError("float_pod needs a GNSS clock product (products.gnss_clock)")
    days = arc_days(config, wildcards.date)
    sat = wildcards.sat
    files = {
        "obs": [f"results/ingest/{sat}/{d}_obs.nc" for d in days],
        "leo": [f"results/ingest/{sat}/{d}_leo.nc" for d in days],
        "quality": [f"results/quality/{sat}/{d}.nc" for d in days],
        "orbit": [expand_template(config["products"]["gnss_orbit"], d, sat) for d in days],
        "clock": [expand_template(config["products"]["gnss_clock"], d, sat) for d in days],
    }
    if config["products"].get("antex"):
        files["antex"] = expand_template(config["products"]["antex"], wildcards.date, sat)
    files.update(applied_code_bias_map(wildcards))
    return files


def applied_code_bias_map(wildcards):
    """{"code_bias": map file} of the period whose map corrects the day's codes, or {}."""
    period = applied_code_bias_period(config, wildcards.date)
    if period is None:
        return {}
    return {"code_bias": f"results/code_bias/{wildcards.sat}/{period}.nc"}


def ambiguity_inputs(wildcards):
    """Observations and quality of the arc's days, the code-bias map and the AR product."""
    days = arc_days(config, wildcards.date)
    sat = wildcards.sat
    files = {
        "obs": [f"results/ingest/{sat}/{d}_obs.nc" for d in days],
        "quality": [f"results/quality/{sat}/{d}.nc" for d in days],
    }
    files.update(applied_code_bias_map(wildcards))
    for key in ("wl_bias", "osb"):
        if config["products"].get(key):
            files[key] = expand_template(config["products"][key], wildcards.date, sat)
    return files


def code_bias_inputs(wildcards):
    """Quality outputs of the days of a code-bias period."""
    days = period_days(config, wildcards.period)
    if not days:
        raise ValueError(f"code-bias period {wildcards.period} has no campaign day")
    return {"quality": [f"results/quality/{wildcards.sat}/{d}.nc" for d in days]}


def sat_yaw_flips(wildcards):
    """Yaw-flip epochs of the satellite if maps are kept per attitude mode, else None."""
    if not config["code_bias"]["attitude_modes"]:
        return None
    return sat_config(wildcards).get("yaw_flips") or None


def sat_pod_sp3_id(wildcards):
    """Satellite id written into the float-POD SP3 file."""
    return sat_config(wildcards).get("pod_sp3_id", "L01")
