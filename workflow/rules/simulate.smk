# simulate: the optional data source of simulated satellites (leopod.simulate.campaign). Writes
# the file formats of real archives under resources/simulate/ (RINEX 3 and 2, SP3, RINEX clock,
# integer-recovery clock + wide-lane biases, Bias-SINEX, CRD, SINEX) with the truth beside them.


# The truth orbit of one satellite over the whole campaign (a formation follower: from its
# leader's initial state and the ROE, with its burns), its code-bias map(s), its manoeuvre file.
rule simulate_truth:
    input:
        code=library_code("simulate_truth"),
    output:
        truth="resources/simulate/{sat}/truth_orbit.nc",
        code_bias_map="resources/simulate/{sat}/code_bias_map.nc",
        # the burns of the satellite (leopod.io.manoeuvre; header only without formation burns)
        manoeuvres="resources/simulate/{sat}/manoeuvres.txt",
    log:
        "logs/simulate_truth/{sat}.log",
    benchmark:
        "logs/benchmarks/simulate_truth/{sat}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=20,
    params:
        settings=sat_simulation,
        formation=sat_formation,
        world_start=CONFIG["start_date"],
        world_end=CONFIG["end_date"],
    script:
        "../../scripts/simulate_truth.py"


# The campaign's true code/phase biases (GNSS satellites, every simulated receiver) and the
# SLR station coordinates.
rule simulate_world:
    input:
        gnss_products=simulation_product_files,
        code=library_code("simulate_world"),
    output:
        biases="resources/simulate/biases_truth.nc",
        stations="resources/simulate/slr_stations.snx",
        eccentricities="resources/simulate/slr_eccentricities.snx",
    log:
        "logs/simulate_world/simulate_world.log",
    benchmark:
        "logs/benchmarks/simulate_world/simulate_world.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        settings=CONFIG["simulate"],
        world_start=CONFIG["start_date"],
        world_end=CONFIG["end_date"],
        # the satellites whose files the simulate rules write
        sats=SIMULATED_SATS,
    script:
        "../../scripts/simulate_world.py"


# GNSS orbits, clocks and ambiguity-resolution products of one day.
rule simulate_gnss:
    input:
        biases=rules.simulate_world.output.biases,
        code=library_code("simulate_gnss"),
    output:
        orbit="resources/simulate/gnss/{date}.sp3",
        clock="resources/simulate/gnss/{date}.clk",
        integer_clock="resources/simulate/gnss/{date}_int.clk",
        wl_bias="resources/simulate/gnss/{date}.wsb",
        osb="resources/simulate/gnss/{date}.bia",
        # P1-C1 DCBs of the simulated satellites, for C1C-based campaigns (products.dcb_p1c1)
        dcb_p1c1="resources/simulate/gnss/{date}_p1c1.dcb",
    log:
        "logs/simulate_gnss/{date}.log",
    benchmark:
        "logs/benchmarks/simulate_gnss/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        settings=CONFIG["simulate"],
        world_start=CONFIG["start_date"],
        world_end=CONFIG["end_date"],
    script:
        "../../scripts/simulate_gnss.py"


# Onboard observations, the day's truth and the SLR normal points of one satellite-day.
rule simulate:
    input:
        unpack(attitude_inputs),
        unpack(sim_antenna_inputs),
        truth=rules.simulate_truth.output.truth,
        biases=rules.simulate_world.output.biases,
        gnss_products=simulation_product_files,
        code=library_code("simulate"),
    output:
        rinex3="resources/simulate/{sat}/{date}.rnx",
        # RINEX 2.11 holds the GPS observations only: no file without simulated GPS
        **({"rinex2": "resources/simulate/{sat}/{date}.obs"}
           if "G" in CONFIG["simulate"]["systems"] else {}),
        truth_sp3="resources/simulate/{sat}/{date}_truth.sp3",
        truth_nc="resources/simulate/{sat}/{date}_truth.nc",
        crd="resources/simulate/{sat}/{date}.crd",
    log:
        "logs/simulate/{sat}/{date}.log",
    benchmark:
        "logs/benchmarks/simulate/{sat}/{date}.tsv"
    conda:
        "../../envs/leopod.yaml"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    params:
        settings=CONFIG["simulate"],
        world_start=CONFIG["start_date"],
        world_end=CONFIG["end_date"],
        pco_body_m=sim_pco,
        leo_antenna=sim_antenna,
        attitude=sat_attitude,
    script:
        "../../scripts/simulate.py"
