# quality: data-quality indicators of one satellite-day (Wang et al. 2024, Table 2;
# Peng et al. 2021, sec. II-B), with the antenna-frame geometry of every observation and figures
# for the report.
rule quality:
    input:
        unpack(quality_antenna),
        unpack(attitude_inputs),
        unpack(antenna_inputs),
        unpack(day_signal_bias_inputs),
        obs=rules.ingest.output.obs,
        gnss=rules.ingest.output.gnss,
        leo=rules.ingest.output.leo,
        code=library_code("quality"),
    output:
        nc=result_path("quality/{sat}/{date}.nc"),
        summary=report(
            result_path("quality/{sat}/{date}_summary.html"),
            caption="../report/quality_summary.rst",
            category="Data quality",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "indicators"},
        ),
        mp_elevation=figure(
            result_path("quality/{sat}/{date}_mp_elevation"),
            caption="../report/quality_mp_elevation.rst",
            category="Data quality",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "MP vs elevation"},
        ),
        skyplot=figure(
            result_path("quality/{sat}/{date}_skyplot"),
            caption="../report/quality_skyplot.rst",
            category="Data quality",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "sky plot"},
        ),
        noise=figure(
            result_path("quality/{sat}/{date}_code_noise"),
            caption="../report/quality_code_noise.rst",
            category="Data quality",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "code noise"},
        ),
        visibility=figure(
            result_path("quality/{sat}/{date}_visibility"),
            caption="../report/quality_visibility.rst",
            category="Data quality",
            labels={"satellite": "{sat}", "day": "{date}", "figure": "visibility and IOD"},
        ),
    log:
        log_path("quality/{sat}/{date}.log"),
    benchmark:
        benchmark_path("quality/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=15,
    params:
        signals=CONFIG["signals"],
        settings=CONFIG["quality"],
        bds2_scb=CONFIG["code_bias"]["bds2_scb"],
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        signal_bias=day_signal_bias,
        gnss_attitude=CONFIG["pod"]["gnss_attitude"],
        title=sat_title,
    script:
        "../../scripts/quality.py"
