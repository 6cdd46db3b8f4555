# Helpers of workflow/rules/*.smk. The configuration check, names derived from the config,
# and the named input, params and resources functions (with docstrings, no lambdas in the
# rules). The logic lives in leopod.workflow.campaign (unit-tested). `config` is never
# modified: CONFIG is its validated copy with the schema's defaults. Upstream files are named
# by the rules that write them (rules.<name>.output.<key>).
import re
from pathlib import Path
from types import SimpleNamespace

from leopod.simulate.product_set import ProductSet
from leopod.workflow.campaign import (
    applied_code_bias_period,
    arc_days,
    campaign_inputs,
    campaign_days,
    code_bias_periods,
    excluded_days,
    expand_template,
    input_templates,
    library_root,
    locate_inputs,
    located_source,
    next_days,
    period_days,
    pod_days,
    satellite_ids,
    script_library_files,
    signal_bias_inputs,
)
from leopod.workflow.config import validated
from leopod.workflow.layout import Layout
from leopod.workflow.variants import formation_pairs, pod_lines, variant_config
from leopod.workflow.downloads import (
    destination_template,
    load_catalogue,
    resolve_downloads,
    uses_downloads,
)

# CONFIG: the campaign checked against the schema, with its defaults filled in (a copy: the
# `config` of Snakemake is never modified). Rules and helpers read CONFIG only.
CONFIG = validated(config, f"{workflow.basedir}/workflow/schemas/config.schema.yaml")
#: The campaign's folders: results/<campaign>, resources/<campaign>, logs/<campaign>
#: (leopod.workflow.layout); every rule names its files through the *_path helpers below.
LAYOUT = Layout.of(CONFIG)

#: The product catalogue of the download rules (download.catalogue, else this one), if used.
DEFAULT_CATALOGUE = f"{workflow.basedir}/config/catalogue.yaml"
CATALOGUE = (
    load_catalogue(CONFIG["download"], DEFAULT_CATALOGUE) if uses_downloads(CONFIG) else None
)
# Inputs given as "download:<family>" are the files of the download rules (DOWNLOADS, the
# families); every other path template is routed through the locate step (LOCATED = {entry:
# template of the config}). INPUTS: {entry: template the rules read}, e.g.
# INPUTS["products.gnss_orbit"] = resource_path("<campaign>/locate/products.gnss_orbit/{date}/
# cod...sp3.gz"). {campaign} of the templates is the campaign's name.
_named = campaign_inputs(CONFIG)
_downloaded, DOWNLOADS = (
    resolve_downloads(_named, CATALOGUE) if CATALOGUE is not None else (_named, [])
)
_located, LOCATED = locate_inputs(_downloaded)
INPUTS = input_templates(_located)

#: The days whose orbits the campaign computes (the POD, validation and summary rules); the
#: days whose data the steps use, DATA_DAYS, hold those of config exclude_pod_days too.
DAYS = pod_days(CONFIG)
DATA_DAYS = campaign_days(CONFIG)
#: Day -> the next day, for the days whose arc overlaps the next day's (the next calendar day
#: is a campaign day: not the last one, not one before an excluded day).
NEXT_DAY = next_days(CONFIG)
OVERLAP_DAYS = list(NEXT_DAY)
SATS = satellite_ids(CONFIG)
#: POD lines {line id: (satellite, variant or None)}: each satellite's own solution, then one
#: line <sat>_<variant> per solution variant (leopod.workflow.variants). The POD, ambiguity
#: and validation rules run per line; their {sat} wildcard is a line id.
LINES = pod_lines(CONFIG)
#: The validated campaign of each variant (its pod and ambiguity keys replaced).
VARIANTS = {
    name: variant_config(config, name, f"{workflow.basedir}/workflow/schemas/config.schema.yaml")
    for name in CONFIG["variants"]
}
#: Satellites whose files the simulate rules write.
SIMULATED_SATS = [s for s in SATS if CONFIG["satellites"][s].get("source") == "simulate"]
#: Pair lines of the formation pairs (satellites.<sat>.formation) {pair id: FormationPair}:
#: "<leader>-<follower>" of the campaign's solution, "<leader>-<follower>_<variant>" of the
#: pair's lines of each variant (leopod.workflow.variants); the baseline steps run per pair line.
PAIRS = formation_pairs(CONFIG, SATS)
#: The pair lines of the campaign's own solution (kinematic baselines, simulated ranges).
BASE_PAIRS = [p for p, line in PAIRS.items() if line.variant is None]
PERIODS = code_bias_periods(CONFIG)
#: Periods of the PCV maps (pcv.period).
PCV_PERIODS = code_bias_periods(CONFIG, "pcv")
#: Folder of the leopod sources the rules depend on: src/ of the checkout beside the
#: Snakefile (None: the imported package).
LIBRARY_ROOT = library_root(workflow.basedir)


wildcard_constraints:
    sat="|".join(re.escape(line) for line in LINES),
    entry="|".join(re.escape(e) for e in LOCATED) or "no-located-input",
    date=r"\d{4}-\d{3}",
    period=r"\d{4}-\d{2}|campaign",
    solution="float_pod|fixed_pod",
    pair="|".join(re.escape(p) for p in PAIRS) or "no-formation-pair",


# --- configuration and file names ----------------------------------------------------------


