# Inter-satellite range of a formation pair and the range check of its baselines. The simulator
# writes a K-band-like range (truth + white noise, simulate.range_sigma_m) in the layout of
# GRACE's grc_kb_rng.csv; range_check compares the length of every baseline solution (reduced-
# dynamic float and DD-fixed, kinematic per system) with it (leopod.validation.formation).


rule simulate_range:
    input:
        a=lambda w: fill(rules.simulate.output.truth_nc, sat=PAIRS[w.pair].leader, date=w.date),
        b=lambda w: fill(rules.simulate.output.truth_nc, sat=PAIRS[w.pair].follower,
                         date=w.date),
        code=library_code("simulate_range"),
    output:
        csv=resource_path("simulate/{pair}/{date}_range.csv"),
    log:
        log_path("simulate_range/{pair}/{date}.log"),
    benchmark:
        benchmark_path("simulate_range/{pair}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        settings=CONFIG["simulate"],
    script:
        "../../scripts/simulate_range.py"


rule range_check:
    input:
        unpack(range_check_inputs),
        code=library_code("range_check"),
    output:
        nc=result_path("range_check/{pair}/{date}.nc"),
        figure=figure(
            result_path("range_check/{pair}/{date}"),
            caption="../report/range_check.rst",
            category="Baseline",
            labels={"pair": "{pair}", "day": "{date}", "figure": "range check"},
        ),
    log:
        log_path("range_check/{pair}/{date}.log"),
    benchmark:
        benchmark_path("range_check/{pair}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        title=pair_title,
    script:
        "../../scripts/range_check.py"


# The campaign summary of a formation pair: per day DD fixing rates and wrong fixes, the
# reduced-dynamic baseline against the truth, kinematic minus truth and minus dynamic per
# system, the range checks; mean and STD rows (paper 003, Tables 4-6).
rule formation_summary:
    input:
        formation_summary_inputs,
        code=library_code("formation_summary"),
    output:
        csv=result_path("summary/{pair}_formation.csv"),
        html=report(
            result_path("summary/{pair}_formation.html"),
            caption="../report/formation_summary.rst",
            category="Baseline",
            labels={"pair": "{pair}", "figure": "formation summary"},
        ),
        figure=figure(
            result_path("summary/{pair}_formation"),
            caption="../report/formation_summary_figure.rst",
            category="Baseline",
            labels={"pair": "{pair}", "figure": "baselines per day"},
        ),
    log:
        log_path("formation_summary/{pair}.log"),
    benchmark:
        benchmark_path("formation_summary/{pair}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    params:
        files=lambda w: formation_summary_files(w.pair),
        phases=pair_phases,
        title=pair_title,
    script:
        "../../scripts/formation_summary.py"


# Baseline overlap: the solutions of a day and of the next campaign day over the span their
# arcs share (6 h for 30-h arcs), in the leader's RTN (paper 003: 0.5-0.8 mm 3D).
rule baseline_overlap:
    input:
        unpack(baseline_overlap_inputs),
        code=library_code("baseline_overlap"),
    output:
        nc=result_path("baseline_overlap/{pair}/{date}.nc"),
    log:
        log_path("baseline_overlap/{pair}/{date}.log"),
    benchmark:
        benchmark_path("baseline_overlap/{pair}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../../scripts/baseline_overlap.py"
