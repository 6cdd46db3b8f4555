# baseline: a formation pair (satellites.<follower>.formation.leader) estimated jointly with
# its fixed inter-satellite double-difference ambiguities (leopod.estimation.baseline); only
# in campaigns with a formation pair.
rule baseline:
    input:
        unpack(baseline_inputs),
        code=library_code("baseline"),
    output:
        nc=result_path("baseline/{pair}/{date}.nc"),
        dd=result_path("baseline/{pair}/{date}_dd.nc"),
        # the two orbits of the DD-fixed baseline solution
        sp3_leader=result_path("baseline/{pair}/{date}_leader.sp3"),
        sp3_follower=result_path("baseline/{pair}/{date}_follower.sp3"),
        figure=figure(
            result_path("baseline/{pair}/{date}_rtn"),
            caption="../report/baseline_rtn.rst",
            category="Baseline",
            labels={"pair": "{pair}", "day": "{date}", "figure": "baseline RTN"},
        ),
        histogram=figure(
            result_path("baseline/{pair}/{date}_dd_fractions"),
            caption="../report/baseline_dd_fractions.rst",
            category="Baseline",
            labels={"pair": "{pair}", "day": "{date}", "figure": "DD fractional parts"},
        ),
    log:
        log_path("baseline/{pair}/{date}.log"),
    benchmark:
        benchmark_path("baseline/{pair}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=6000,
        runtime=30,
    params:
        signals=CONFIG["signals"],
        pod=lambda w: pair_config(w.pair)["pod"],
        settings=lambda w: pair_config(w.pair)["ambiguity"],
        code_bias=CONFIG["code_bias"],
        baseline=CONFIG["baseline"],
        pair=baseline_pair_params,
    script:
        "../../scripts/baseline.py"
