# gnss_products: the day's GNSS orbits (SP3), clocks (RINEX clock) and satellite antennas
# (ANTEX, the satellites of the campaign's systems) parsed once into netCDF, which ingest and
# every POD arc containing the day read instead of the text files.
rule gnss_products:
    input:
        unpack(gnss_product_inputs),
        code=library_code("gnss_products"),
    output:
        **gnss_product_outputs(),
    log:
        log_path("gnss_products/{date}.log"),
    benchmark:
        benchmark_path("gnss_products/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        systems=sorted(CONFIG["signals"]),
    script:
        "../../scripts/gnss_products.py"


# ingest: raw RINEX + the day's GNSS products (gnss_products) -> canonical observations, GNSS
# orbits/clocks at the observation epochs, and the a-priori LEO orbit (netCDF).
rule ingest:
    input:
        unpack(ingest_inputs),
        unpack(attitude_inputs),
        unpack(antenna_inputs),
        code=library_code("ingest"),
    output:
        obs=result_path("ingest/{sat}/{date}_obs.nc"),
        gnss=result_path("ingest/{sat}/{date}_gnss.nc"),
        leo=result_path("ingest/{sat}/{date}_leo.nc"),
    log:
        log_path("ingest/{sat}/{date}.log"),
    benchmark:
        benchmark_path("ingest/{sat}/{date}.tsv")
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=15,
    params:
        signals=CONFIG["signals"],
        pco_body_m=sat_pco,
        leo_antenna=sat_antenna,
        attitude=sat_attitude,
        sp3_id=sat_sp3_id,
    script:
        "../../scripts/ingest.py"
