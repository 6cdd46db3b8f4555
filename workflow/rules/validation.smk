# Validation (issue 8): overlaps of consecutive arcs, orbits against a reference orbit (the
# simulated truth or an external orbit), laser ranging residuals, and the campaign summary.
# {solution} is float_pod or fixed_pod.


# Two consecutive arcs over their common span (30-h arcs: 6 h), RTN and 3D.
rule overlap:
    input:
        unpack(overlap_inputs),
        code=library_code("overlap"),
    output:
        nc="results/overlap/{sat}/{solution}/{date}.nc",
    log:
        "logs/overlap/{sat}/{solution}/{date}.log",
    benchmark:
        "logs/benchmarks/overlap/{sat}/{solution}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    params:
        trim_s=CONFIG["validation"]["overlap_trim_s"],
        title=solution_title,
    script:
        "../../scripts/overlap.py"


# Campaign overlap statistics per arc pair and mean +- STD, float and fixed (Jiang et al. 2023,
# Fig. 13).
rule overlap_summary:
    input:
        unpack(per_day_validation(rules.overlap.output.nc, days=OVERLAP_DAYS)),
        code=library_code("overlap_summary"),
    output:
        nc="results/overlap/{sat}/summary.nc",
        csv=report(
            "results/overlap/{sat}/summary.csv",
            caption="../report/overlap_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "overlap table"},
        ),
        figure=figure(
            "results/overlap/{sat}/overlaps",
            caption="../report/overlap_figure.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "overlaps"},
        ),
    log:
        "logs/overlap_summary/{sat}.log",
    benchmark:
        "logs/benchmarks/overlap_summary/{sat}.tsv"
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


# A POD arc minus the reference orbit over its day (simulated campaigns: the truth).
rule reference_orbit:
    input:
        orbit=pod_orbit,
        reference=reference_files,
        code=library_code("reference_orbit"),
    output:
        nc="results/reference_orbit/{sat}/{solution}/{date}.nc",
    log:
        "logs/reference_orbit/{sat}/{solution}/{date}.log",
    benchmark:
        "logs/benchmarks/reference_orbit/{sat}/{solution}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        reference_id=sat_reference_id,
        time_system=sat_reference_time_system,
        solution=solution_name,
        title=sat_title,
    script:
        "../../scripts/reference_orbit.py"


# Daily and campaign statistics of the reference-orbit differences (Wang et al. 2024, Table 4).
rule reference_summary:
    input:
        unpack(per_day_validation(rules.reference_orbit.output.nc)),
        code=library_code("reference_summary"),
    output:
        nc="results/reference_orbit/{sat}/summary.nc",
        csv=report(
            "results/reference_orbit/{sat}/summary.csv",
            caption="../report/reference_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "reference-orbit table"},
        ),
        differences=figure(
            "results/reference_orbit/{sat}/differences",
            caption="../report/reference_differences.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "orbit minus reference"},
        ),
        daily=figure(
            "results/reference_orbit/{sat}/daily",
            caption="../report/reference_daily.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "daily RMS vs reference"},
        ),
    log:
        "logs/reference_summary/{sat}.log",
    benchmark:
        "logs/benchmarks/reference_summary/{sat}.tsv"
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


# Laser ranging residuals of one arc's day (station motion, eccentricities, light time,
# troposphere, relativity; screening).
rule slr:
    input:
        unpack(slr_inputs),
        unpack(attitude_inputs),
        code=library_code("slr"),
    output:
        nc="results/slr/{sat}/{solution}/{date}.nc",
    log:
        "logs/slr/{sat}/{solution}/{date}.log",
    benchmark:
        "logs/benchmarks/slr/{sat}/{solution}/{date}.tsv"
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
        solution=solution_name,
        title=sat_title,
    script:
        "../../scripts/slr.py"


# SLR statistics per station, per elevation bin and projected on R/T/N, float and fixed.
rule slr_summary:
    input:
        unpack(per_day_validation(rules.slr.output.nc)),
        code=library_code("slr_summary"),
    output:
        nc="results/slr/{sat}/summary.nc",
        stations_csv=report(
            "results/slr/{sat}/stations.csv",
            caption="../report/slr_stations_table.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR per station (table)"},
        ),
        elevation_csv="results/slr/{sat}/elevation.csv",
        stations_png=figure(
            "results/slr/{sat}/stations",
            caption="../report/slr_stations.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR per station"},
        ),
        elevation_png=figure(
            "results/slr/{sat}/elevation",
            caption="../report/slr_elevation.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR vs elevation"},
        ),
        time_png=figure(
            "results/slr/{sat}/residuals",
            caption="../report/slr_time.rst",
            category="Validation",
            labels={"satellite": "{sat}", "figure": "SLR residuals"},
        ),
    log:
        "logs/slr_summary/{sat}.log",
    benchmark:
        "logs/benchmarks/slr_summary/{sat}.tsv"
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
        nc="results/summary/{sat}.nc",
        csv="results/summary/{sat}.csv",
        html=report(
            "results/summary/{sat}.html",
            caption="../report/campaign_summary.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "campaign summary"},
        ),
        pco_z_png=figure(
            "results/summary/{sat}_pco_z",
            caption="../report/summary_pco_z.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "PCO-Z float vs fixed"},
        ),
        fixing_png=figure(
            "results/summary/{sat}_fixing_rates",
            caption="../report/summary_fixing_rates.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "fixing rates"},
        ),
        isb_png=figure(
            "results/summary/{sat}_isb",
            caption="../report/summary_isb.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "inter-system biases"},
        ),
    log:
        "logs/campaign_summary/{sat}.log",
    benchmark:
        "logs/benchmarks/campaign_summary/{sat}.tsv"
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
        csv="results/summary/{sat}_variants.csv",
        html=report(
            "results/summary/{sat}_variants.html",
            caption="../report/variant_comparison.rst",
            category="Summary",
            labels={"satellite": "{sat}", "figure": "solution variants"},
        ),
    log:
        "logs/variant_comparison/{sat}.log",
    benchmark:
        "logs/benchmarks/variant_comparison/{sat}.tsv"
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