def result_path(path):
    """``results/<campaign>/<path>``: a product of the campaign."""
    return f"{LAYOUT.results}/{path}"


def resource_path(path):
    """``resources/<campaign>/<path>``: a simulated or located input of the campaign."""
    return f"{LAYOUT.resources}/{path}"


def log_path(path):
    """``logs/<campaign>/<path>``: a job's log."""
    return f"{LAYOUT.logs}/{path}"


def benchmark_path(path):
    """``logs/<campaign>/benchmarks/<path>``: a job's Snakemake benchmark file."""
    return f"{LAYOUT.benchmarks}/{path}"


def figure(path, **marks):
    """A figure output of a rule: ``path`` (without suffix) in the campaign's
    ``report.figure_format`` (png, svg or pdf), marked for the report with ``marks``
    (caption, category, labels); leopod.plots.save_figure writes the format of the suffix."""
    return report(f"{path}.{CONFIG['report']['figure_format']}", **marks)


def library_code(script):
    """leopod source files that scripts/<script>.py imports; as inputs of a step they make a
    library change rerun exactly the steps that run the changed code."""
    return script_library_files(f"{workflow.basedir}/scripts/{script}.py", LIBRARY_ROOT)


def product_file(key):
    """Path template of the input products.<key> as the rules read it (a download or locate
    output), or None."""
    return INPUTS.get(f"products.{key}")


def sat_file(sat, key):
    """Path template of the input satellites.<sat>.<key> as the rules read it, or None."""
    return INPUTS.get(f"satellites.{sat}.{key}")


def download_log(family):
    """Log file (template) of a download_<family> job, beside its destination's name."""
    name = Path(destination_template(CATALOGUE.family(family))).name
    return log_path(f"download/{family}/{name}.log")


def satellite(wildcards):
    """The satellite of a job (of its POD line for the POD and validation steps)."""
    return LINES[wildcards.sat][0]


def sat_config(wildcards):
    """The config block of the satellite of a job."""
    return CONFIG["satellites"][satellite(wildcards)]


def line_config(wildcards):
    """The validated campaign of a job's POD line (a variant's, or the campaign)."""
    variant = LINES[wildcards.sat][1]
    return CONFIG if variant is None else VARIANTS[variant]


def line_pod(wildcards):
    """The pod section of a job's POD line."""
    return line_config(wildcards)["pod"]


def line_ambiguity(wildcards):
    """The ambiguity section of a job's POD line."""
    return line_config(wildcards)["ambiguity"]


def is_simulated(sat):
    """True if the satellite's (or POD line's satellite's) files are written by the simulate
    rules."""
    return LINES.get(sat, (sat, None))[0] in SIMULATED_SATS


def pair_config(pair):
    """The validated campaign of a pair line (its variant's, or the campaign)."""
    variant = PAIRS[pair].variant
    return CONFIG if variant is None else VARIANTS[variant]


def pair_phases(wildcards):
    """{system: phase signal pair} of the systems of a pair line's POD."""
    system = pair_config(wildcards.pair)["pod"]["system"]
    return {x: CONFIG["signals"][x]["phase"] for x in ([system] if isinstance(system, str)
                                                       else system)}


def pair_title(wildcards):
    """"<follower> - <leader>" of a pair line (POD line ids), for titles."""
    return f"{PAIRS[wildcards.pair].follower} - {PAIRS[wildcards.pair].leader}"


def ar_product_named():
    """True if the campaign names an AR product (CNES/CLS WL biases or Bias-SINEX OSBs)."""
    return bool(product_file("wl_bias") or product_file("osb"))


def solutions():
    """POD solutions of the campaign: float, and fixed when ambiguities are resolved with an
    AR product. Without one no single difference can be fixed, and a copy of the float orbit
    is not written under the name of a fixed solution."""
    if not product_file("gnss_clock"):
        return []
    fixed = CONFIG["ambiguity"]["enabled"] and ar_product_named()
    return ["float_pod"] + (["fixed_pod"] if fixed else [])


#: The solutions a validation job compares (the float one alone names the outputs' pattern in
#: a campaign without POD, whose validation rules no target asks for).
VALIDATED = solutions() or ["float_pod"]


# --- upstream outputs ----------------------------------------------------------------------


def fill(pattern, **wildcards):
    """An output pattern (rules.<rule>.output.<name>) with its wildcards filled in: a plain
    path, without the pattern's flags (report())."""
    return str(pattern).format(**wildcards)


def pod_output(solution, name):
    """Output pattern ``name`` of the POD rule of a solution (float_pod or fixed_pod)."""
    return getattr(getattr(rules, solution).output, name)


def reference_template(sat):
    """Path template of the satellite's reference orbit (simulated: the truth, its netCDF
    file: exact, and read in a tenth of the time of its SP3 copy), or None."""
    if sat_file(sat, "reference_orbit"):
        return sat_file(sat, "reference_orbit")
    if is_simulated(sat):
        return str(rules.simulate.output.truth_nc)
    return None


def manoeuvre_file(sat):
    """The satellite's manoeuvre file (simulated: its simulated burns), or None."""
    path = CONFIG["satellites"][sat]["manoeuvres"]
    if path is None and is_simulated(sat):
        path = expand(rules.simulate_truth.output.manoeuvres, sat=sat)[0]
    return path


