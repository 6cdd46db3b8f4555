# ingest: raw RINEX + GNSS products -> canonical observations, GNSS orbits/clocks at the
# observation epochs, and the a-priori LEO orbit (netCDF).
rule ingest:
    input:
        unpack(ingest_inputs),
        code=library_code("ingest"),
    output:
        obs="results/ingest/{sat}/{date}_obs.nc",
        gnss="results/ingest/{sat}/{date}_gnss.nc",
        leo="results/ingest/{sat}/{date}_leo.nc",
    log:
        "logs/ingest/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/ingest/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=15,
    params:
        signals=CONFIG["signals"],
        pco_body_m=sat_pco,
        sp3_id=sat_sp3_id,
    script:
        "../../scripts/ingest.py"
