# kinematic_pod: epoch-wise positions and receiver clocks from undifferenced IF code and phase
# with the pass ambiguities shared across epochs (float, or with the fixed single differences
# of the ambiguity step: kinematic.ambiguities), linearised at the float reduced-dynamic orbit
# of the arc (leopod.estimation.kinematic). Runs when kinematic.enabled.


rule kinematic_pod:
    input:
        unpack(kinematic_inputs),
        script=f"{workflow.basedir}/scripts/kinematic_pod.py",
        code=library_code("kinematic_pod"),
    output:
        nc="results/kinematic_pod/{sat}/{date}.nc",
        sp3="results/kinematic_pod/{sat}/{date}.sp3",
        figure=report(
            "results/kinematic_pod/{sat}/{date}_rtn.png",
            caption="../report/kinematic_rtn.rst",
            category="Kinematic POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "kinematic minus float"},
        ),
    log:
        "logs/kinematic_pod/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/kinematic_pod/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=pod_mem_mb,
        runtime=30,
    params:
        signals=CONFIG["signals"],
        pod=line_pod,
        kinematic=CONFIG["kinematic"],
        settings=line_ambiguity,
        pco_body_m=sat_pco,
        attitude=sat_attitude,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,
    script:
        "../../scripts/kinematic_pod.py"