def slr_template(sat):
    """Path template of the satellite's CRD normal points (simulated: written beside the
    observations), or None."""
    if sat_file(sat, "slr_normal_points"):
        return sat_file(sat, "slr_normal_points")
    if is_simulated(sat):
        return str(rules.simulate.output.crd)
    return None


def applied_code_bias_map(wildcards):
    """{"code_bias": map file} of the period whose map corrects the day's codes, or {}."""
    period = applied_code_bias_period(CONFIG, wildcards.date)
    if period is None:
        return {}
    return {"code_bias": fill(rules.code_bias.output.nc, sat=satellite(wildcards), period=period)}


# --- input functions -----------------------------------------------------------------------


def locate_source(wildcards):
    """The file a located input stands for (path from the config, relative to the workdir)."""
    return located_source(LOCATED, wildcards.entry, wildcards.path)


def existing_locate_source(wildcards):
    """The located file as input if it exists; else none, so that the locate job itself
    fails with a clear message instead of the whole campaign stopping on a missing input."""
    source = locate_source(wildcards)
    return [source] if Path(source).is_file() else []


def simulation_product_files(wildcards):
    """The real GNSS product set the simulator uses (simulate.gnss_products), if any."""
    products = CONFIG["simulate"]["gnss_products"]
    return [] if products is None else ProductSet.from_config(products).files


def gnss_product_inputs(wildcards):
    """The SP3, clock (if any) and ANTEX (if any) files of a day."""
    files = {"orbit": expand_template(product_file("gnss_orbit"), wildcards.date)}
    for key, name in (("clock", "gnss_clock"), ("antex", "antex")):
        if product_file(name):
            files[key] = expand_template(product_file(name), wildcards.date)
    return files


def gnss_product_outputs():
    """netCDF files of the gnss_products rule: orbit always, clock and satellite antennas
    when the campaign has a clock product and an ANTEX file."""
    base = result_path("gnss_products/{date}")
    files = {"orbit": f"{base}_orbit.nc"}
    if product_file("gnss_clock"):
        files["clock"] = f"{base}_clock.nc"
    if product_file("antex"):
        files["antenna"] = f"{base}_antenna.nc"
    return files


def day_products(days, *keys):
    """{key: [netCDF product of every day]} of the gnss_products rule (keys it writes)."""
    outputs = rules.gnss_products.output
    return {k: [fill(getattr(outputs, k), date=d) for d in days] for k in keys
            if hasattr(outputs, k)}


def ingest_inputs(wildcards):
    """Observation file, the day's GNSS products (netCDF) and the optional a-priori orbit of
    one satellite-day."""
    sat, date = wildcards.sat, wildcards.date
    files = {"obs": expand_template(sat_file(sat, "observations"), date, sat)}
    files.update({k: v[0] for k, v in day_products([date], "orbit", "clock", "antenna").items()})
    if sat_file(sat, "apriori_orbit"):
        files["apriori"] = expand_template(sat_file(sat, "apriori_orbit"), date, sat)
    return files


def quality_antenna(wildcards):
    """The satellite antennas of the day (netCDF of gnss_products), if the campaign has an
    ANTEX file: the multipath is formed without the antenna terms the POD models."""
    return {k: v[0] for k, v in day_products([wildcards.date], "antenna").items()}


def code_bias_inputs(wildcards):
    """Quality outputs of the days of a code-bias period."""
    days = period_days(CONFIG, wildcards.period)
    if not days:
        raise ValueError(f"code-bias period {wildcards.period} has no campaign day")
    return {"quality": expand(rules.quality.output.nc, sat=wildcards.sat, date=days)}


def pcv_solution(wildcards):
    """POD solution whose residuals the PCV map stacks (pcv.solution; auto = fixed if the
    campaign resolves ambiguities, else float)."""
    chosen = CONFIG["pcv"]["solution"]
    if chosen == "auto":
        return "fixed_pod" if "fixed_pod" in solutions() else "float_pod"
    if chosen not in solutions():
        raise ValueError(f"pcv.solution {chosen}: the campaign has no such POD solution "
                         f"({', '.join(solutions()) or 'none: no clock product'})")
    return chosen


def pcv_inputs(wildcards):
    """Residuals (residual method) or normal equations (direct method) of the POD days of a
    PCV period (the line's chosen solution) and the ANTEX file of the satellite's antenna, if
    it has one (the a-priori PCV the map adds to)."""
    days = period_days(CONFIG, wildcards.period, "pcv")
    if not days:
        raise ValueError(f"PCV period {wildcards.period} has no campaign day")
    if CONFIG["pcv"]["method"] == "direct":
        files = {"neq": expand(rules.pcv_neq.output.neq, sat=wildcards.sat, date=days)}
    else:
        files = {"residuals": [fill(pod_output(pcv_solution(wildcards), "residuals"),
                                    sat=wildcards.sat, date=d) for d in days]}
    return {**files, **apriori_antex(wildcards, days[0])}


def pcv_neq_inputs(wildcards):
    """float_pod's inputs of the day, its float solution and, for the fixed POD (pcv.solution),
    the ambiguity table."""
    files = float_pod_inputs(wildcards)
    for name in ("orbit", "parameters", "ambiguities", "residuals"):
        files[f"float_{name}"] = fill(pod_output("float_pod", name), sat=wildcards.sat,
                                      date=wildcards.date)
    if pcv_solution(wildcards) == "fixed_pod":
        files["table"] = fill(rules.ambiguity.output.table, sat=wildcards.sat,
                              date=wildcards.date)
    return files


