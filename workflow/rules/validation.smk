# Validation (issue 8): overlaps of consecutive arcs, orbits against a reference orbit (the
# simulated truth or an external orbit), laser ranging residuals, and the campaign summary.
# One job per satellite-day validates all POD solutions of the campaign (float_pod, fixed_pod),
# one file each in <step>/{sat}/{solution}/: a job of its own per solution cost more in
# starting it than in the comparison (issue 18).

OVERLAP_NC = result_path("overlap/{sat}/{solution}/{date}.nc")
REFERENCE_NC = result_path("reference_orbit/{sat}/{solution}/{date}.nc")
SLR_NC = result_path("slr/{sat}/{solution}/{date}.nc")


# Two consecutive arcs over their common span (30-h arcs: 6 h), RTN and 3D.
rule overlap:
    input:
        unpack(overlap_inputs),
        code=library_code("overlap"),
    output:
        nc=each_solution(OVERLAP_NC),
    log:
        log_path("overlap/{sat}/{date}.log"),
    benchmark:
        benchmark_path("overlap/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        trim_s=CONFIG["validation"]["overlap_trim_s"],
        solutions=VALIDATED,
        title=sat_title,
    script:
        "../../scripts/overlap.py"


# Campaign overlap statistics per arc pair and mean +- STD, float and fixed (Jiang et al. 2023,
# Fig. 13).
rule overlap_summary:
    input:
        unpack(per_day_validation(OVERLAP_NC, days=OVERLAP_DAYS)),
        code=library_code("overlap_summary"),
    output:
        nc=result_path("overlap/{sat}/summary.nc"),
        csv=result_path("overlap/{sat}/summary.csv"),
        html=report(
            result_path("overlap/{sat}/summary.html"),
            caption="../report/overlap_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "overlap table"},
        ),
        figure=figure(
            result_path("overlap/{sat}/overlaps"),
            caption="../report/overlap_figure.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "overlaps"},
        ),
    log:
        log_path("overlap_summary/{sat}.log"),
    benchmark:
        benchmark_path("overlap_summary/{sat}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        solutions=solutions(),
        title=sat_name,
    script:
        "../../scripts/overlap_summary.py"


# The POD arcs minus the reference orbit over their day (simulated campaigns: the truth).
rule reference_orbit:
    input:
        unpack(pod_orbits),
        reference=reference_files,
        code=library_code("reference_orbit"),
    output:
        nc=each_solution(REFERENCE_NC),
    log:
        log_path("reference_orbit/{sat}/{date}.log"),
    benchmark:
        benchmark_path("reference_orbit/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        reference_id=sat_reference_id,
        time_system=sat_reference_time_system,
        solutions=VALIDATED,
        title=sat_title,
    script:
        "../../scripts/reference_orbit.py"


# Daily and campaign statistics of the reference-orbit differences (Wang et al. 2024, Table 4).
rule reference_summary:
    input:
        unpack(per_day_validation(REFERENCE_NC)),
        code=library_code("reference_summary"),
    output:
        nc=result_path("reference_orbit/{sat}/summary.nc"),
        csv=result_path("reference_orbit/{sat}/summary.csv"),
        html=report(
            result_path("reference_orbit/{sat}/summary.html"),
            caption="../report/reference_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "reference-orbit table"},
        ),
        differences=figure(
            result_path("reference_orbit/{sat}/differences"),
            caption="../report/reference_differences.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "orbit minus reference"},
        ),
        daily=figure(
            result_path("reference_orbit/{sat}/daily"),
            caption="../report/reference_daily.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "daily RMS vs reference"},
        ),
    log:
        log_path("reference_summary/{sat}.log"),
    benchmark:
        benchmark_path("reference_summary/{sat}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        solutions=solutions(),
        title=sat_name,
    script:
        "../../scripts/reference_summary.py"


# Laser ranging residuals of the arcs' day (station motion, eccentricities, light time,
# troposphere, relativity; screening).
rule slr:
    input:
        unpack(slr_inputs),
        unpack(attitude_inputs),
        code=library_code("slr"),
    output:
        nc=each_solution(SLR_NC),
    log:
        log_path("slr/{sat}/{date}.log"),
    benchmark:
        benchmark_path("slr/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        settings=CONFIG["validation"]["slr"],
        retro_offset_body_m=retro_offset,
        attitude=sat_attitude,
        solutions=VALIDATED,
        title=sat_title,
    script:
        "../../scripts/slr.py"


# SLR statistics per station, per elevation bin and projected on R/T/N, float and fixed.
rule slr_summary:
    input:
        unpack(per_day_validation(SLR_NC)),
        code=library_code("slr_summary"),
    output:
        nc=result_path("slr/{sat}/summary.nc"),
        stations_csv=result_path("slr/{sat}/stations.csv"),
        stations_html=report(
            result_path("slr/{sat}/stations.html"),
            caption="../report/slr_stations_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR per station (table)"},
        ),
        elevation_csv=result_path("slr/{sat}/elevation.csv"),
        stations_png=figure(
            result_path("slr/{sat}/stations"),
            caption="../report/slr_stations.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR per station"},
        ),
        elevation_png=figure(
            result_path("slr/{sat}/elevation"),
            caption="../report/slr_elevation.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR vs elevation"},
        ),
        time_png=figure(
            result_path("slr/{sat}/residuals"),
            caption="../report/slr_time.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR residuals"},
        ),
    log:
        log_path("slr_summary/{sat}.log"),
    benchmark:
        benchmark_path("slr_summary/{sat}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        settings=CONFIG["validation"]["slr"],
        solutions=solutions(),
        title=sat_name,
    script:
        "../../scripts/slr_summary.py"


# Campaign summary: per day and solution the residual RMS (all and per GNSS system), fixing
# rates (graph rank and share of SDs), overlap, reference orbit and SLR statistics and the PCO-Z
# estimates (the tables of the source papers), as netCDF, CSV and an HTML table, with the PCO-Z
# (float vs fixed) and fixing-rate figures.
rule campaign_summary:
    input:
        summary_inputs,
        code=library_code("campaign_summary"),
    output:
        nc=result_path("summary/{sat}.nc"),
        csv=result_path("summary/{sat}.csv"),
        html=report(
            result_path("summary/{sat}.html"),
            caption="../report/campaign_summary.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "campaign summary"},
        ),
        pco_z_png=figure(
            result_path("summary/{sat}_pco_z"),
            caption="../report/summary_pco_z.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "PCO-Z float vs fixed"},
        ),
        fixing_png=figure(
            result_path("summary/{sat}_fixing_rates"),
            caption="../report/summary_fixing_rates.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "fixing rates"},
        ),
        isb_png=figure(
            result_path("summary/{sat}_isb"),
            caption="../report/summary_isb.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "inter-system biases"},
        ),
    log:
        log_path("campaign_summary/{sat}.log"),
    benchmark:
        benchmark_path("campaign_summary/{sat}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        solutions=solutions(),
        days=DAYS,
        files=campaign_summary_files,
        title=sat_name,
        phases={x: CONFIG["signals"][x]["phase"] for x in CONFIG["signals"]},
        quality_gate=CONFIG["pod"]["quality_gate"],
        excluded=excluded_days(CONFIG),
    script:
        "../../scripts/campaign_summary.py"


# Solution variants (config 'variants'): the campaign summaries of a satellite's POD lines side
# by side, mean +- STD over the days (e.g. GPS, BDS-3 and GPS + BDS-3; Jiang et al. 2023).
rule variant_comparison:
    input:
        summaries=line_summaries,
        code=library_code("variant_comparison"),
    output:
        csv=result_path("summary/{sat}_variants.csv"),
        html=report(
            result_path("summary/{sat}_variants.html"),
            caption="../report/variant_comparison.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "solution variants"},
        ),
    log:
        log_path("variant_comparison/{sat}.log"),
    benchmark:
        benchmark_path("variant_comparison/{sat}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        lines=sat_lines,
        title=sat_name,
    script:
        "../../scripts/variant_comparison.py"
