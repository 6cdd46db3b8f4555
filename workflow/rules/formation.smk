# Inter-satellite range of a formation pair and the range check of its baselines. The simulator
# writes a K-band-like range (truth + white noise, simulate.range_sigma_m) in the layout of
# GRACE's grc_kb_rng.csv; range_check compares the length of every baseline solution (reduced-
# dynamic float and DD-fixed, kinematic per system) with it (leopod.validation.formation).


rule simulate_range:
    input:
        a=lambda w: fill(rules.simulate.output.truth_nc, sat=PAIRS[w.pair][0], date=w.date),
        b=lambda w: fill(rules.simulate.output.truth_nc, sat=PAIRS[w.pair][1], date=w.date),
        code=library_code("simulate_range"),
    output:
        csv="resources/simulate/{pair}/{date}_range.csv",
    log:
        "logs/simulate_range/{pair}/{date}.log",
    benchmark:
        "logs/benchmarks/simulate_range/{pair}/{date}.tsv"
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
        nc="results/range_check/{pair}/{date}.nc",
        figure=report(
            "results/range_check/{pair}/{date}.png",
            caption="../report/range_check.rst",
            category="Baseline",
            labels={"pair": "{pair}", "day": "{date}", "figure": "range check"},
        ),
    log:
        "logs/range_check/{pair}/{date}.log",
    benchmark:
        "logs/benchmarks/range_check/{pair}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        title=lambda w: " - ".join(reversed(PAIRS[w.pair])),
    script:
        "../../scripts/range_check.py"