def apriori_antex(wildcards, day):
    """{'leo_antex': the ANTEX file of the satellite's antenna on ``day``} (the a-priori PCV
    a PCV map adds to) or {} without one."""
    template = sat_file(satellite(wildcards), "antenna")
    if not template:
        return {}
    return {"leo_antex": expand_template(template, day, satellite(wildcards))}


def pcv_stack_inputs(wildcards):
    """The ANTEX file of the satellite's antenna on the first campaign day, if any."""
    return apriori_antex(wildcards, DAYS[0])


def pcv_title(wildcards):
    """Title of a satellite line's PCV period for figures."""
    return f"{sat_name(wildcards)} {wildcards.period}"


def signal_bias_files(wildcards, days):
    """Bias products (OSB, P1-C1 DCB) of ``days`` whose satellite biases the step removes
    from the observations, and the spec of its script (leopod.workflow.campaign)."""
    return signal_bias_inputs(INPUTS, LOCATED, wildcards.date, days)


def arc_signal_bias(wildcards):
    """Spec of the bias products of the arc's days (params of the POD and ambiguity steps)."""
    return signal_bias_files(wildcards, arc_days(CONFIG, wildcards.date))[1]


def day_signal_bias_inputs(wildcards):
    """Bias products of one day (inputs of the quality step)."""
    return signal_bias_files(wildcards, [wildcards.date])[0]


def day_signal_bias(wildcards):
    """Spec of the bias products of one day (params of the quality step)."""
    return signal_bias_files(wildcards, [wildcards.date])[1]


def float_pod_inputs(wildcards):
    """Ingest/quality outputs and GNSS products (netCDF) of the days of the arc of a
    satellite-day; the satellite antennas of the day."""
    if not product_file("gnss_clock"):
        raise ValueError("float_pod needs a GNSS clock product (products.gnss_clock)")
    days = arc_days(CONFIG, wildcards.date)
    sat = satellite(wildcards)
    files = {
        "obs": expand(rules.ingest.output.obs, sat=sat, date=days),
        "leo": expand(rules.ingest.output.leo, sat=sat, date=days),
        "quality": expand(rules.quality.output.nc, sat=sat, date=days),
        **day_products(days, "orbit", "clock"),
        **day_products([wildcards.date], "antenna"),
    }
    if "antenna" in files:
        files["antenna"] = files["antenna"][0]
    files.update(applied_code_bias_map(wildcards))
    files.update(signal_bias_files(wildcards, days)[0])
    if manoeuvre_file(sat):
        files["manoeuvres"] = manoeuvre_file(sat)
    files.update(attitude_inputs(wildcards))
    files.update(antenna_inputs(wildcards))
    return files


def baseline_inputs(wildcards):
    """baseline: float_pod's inputs, float solution and (simulated) truth orbit of the leader
    (keys a_*) and the follower (b_*) of a formation pair; with baseline.mode
    reference_fixed also the leader's fixed POD parameters and ambiguities (a_fixed_*)."""
    files = {}
    line = PAIRS[wildcards.pair]
    for key, sat in (("a", line.leader), ("b", line.follower)):
        w = SimpleNamespace(sat=sat, date=wildcards.date)
        inputs = float_pod_inputs(w)
        for name in ("orbit", "parameters", "ambiguities", "residuals"):
            inputs[f"float_{name}"] = fill(pod_output("float_pod", name), sat=sat,
                                           date=wildcards.date)
        if is_simulated(sat):
            # the truth netCDF, not the SP3: SP3 positions are rounded to 1 mm, which puts
            # 0.7 mm 3D RMS of rounding into a truth baseline
            inputs["truth"] = fill(rules.simulate.output.truth_nc, sat=LINES[sat][0],
                                   date=wildcards.date)
        files.update({f"{key}_{k}": v for k, v in inputs.items()})
    if CONFIG["baseline"]["mode"] == "reference_fixed":
        # the leader held at its single-difference-fixed POD
        leader = line.leader
        for name in ("parameters", "ambiguities"):
            files[f"a_fixed_{name}"] = fill(pod_output("fixed_pod", name), sat=leader,
                                            date=wildcards.date)
    return files


def baseline_pair_params(wildcards):
    """Per satellite of a pair (leader, follower): name, PCO, attitude, yaw flips, bias spec,
    SP3 id."""
    out = []
    for sat in PAIRS[wildcards.pair][:2]:
        w = SimpleNamespace(sat=sat, date=wildcards.date)
        out.append({"sat": sat, "title": sat_name(w), "pco_body_m": sat_pco(w),
                    "antenna": sat_antenna(w),
                    "attitude": sat_attitude(w), "yaw_flips": sat_yaw_flips(w),
                    "signal_bias": arc_signal_bias(w), "sp3_id": sat_pod_sp3_id(w)})
    return out


def kinematic_baseline_inputs(wildcards):
    """kinematic_baseline: the baseline rule's inputs, its DD table and its (reduced-dynamic)
    baseline."""
    files = baseline_inputs(wildcards)
    files["dd"] = fill(rules.baseline.output.dd, pair=wildcards.pair, date=wildcards.date)
    files["dynamic"] = fill(rules.baseline.output.nc, pair=wildcards.pair, date=wildcards.date)
    return files


