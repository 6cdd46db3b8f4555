# float_pod: reduced-dynamic orbit from ionosphere-free code and phase with float ambiguities
# (30-h arcs centred on the day by default, using the neighbouring days when they exist).
rule float_pod:
    input:
        unpack(float_pod_inputs),
        script=f"{workflow.basedir}/scripts/float_pod.py",
        code=library_code("float_pod"),
    output:
        **pod_outputs("float_pod", "Float POD"),
        **float_linearisation(),
    log:
        log_path("float_pod/{sat}/{date}.log"),
    benchmark:
        benchmark_path("float_pod/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=pod_mem_mb,
        runtime=30,
    params:
        step="float_pod",
        signals=CONFIG["signals"],
        pod=line_pod,
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        macro_model=sat_macro_model,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,
    script:
        # the step's own script (a path with params, so that fixed_pod can reuse this rule);
        # listed as an input too, since Snakemake sees no change of such a path
        "../../scripts/{params.step}.py"


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
        table=result_path("ambiguity/{sat}/{date}.nc"),
        histogram=figure(
            result_path("ambiguity/{sat}/{date}_fractions"),
            caption="../report/ambiguity_fractions.rst",
            category="Ambiguity resolution",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "fractional parts"},
        ),
    log:
        log_path("ambiguity/{sat}/{date}.log"),
    benchmark:
        benchmark_path("ambiguity/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=10,
    params:
        signals=CONFIG["signals"],
        pod=line_pod,
        settings=line_ambiguity,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,
        title=sat_title,
    script:
        "../../scripts/ambiguity.py"


# fixed_pod: the float POD re-solved with the fixed single differences as tight constraints:
# float_pod's rule with the float solution and the ambiguity table as further inputs and the
# ambiguity settings as a further param.
use rule float_pod as fixed_pod with:
    input:
        unpack(float_pod_inputs),
        table=rules.ambiguity.output.table,
        float_orbit=rules.float_pod.output.orbit,
        float_parameters=rules.float_pod.output.parameters,
        float_ambiguities=rules.float_pod.output.ambiguities,
        float_residuals=rules.float_pod.output.residuals,
        **float_linearisation(),
        script=f"{workflow.basedir}/scripts/fixed_pod.py",
        code=library_code("fixed_pod"),
    output:
        **pod_outputs("fixed_pod", "Fixed POD"),
    log:
        log_path("fixed_pod/{sat}/{date}.log"),
    benchmark:
        benchmark_path("fixed_pod/{sat}/{date}.tsv")
    params:
        step="fixed_pod",
        signals=CONFIG["signals"],
        pod=line_pod,
        settings=line_ambiguity,
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        macro_model=sat_macro_model,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,
