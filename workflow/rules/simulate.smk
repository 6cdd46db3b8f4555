# simulate: the optional data source of simulated satellites. Writes the same file formats as
# real archives (RINEX, SP3, RINEX clock) under resources/simulate/, plus the truth.
rule simulate_gnss:
    params:
        world_start=config["start_date"],
        settings=config["simulate"],
    input:
        code=library_files("simulate", "io"),
    output:
        orbit="resources/simulate/gnss/{date}.sp3",
        clock="resources/simulate/gnss/{date}.clk",
    log:
        "logs/simulate_gnss/{date}.log",
    benchmark:
        "benchmarks/simulate_gnss/{date}.tsv"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    conda:
        "../../envs/leopod.yaml"
    script:
        "../../scripts/simulate_gnss.py"


rule simulate:
    params:
        world_start=config["start_date"],
        settings=config["simulate"],
    input:
        code=library_files("simulate", "io"),
    output:
        obs="resources/simulate/{sat}/{date}.rnx",
        truth_sp3="resources/simulate/{sat}/{date}_truth.sp3",
        truth_nc="resources/simulate/{sat}/{date}_truth.nc",
    log:
        "logs/simulate/{sat}/{date}.log",
    benchmark:
        "benchmarks/simulate/{sat}/{date}.tsv"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    conda:
        "../../envs/leopod.yaml"
    script:
        "../../scripts/simulate.py"