def kinematic_baselines(pair):
    """True if the pair line has kinematic baselines (kinematic.baseline_systems; the
    campaign's own solution only: it holds every system's kinematic solution)."""
    return bool(CONFIG["kinematic"]["baseline_systems"]) and PAIRS[pair].variant is None


def pair_label(pair):
    """Short label of a pair line's solution: its variant, or the campaign's systems
    ("G+C")."""
    variant = PAIRS[pair].variant
    if variant is not None:
        return variant
    system = CONFIG["pod"]["system"]
    return system if isinstance(system, str) else "+".join(system)


def formation_summary_files(pair):
    """{date: {product: path or [paths]}} of the formation summary of a pair line: baseline,
    DD table, kinematic baseline, overlap with the next day, range check, (simulated pairs) the
    float residuals and truth files that give the wrong DD fixes, and (the campaign's own pair
    line, with variants) the baselines of every pair line of the pair ("lines", by label)."""
    a, b = PAIRS[pair][:2]
    simulated = is_simulated(a) and is_simulated(b)
    out = {}
    for date in DAYS:
        files = {"baseline": fill(rules.baseline.output.nc, pair=pair, date=date),
                 "dd": fill(rules.baseline.output.dd, pair=pair, date=date)}
        if kinematic_baselines(pair):
            files["kinematic"] = fill(rules.kinematic_baseline.output.nc, pair=pair, date=date)
        if VARIANTS and PAIRS[pair].variant is None:
            files["lines"] = {pair_label(p): fill(rules.baseline.output.nc, pair=p, date=date)
                              for p, line in PAIRS.items() if line.base == pair}
        if date in OVERLAP_DAYS:
            files["overlap"] = fill(rules.baseline_overlap.output.nc, pair=pair, date=date)
        if simulated:
            files["range"] = fill(rules.range_check.output.nc, pair=pair, date=date)
            for key, sat in (("a", a), ("b", b)):
                files[f"residuals_{key}"] = fill(pod_output("float_pod", "residuals"), sat=sat,
                                                 date=date)
                files[f"truth_{key}"] = expand(rules.simulate.output.truth_nc,
                                               sat=LINES[sat][0], date=arc_days(CONFIG, date))
        out[date] = files
    return out


def formation_summary_inputs(wildcards):
    """Every file the formation summary of a pair reads."""
    return sorted({p for files in formation_summary_files(wildcards.pair).values()
                   for v in files.values()
                   for p in ([v] if isinstance(v, str) else list(v.values())
                             if isinstance(v, dict) else v)})


def baseline_overlap_inputs(wildcards):
    """The baseline solutions of a day and of the next day, and the leader's float
    orbit of the day (RTN axes)."""
    later = NEXT_DAY[wildcards.date]
    files = {"dynamic_a": fill(rules.baseline.output.nc, pair=wildcards.pair,
                               date=wildcards.date),
             "dynamic_b": fill(rules.baseline.output.nc, pair=wildcards.pair, date=later),
             "leader": fill(pod_output("float_pod", "orbit"),
                            sat=PAIRS[wildcards.pair].leader, date=wildcards.date)}
    if kinematic_baselines(wildcards.pair):
        files["kinematic_a"] = fill(rules.kinematic_baseline.output.nc, pair=wildcards.pair,
                                    date=wildcards.date)
        files["kinematic_b"] = fill(rules.kinematic_baseline.output.nc, pair=wildcards.pair,
                                    date=later)
    return files


def range_check_inputs(wildcards):
    """range_check: the pair's range series (one per pair: of its satellites' truth) and the
    pair line's baseline solutions of the day."""
    files = {"range": fill(rules.simulate_range.output.csv, pair=PAIRS[wildcards.pair].base,
                           date=wildcards.date),
             "dynamic": fill(rules.baseline.output.nc, pair=wildcards.pair,
                             date=wildcards.date)}
    if kinematic_baselines(wildcards.pair):
        files["kinematic"] = fill(rules.kinematic_baseline.output.nc, pair=wildcards.pair,
                                  date=wildcards.date)
    return files


def kinematic_inputs(wildcards):
    """kinematic_pod: float_pod's inputs, its orbit and, for fixed ambiguities, the ambiguity table."""
    files = float_pod_inputs(wildcards)
    files["float_orbit"] = fill(rules.float_pod.output.orbit, sat=wildcards.sat,
                                date=wildcards.date)
    if CONFIG["kinematic"]["ambiguities"] == "fixed":
        files["table"] = fill(rules.ambiguity.output.table, sat=wildcards.sat,
                              date=wildcards.date)
    return files


def ambiguity_inputs(wildcards):
    """Observations and quality of the arc's days, the code-bias map and the AR product."""
    days = arc_days(CONFIG, wildcards.date)
    sat = satellite(wildcards)
    files = {
        "obs": expand(rules.ingest.output.obs, sat=sat, date=days),
        "quality": expand(rules.quality.output.nc, sat=sat, date=days),
    }
    files.update(applied_code_bias_map(wildcards))
    files.update(signal_bias_files(wildcards, days)[0])
    for key in ("wl_bias", "osb"):
        if product_file(key):
            files[key] = expand_template(product_file(key), wildcards.date, sat)
    return files


def each_solution(pattern):
    """The files of an output pattern with {solution} for every validated solution."""
    return [pattern.replace("{solution}", s) for s in VALIDATED]


