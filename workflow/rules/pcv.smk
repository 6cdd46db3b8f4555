# pcv_neq: for the direct method (pcv.method: direct), the day's normal equations of the PCV
# nodes (and PCO-Z): the fixed (else float) POD linearised at its float solution with the antenna
# columns, every arc parameter and ambiguity reduced out (leopod.antenna.pcv_direct); float_pod's
# rule with the float solution (and the ambiguity table) as further inputs.
use rule float_pod as pcv_neq with:
    input:
        unpack(pcv_neq_inputs),
        script=f"{workflow.basedir}/scripts/pcv_neq.py",
        code=library_code("pcv_neq"),
    output:
        neq=result_path("pcv_neq/{sat}/{date}.nc"),
    log:
        log_path("pcv_neq/{sat}/{date}.log"),
    benchmark:
        benchmark_path("pcv_neq/{sat}/{date}.tsv")
    params:
        step="pcv_neq",
        signals=CONFIG["signals"],
        pod=line_pod,
        settings=line_ambiguity,
        pcv=CONFIG["pcv"],
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        code_bias=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        signal_bias=arc_signal_bias,


# pcv: receiver phase-centre variations of one satellite line and period (pcv.enabled) by the
# residual method (Wang et al. 2024, eqs. 12-13: the ionosphere-free phase residuals of the POD
# days stacked on an antenna-frame grid) or the direct method (eqs. 10-11: the days' normal
# equations of pcv_neq summed and solved with the datum conditions). The ANTEX it writes (the
# POD's PCO and PCV + the map) is applied by a further campaign through satellites.<sat>.antenna
# (type "LEOPOD PCV").
rule pcv:
    input:
        unpack(pcv_inputs),
        code=library_code("pcv"),
    output:
        nc=result_path("pcv/{sat}/{period}.nc"),
        antex=result_path("pcv/{sat}/{period}.atx"),
        map=figure(
            result_path("pcv/{sat}/{period}_map"),
            caption="../report/pcv_map.rst",
            category="Antenna PCV",
            labels={"satellite": "{sat}", "period": "{period}", "figure": "PCV map"},
        ),
    log:
        log_path("pcv/{sat}/{period}.log"),
    benchmark:
        benchmark_path("pcv/{sat}/{period}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=10,
    params:
        settings=CONFIG["pcv"],
        solution=pcv_solution,
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        title=pcv_title,
    script:
        "../../scripts/pcv.py"


# pcv_stack: the maps of all PCV periods stacked (inverse-variance mean per node, the datum
# applied again), with the differences between consecutive periods (map stability).
rule pcv_stack:
    input:
        unpack(pcv_stack_inputs),
        maps=expand(rules.pcv.output.nc, period=PCV_PERIODS, allow_missing=True),
        code=library_code("pcv_stack"),
    output:
        nc=result_path("pcv/{sat}/stack.nc"),
        antex=result_path("pcv/{sat}/stack.atx"),
        differences=result_path("pcv/{sat}/stack_differences.csv"),
        map=figure(
            result_path("pcv/{sat}/stack_map"),
            caption="../report/pcv_stack.rst",
            category="Antenna PCV",
            labels={"satellite": "{sat}", "period": "all", "figure": "stacked PCV map"},
        ),
    log:
        log_path("pcv/{sat}/stack.log"),
    benchmark:
        benchmark_path("pcv/{sat}/stack.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        settings=CONFIG["pcv"],
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        title=sat_name,
    script:
        "../../scripts/pcv_stack.py"
