# Configuration check and small input helpers; the logic lives in leopod.campaign (tested).
from snakemake.utils import validate

from leopod.campaign import (
    applied_code_bias_period,
    arc_days,
    campaign_days,
    code_bias_periods,
    expand_template,
    library_files,
    period_days,
    satellite_ids,
)


validate(config, "../schemas/config.schema.yaml", set_default=True)

DAYS = campaign_days(config)
SATS = satellite_ids(config)


wildcard_constraints:
    sat="|".join(SATS),
    date=r"\d{4}-\d{3}",
    period=r"\d{4}-\d{2}|campaign",


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
    products = config.get("simulate", {}).get("gnss_products")
    if not products:
        return []
    files = []
    for key in ("orbit", "clock"):
        value = products[key]
        files += [value] if isinstance(value, str) else list(value)
    return [*files, products["osb"], *([products["dcb_p1c1"]] if products.get("dcb_p1c1") else [])]


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