def pod_orbits(wildcards):
    """``{solution: orbit}`` of the validated POD solutions of a satellite-day."""
    return {s: fill(pod_output(s, "orbit"), sat=wildcards.sat, date=wildcards.date)
            for s in VALIDATED}


def overlap_inputs(wildcards):
    """The arcs of a day (``<solution>_a``) and of the next day (``<solution>_b``, NEXT_DAY)
    of every validated solution."""
    later = NEXT_DAY[wildcards.date]
    files = {}
    for s in VALIDATED:
        orbit = pod_output(s, "orbit")
        files[f"{s}_a"] = fill(orbit, sat=wildcards.sat, date=wildcards.date)
        files[f"{s}_b"] = fill(orbit, sat=wildcards.sat, date=later)
    return files


def reference_files(wildcards):
    """Reference-orbit file(s) of a satellite-day."""
    sat = satellite(wildcards)
    return [expand_template(reference_template(sat), wildcards.date, sat)]


def slr_inputs(wildcards):
    """Orbits (one per validated solution), normal points, station coordinates and
    eccentricities of an SLR validation."""
    sat, date = satellite(wildcards), wildcards.date
    files = {
        **pod_orbits(wildcards),
        "normal_points": expand_template(slr_template(sat), date, sat),
    }
    world = rules.simulate_world.output
    stations = product_file("slr_stations") or (str(world.stations) if is_simulated(sat) else None)
    if stations is None:
        raise ValueError("SLR validation needs products.slr_stations (SINEX)")
    files["stations"] = expand_template(stations, date, sat)
    ecc = product_file("slr_eccentricities") or (
        str(world.eccentricities) if is_simulated(sat) else None
    )
    if ecc:
        files["eccentricities"] = expand_template(ecc, date, sat)
    if CONFIG["validation"]["slr"].get("ocean_loading_blq"):
        files["ocean_loading"] = CONFIG["validation"]["slr"]["ocean_loading_blq"]
    return files


def per_day_validation(pattern, days=None):
    """Input function: ``{solution: [files of every day]}`` of a per-day validation product
    (output pattern with {sat}, {solution} and {date}) of a satellite; ``days`` default to the
    campaign's."""
    days = DAYS if days is None else days

    def inputs(wildcards):
        return {
            s: expand(str(pattern), sat=wildcards.sat, solution=s, date=days) for s in solutions()
        }

    return inputs


def summary_files(sat):
    """``{solution: {product: {date: file}}}`` of the campaign summary of a POD line."""
    base = LINES[sat][0]
    files = {}
    for solution in solutions():
        residuals = pod_output(solution, "residuals")
        parameters = pod_output(solution, "parameters")
        f = {
            "residuals": {d: fill(residuals, sat=sat, date=d) for d in DAYS},
            "parameters": {d: fill(parameters, sat=sat, date=d) for d in DAYS},
        }
        if "fixed_pod" in solutions():
            f["ambiguity"] = {d: fill(rules.ambiguity.output.table, sat=sat, date=d) for d in DAYS}
        f["overlap"] = {
            d: fill(OVERLAP_NC, sat=sat, solution=solution, date=d) for d in OVERLAP_DAYS
        }
        if reference_template(base):
            f["reference"] = {
                d: fill(REFERENCE_NC, sat=sat, solution=solution, date=d) for d in DAYS
            }
        if slr_template(base):
            f["slr"] = {
                d: fill(SLR_NC, sat=sat, solution=solution, date=d) for d in DAYS
            }
        if is_simulated(base) and "fixed_pod" in solutions():
            # the simulator's integers of the arc's days: wrong fixes per system
            f["truth"] = {
                d: [fill(rules.simulate.output.truth_nc, sat=base, date=a)
                    for a in arc_days(CONFIG, d)]
                for d in DAYS
            }
        files[solution] = f
    return files


def summary_inputs(wildcards):
    """Every file the campaign summary of a satellite reads."""
    return sorted(
        {
            path
            for per_solution in summary_files(wildcards.sat).values()
            for per_day in per_solution.values()
            for paths in per_day.values()
            for path in ([paths] if isinstance(paths, str) else paths)
        }
    )


