# float_pod: reduced-dynamic orbit from ionosphere-free code and phase with float ambiguities
# (30-h arcs centred on the day by default, using the neighbouring days when they exist).
rule float_pod:
    input:
        unpack(float_pod_inputs),
        code=library_code("float_pod"),
    output:
        orbit="results/float_pod/{sat}/{date}_orbit.nc",
        sp3="results/float_pod/{sat}/{date}.sp3",
        residuals="results/float_pod/{sat}/{date}_residuals.nc",
        parameters="results/float_pod/{sat}/{date}_parameters.nc",
        ambiguities="results/float_pod/{sat}/{date}_ambiguities.nc",
        res_time=report(
            "results/float_pod/{sat}/{date}_residuals_time.png",
            caption="../report/pod_residuals_time.rst",
            category="Float POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "residuals vs time"},
        ),
        res_elevation=report(
            "results/float_pod/{sat}/{date}_residuals_elevation.png",
            caption="../report/pod_residuals_elevation.rst",
            category="Float POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "residuals vs elevation"},
        ),
        res_skymap=report(
            "results/float_pod/{sat}/{date}_residual_skymap.png",
            caption="../report/pod_residual_skymap.rst",
            category="Float POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "phase residual map"},
        ),
        apriori=report(
            "results/float_pod/{sat}/{date}_apriori_rtn.png",
            caption="../report/pod_apriori_rtn.rst",
            category="Float POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "RTN vs a-priori"},
        ),
    log:
        "logs/float_pod/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/float_pod/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=pod_mem_mb,
        runtime=30,
    params:
        signals=config["signals"],
        pod=config["pod"],
        pco_body_m=sat_pco,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=config["code_bias"],
        yaw_flips=sat_yaw_flips,
    script:
        "../../scripts/float_pod.py"


# ambiguity: wide-lane/narrow-lane fixing of the single-differenced float ambiguities
# (Peng et al. 2021, sec. III-B; Jiang et al. 2023) with the campaign's AR product (CNES/CLS WL
# biases + integer clocks, or Bias-SINEX OSB); without a product nothing is fixed and the table
# says so.
rule ambiguity:
    input:
        unpack(ambiguity_inputs),
        ambiguities=rules.float_pod.output.ambiguities,
        residuals=rules.float_pod.output.residuals,
        code=library_code("ambiguity"),
    output:
        table="results/ambiguity/{sat}/{date}.nc",
        histogram=report(
            "results/ambiguity/{sat}/{date}_fractions.png",
            caption="../report/ambiguity_fractions.rst",
            category="Ambiguity resolution",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "fractional parts"},
        ),
    log:
        "logs/ambiguity/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/ambiguity/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=10,
    params:
        signals=config["signals"],
        pod=config["pod"],
        settings=config["ambiguity"],
        code_bias=config["code_bias"],
        yaw_flips=sat_yaw_flips,
        title=sat_title,
    script:
        "../../scripts/ambiguity.py"


# fixed_pod: the float POD re-solved with the fixed single differences as tight constraints:
# float_pod's inputs plus the float solution and the ambiguity table, its params plus the
# ambiguity settings, its environment and resources. (Not "use rule float_pod as fixed_pod
# with:", which cannot replace the script.)
rule fixed_pod:
    input:
        unpack(float_pod_inputs),
        table=rules.ambiguity.output.table,
        float_orbit=rules.float_pod.output.orbit,
        float_parameters=rules.float_pod.output.parameters,
        float_ambiguities=rules.float_pod.output.ambiguities,
        float_residuals=rules.float_pod.output.residuals,
        code=library_code("fixed_pod"),
    output:
        orbit="results/fixed_pod/{sat}/{date}_orbit.nc",
        sp3="results/fixed_pod/{sat}/{date}.sp3",
        residuals="results/fixed_pod/{sat}/{date}_residuals.nc",
        parameters="results/fixed_pod/{sat}/{date}_parameters.nc",
        ambiguities="results/fixed_pod/{sat}/{date}_ambiguities.nc",
        res_time=report(
            "results/fixed_pod/{sat}/{date}_residuals_time.png",
            caption="../report/pod_residuals_time.rst",
            category="Fixed POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "residuals vs time"},
        ),
        res_elevation=report(
            "results/fixed_pod/{sat}/{date}_residuals_elevation.png",
            caption="../report/pod_residuals_elevation.rst",
            category="Fixed POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "residuals vs elevation"},
        ),
        res_skymap=report(
            "results/fixed_pod/{sat}/{date}_residual_skymap.png",
            caption="../report/pod_residual_skymap.rst",
            category="Fixed POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "phase residual map"},
        ),
        apriori=report(
            "results/fixed_pod/{sat}/{date}_apriori_rtn.png",
            caption="../report/pod_apriori_rtn.rst",
            category="Fixed POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "RTN vs a-priori"},
        ),
    log:
        "logs/fixed_pod/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/fixed_pod/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=pod_mem_mb,
        runtime=30,
    params:
        signals=config["signals"],
        pod=config["pod"],
        settings=config["ambiguity"],
        pco_body_m=sat_pco,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=config["code_bias"],
        yaw_flips=sat_yaw_flips,
    script:
        "../../scripts/fixed_pod.py"
