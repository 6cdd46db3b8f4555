# code_bias: antenna-frame code-bias maps (Peng et al. 2021, sec. II; Jiang et al. 2023) of one
# satellite and period from the multipath series of the quality step; code_bias_stack: the maps of
# all periods stacked, with the differences between consecutive periods (map stability).
rule code_bias:
    input:
        unpack(code_bias_inputs),
        code=library_code("code_bias"),
    output:
        nc=result_path("code_bias/{sat}/{period}.nc"),
        statistics=result_path("code_bias/{sat}/{period}_statistics.csv"),
        maps=figure(
            result_path("code_bias/{sat}/{period}_maps"),
            caption="../report/code_bias_maps.rst",
            category="Code-bias maps",
            labels={"satellite": "{sat}", "period": "{period}", "figure": "maps"},
        ),
        counts=figure(
            result_path("code_bias/{sat}/{period}_counts"),
            caption="../report/code_bias_counts.rst",
            category="Code-bias maps",
            labels={"satellite": "{sat}", "period": "{period}", "figure": "observations"},
        ),
        mp_elevation=figure(
            result_path("code_bias/{sat}/{period}_mp_elevation"),
            caption="../report/code_bias_mp_elevation.rst",
            category="Code-bias maps",
            labels={"satellite": "{sat}", "period": "{period}", "figure": "MP before/after"},
        ),
    log:
        log_path("code_bias/{sat}/{period}.log"),
    benchmark:
        benchmark_path("code_bias/{sat}/{period}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=4000,
        runtime=30,
    params:
        settings=CONFIG["code_bias"],
        yaw_flips=sat_yaw_flips,
        title=period_title,
    script:
        "../../scripts/code_bias.py"


rule code_bias_stack:
    input:
        maps=expand(rules.code_bias.output.nc, period=PERIODS, allow_missing=True),
        code=library_code("code_bias_stack"),
    output:
        nc=result_path("code_bias/{sat}/stack.nc"),
        differences=result_path("code_bias/{sat}/stack_differences.csv"),
        maps=figure(
            result_path("code_bias/{sat}/stack_maps"),
            caption="../report/code_bias_stack.rst",
            category="Code-bias maps",
            labels={"satellite": "{sat}", "period": "all", "figure": "stacked maps"},
        ),
        difference=figure(
            result_path("code_bias/{sat}/stack_differences"),
            caption="../report/code_bias_differences.rst",
            category="Code-bias maps",
            labels={"satellite": "{sat}", "period": "all", "figure": "period differences"},
        ),
    log:
        log_path("code_bias/{sat}/stack.log"),
    benchmark:
        benchmark_path("code_bias/{sat}/stack.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        title=sat_name,
    script:
        "../../scripts/code_bias_stack.py"