def all_targets():
    """Final products of every satellite-day and code-bias period of the campaign."""
    per_day = [rules.quality.output.nc, rules.quality.output.summary]
    if product_file("gnss_clock"):  # POD needs a clock product (schema)
        per_day.append(rules.float_pod.output.sp3)
        if "fixed_pod" in solutions():
            per_day += [rules.ambiguity.output.table, rules.fixed_pod.output.sp3]
    targets = expand([str(p) for p in per_day[:2]], sat=SATS, date=DATA_DAYS)
    targets += expand([str(p) for p in per_day[2:]], sat=LINES, date=DAYS)
    targets += expand(rules.code_bias.output.nc, sat=SATS, period=PERIODS)
    # inter-satellite DDs need no AR product: the float solutions of the pair are enough
    if PAIRS and CONFIG["ambiguity"]["enabled"] and product_file("gnss_clock"):
        targets += expand(rules.baseline.output.nc, pair=list(PAIRS), date=DAYS)
        if CONFIG["kinematic"]["baseline_systems"]:
            targets += expand(rules.kinematic_baseline.output.nc, pair=BASE_PAIRS, date=DAYS)
        simulated_pairs = [p for p, line in PAIRS.items()
                           if is_simulated(line.leader) and is_simulated(line.follower)]
        targets += expand(rules.range_check.output.nc, pair=simulated_pairs, date=DAYS)
        if OVERLAP_DAYS:
            targets += expand(rules.baseline_overlap.output.nc, pair=list(PAIRS),
                              date=OVERLAP_DAYS)
        targets += expand(rules.formation_summary.output.csv, pair=list(PAIRS))
    if CONFIG["kinematic"]["enabled"] and product_file("gnss_clock"):
        targets += expand(rules.kinematic_pod.output.sp3, sat=LINES, date=DAYS)
    if len(PERIODS) > 1:
        targets += expand(rules.code_bias_stack.output.nc, sat=SATS)
    if CONFIG["pcv"]["enabled"] and solutions():
        targets += expand(rules.pcv.output.antex, sat=SATS, period=PCV_PERIODS)
        if len(PCV_PERIODS) > 1:
            targets += expand(rules.pcv_stack.output.antex, sat=SATS)
    if solutions():
        if OVERLAP_DAYS:
            targets += expand(rules.overlap_summary.output.nc, sat=LINES)
        targets += expand(
            rules.reference_summary.output.nc,
            sat=[line for line, (s, _) in LINES.items() if reference_template(s)],
        )
        targets += expand(
            rules.slr_summary.output.nc,
            sat=[line for line, (s, _) in LINES.items() if slr_template(s)],
        )
        targets += expand(rules.campaign_summary.output.nc, sat=LINES)
        if VARIANTS:
            targets += expand(rules.variant_comparison.output.csv, sat=SATS)
    return targets


# --- params functions ----------------------------------------------------------------------


def sat_simulation(wildcards):
    """The simulate section with the satellite's orbit keys (satellites.<sat>.simulate_orbit);
    for a formation follower those of its leader, whose orbit the ROE displace."""
    block = sat_config(wildcards)
    formation = block.get("formation")
    if formation is not None:
        if formation["leader"] not in SIMULATED_SATS:
            raise ValueError(f"satellites.{satellite(wildcards)}.formation.leader: "
                             f"{formation['leader']!r} is not a simulated satellite of the "
                             f"campaign ({', '.join(SIMULATED_SATS)})")
        block = CONFIG["satellites"][formation["leader"]]
    section = dict(CONFIG["simulate"])
    section["orbit"] = {**section["orbit"], **block["simulate_orbit"]}
    return section


def sat_formation(wildcards):
    """The satellite's formation block (satellites.<sat>.formation), or None."""
    return sat_config(wildcards).get("formation")


def sat_name(wildcards):
    """Full name of the satellite (and the variant of a POD line), for titles."""
    sat, variant = LINES.get(wildcards.sat, (wildcards.sat, None))
    name = CONFIG["satellites"][sat].get("name", sat)
    return name if variant is None else f"{name} [{variant}]"


def sat_title(wildcards):
    """Title of a satellite-day for figures."""
    return f"{sat_name(wildcards)} {wildcards.date}"


def period_title(wildcards):
    """Title of a satellite's code-bias period for figures."""
    return f"{sat_name(wildcards)} {wildcards.period}"


def sat_lines(wildcards):
    """POD line ids of a satellite: its own, then those of its variants."""
    return [line for line, (sat, _) in LINES.items() if sat == wildcards.sat]


def line_summaries(wildcards):
    """Campaign summaries (netCDF) of the POD lines of a satellite, in line order."""
    return [fill(rules.campaign_summary.output.nc, sat=line) for line in sat_lines(wildcards)]


def campaign_summary_files(wildcards):
    """``{solution: {product: {date: file}}}`` the campaign summary of a satellite reads."""
    return summary_files(wildcards.sat)


def sat_pco(wildcards):
    """Antenna phase-centre offsets in the body frame [m] per band of the satellite."""
    return sat_config(wildcards).get("antenna_pco_body_m", {})


def sat_antenna(wildcards):
    """The satellite's ANTEX antenna block (satellites.<sat>.antenna: type, ARP, frame; the
    file itself is an input: antenna_inputs); refuses it together with antenna_pco_body_m."""
    block = sat_config(wildcards)
    antenna = dict(block["antenna"])
    if antenna["antex"] is not None and block.get("antenna_pco_body_m"):
        raise ValueError(f"satellites.{satellite(wildcards)}: give either antenna_pco_body_m "
                         "or antenna.antex (an ANTEX receiver antenna), not both")
    return antenna


def antenna_inputs(wildcards):
    """{'leo_antex': the ANTEX file of the satellite's antenna (satellites.<sat>.antenna.antex,
    located)} or {} without one."""
    sat = satellite(wildcards)
    template = sat_file(sat, "antenna")
    if not template:
        return {}
    return {"leo_antex": expand_template(template, wildcards.date, sat)}


def sim_antenna_block(wildcards):
    """satellites.<sat>.simulate_antenna if it names an ANTEX file, else None."""
    block = sat_config(wildcards).get("simulate_antenna") or {}
    return dict(block) if block.get("antex") is not None else None


def sim_pco(wildcards):
    """PCO table of the simulator: none when satellites.<sat>.simulate_antenna replaces the
    satellite's antenna."""
    return {} if sim_antenna_block(wildcards) else sat_pco(wildcards)


