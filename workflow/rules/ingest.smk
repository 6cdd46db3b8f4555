# ingest: raw RINEX + GNSS products -> canonical observations, GNSS orbits/clocks at the
# observation epochs, and the a-priori LEO orbit (netCDF).
rule ingest:
    params:
        signals=config["signals"],
        pco_body_m=sat_pco,
        sp3_id=sat_sp3_id,
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
        "benchmarks/ingest/{sat}/{date}.tsv"
    threads: 1
    resources:
        mem_mb=3000,
        runtime=15,
    conda:
        "../../envs/leopod.yaml"
    script:
        "../../scripts/ingest.py"
