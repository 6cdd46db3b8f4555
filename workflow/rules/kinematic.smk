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
        nc=result_path("kinematic_pod/{sat}/{date}.nc"),
        sp3=result_path("kinematic_pod/{sat}/{date}.sp3"),
        figure=figure(
            result_path("kinematic_pod/{sat}/{date}_rtn"),
            caption="../report/kinematic_rtn.rst",
            category="Kinematic POD",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "kinematic minus float"},
        ),
    log:
        log_path("kinematic_pod/{sat}/{date}.log"),
    benchmark:
        benchmark_path("kinematic_pod/{sat}/{date}.tsv")
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
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        title=sat_title,
        sp3_id=sat_pod_sp3_id,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,
    script:
        "../../scripts/kinematic_pod.py"


# kinematic_baseline: epoch-wise baseline of a formation pair from receiver single differences
# (follower estimated, leader held at its float orbit), float and with the fixed DDs of the
# baseline step, one solution per GNSS of kinematic.baseline_systems, compared with the
# reduced-dynamic baseline and (simulated pairs) the truth
# (leopod.estimation.kinematic_baseline).
rule kinematic_baseline:
    input:
        unpack(kinematic_baseline_inputs),
        code=library_code("kinematic_baseline"),
    output:
        nc=result_path("kinematic_baseline/{pair}/{date}.nc"),
        figure=figure(
            result_path("kinematic_baseline/{pair}/{date}_minus_dynamic"),
            caption="../report/kinematic_baseline.rst",
            category="Baseline",
            labels={"pair": "{pair}", "day": "{date}", "figure": "kinematic minus dynamic"},
        ),
    log:
        log_path("kinematic_baseline/{pair}/{date}.log"),
    benchmark:
        benchmark_path("kinematic_baseline/{pair}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=6000,
        runtime=30,
    params:
        signals=CONFIG["signals"],
        pod=CONFIG["pod"],
        kinematic=CONFIG["kinematic"],
        settings=CONFIG["ambiguity"],
        code_bias=CONFIG["code_bias"],
        pair=baseline_pair_params,
    script:
        "../../scripts/kinematic_baseline.py"