def sim_antenna(wildcards):
    """Antenna block of the simulator: satellites.<sat>.simulate_antenna, else the
    satellite's antenna."""
    return sim_antenna_block(wildcards) or sat_antenna(wildcards)


def sim_antenna_inputs(wildcards):
    """{'leo_antex': the simulator's ANTEX file} (simulate_antenna, else the satellite's
    antenna: antenna_inputs) or {}."""
    if not sim_antenna_block(wildcards):
        return antenna_inputs(wildcards)
    sat = satellite(wildcards)
    return {"leo_antex": expand_template(sat_file(sat, "simulate_antenna"), wildcards.date,
                                         sat)}


def sat_attitude(wildcards):
    """Attitude law of the satellite (leopod.frames.leo_attitude.LeoAttitude): its 'attitude',
    'yaw_steering', 'attitude_offset' and 'attitude_file' keys, the same for every step (the
    files themselves are inputs: attitude_inputs)."""
    block = sat_config(wildcards)
    return {key: block[key] if isinstance(block[key], str) else dict(block[key])
            for key in ("attitude", "yaw_steering", "attitude_offset", "attitude_file")}


def sat_macro_model(wildcards):
    """The satellite's macro model section (plates of pod.forces.<force>.plates), or None."""
    return sat_config(wildcards)["macro_model"]


def attitude_inputs(wildcards):
    """{'attitude': the satellite's attitude files of the days the job's arc reaches} for the
    'file' attitude law (a daily step reads its neighbours too: a day's last epochs lie
    after the day's last record), else {}."""
    sat = satellite(wildcards)
    template = sat_file(sat, "attitude_file")
    if not template or CONFIG["satellites"][sat]["attitude"] != "file":
        return {}
    days = arc_days(CONFIG, wildcards.date)
    return {"attitude": list(dict.fromkeys(expand_template(template, d, sat) for d in days))}


def sat_sp3_id(wildcards):
    """Id of the LEO inside its a-priori SP3 file (None: the only one)."""
    return sat_config(wildcards).get("sp3_id")


def sat_pod_sp3_id(wildcards):
    """Satellite id written into the float-POD SP3 file."""
    return sat_config(wildcards).get("pod_sp3_id", "L01")


def sat_yaw_flips(wildcards):
    """Yaw-flip epochs of the satellite if maps are kept per attitude mode, else None."""
    if not CONFIG["code_bias"]["attitude_modes"]:
        return None
    return sat_config(wildcards).get("yaw_flips") or None


def sat_reference_id(wildcards):
    """Id of the satellite inside its SP3 reference orbit (None: the only one)."""
    return sat_config(wildcards).get("reference_id")


def sat_reference_time_system(wildcards):
    """Time system of the epochs of the satellite's reference orbit (None: from the file)."""
    return sat_config(wildcards).get("reference_time_system")


def retro_offset(wildcards):
    """Retro-reflector offset from the centre of mass in the body frame [m]."""
    block = sat_config(wildcards)
    if block["retro_offset_body_m"] is not None:
        return block["retro_offset_body_m"]
    return list(CONFIG["simulate"]["slr"]["retro_offset_body_m"])


# --- resources functions -------------------------------------------------------------------


def float_linearisation():
    """The float POD's last linearisation (orbit and partials at the fixed POD's epochs,
    ~20 MB for a 30-h arc), which fixed_pod reads instead of integrating again
    (leopod.estimation.linearisation): an output of float_pod and an input of fixed_pod when
    the campaign has a fixed solution. A regular file, not temp(): fixed_pod reruns alone
    (e.g. after an ambiguity setting changed) without rerunning float_pod."""
    if "fixed_pod" not in solutions():
        return {}
    return {"linearisation": result_path("float_pod/{sat}/{date}_linearisation.nc")}


def pod_outputs(step, category):
    """Products and report figures of a POD step (float_pod or fixed_pod), named as
    scripts/float_pod.py and scripts/fixed_pod.py write them."""
    figures = {
        "res_time": ("residuals_time", "pod_residuals_time", "residuals vs time"),
        "res_elevation": ("residuals_elevation", "pod_residuals_elevation",
                          "residuals vs elevation"),
        "res_skymap": ("residual_skymap", "pod_residual_skymap", "phase residual map"),
        "apriori": ("apriori_rtn", "pod_apriori_rtn", "RTN vs a-priori"),
    }
    base = result_path(f"{step}/{{sat}}/{{date}}")
    return {
        "orbit": f"{base}_orbit.nc",
        # SP3-d of the day (00:00 to before 24:00: daily files concatenate) and of the arc
        "sp3": f"{base}.sp3",
        "sp3_arc": f"{base}_arc.sp3",
        "residuals": f"{base}_residuals.nc",
        "parameters": f"{base}_parameters.nc",
        "ambiguities": f"{base}_ambiguities.nc",
        **{
            key: figure(
                f"{base}_{name}",
                caption=f"../report/{caption}.rst",
                category=category,
                labels={"satellite": "{sat}", "day": "{date}", "figure": label},
            )
            for key, (name, caption, label) in figures.items()
        },
    }


def pod_mem_mb(wildcards, attempt):
    """Memory of a POD job [MB]: 3 GB (measured peak RSS 1.0-1.6 GB for 30-h arcs at 30 s,
    benchmarks/campaign.py), twice as much for each retry of a job killed for memory
    (profiles/slurm: retries)."""
    return 3000 * attempt
