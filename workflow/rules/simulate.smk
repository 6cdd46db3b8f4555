# simulate: the optional data source of simulated satellites (leopod.simulate.campaign). Writes
# the file formats of real archives under resources/<campaign>/simulate/ (RINEX 3 and 2, SP3,
# RINEX clock, integer-recovery clock + wide-lane biases, Bias-SINEX, CRD, SINEX) with the truth
# beside them.


# The truth orbit of one satellite over the whole campaign (a formation follower: from its
# leader's initial state and the ROE, with its burns), its code-bias map(s), its manoeuvre file.
rule simulate_truth:
    input:
        code=library_code("simulate_truth"),
    output:
        truth=resource_path("simulate/{sat}/truth_orbit.nc"),
        code_bias_map=resource_path("simulate/{sat}/code_bias_map.nc"),
        # the burns of the satellite (leopod.io.manoeuvre; header only without formation burns)
        manoeuvres=resource_path("simulate/{sat}/manoeuvres.txt"),
    log:
        log_path("simulate_truth/{sat}.log"),
    benchmark:
        benchmark_path("simulate_truth/{sat}.tsv")
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
        biases=resource_path("simulate/biases_truth.nc"),
        stations=resource_path("simulate/slr_stations.snx"),
        eccentricities=resource_path("simulate/slr_eccentricities.snx"),
    log:
        log_path("simulate_world/simulate_world.log"),
    benchmark:
        benchmark_path("simulate_world/simulate_world.tsv")
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
        orbit=resource_path("simulate/gnss/{date}.sp3"),
        clock=resource_path("simulate/gnss/{date}.clk"),
        integer_clock=resource_path("simulate/gnss/{date}_int.clk"),
        wl_bias=resource_path("simulate/gnss/{date}.wsb"),
        osb=resource_path("simulate/gnss/{date}.bia"),
        # P1-C1 DCBs of the simulated satellites, for C1C-based campaigns (products.dcb_p1c1)
        dcb_p1c1=resource_path("simulate/gnss/{date}_p1c1.dcb"),
    log:
        log_path("simulate_gnss/{date}.log"),
    benchmark:
        benchmark_path("simulate_gnss/{date}.tsv")
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
        rinex3=resource_path("simulate/{sat}/{date}.rnx"),
        # RINEX 2.11 holds the GPS observations only: no file without simulated GPS
        **({"rinex2": resource_path("simulate/{sat}/{date}.obs")}
           if "G" in CONFIG["simulate"]["systems"] else {}),
        truth_sp3=resource_path("simulate/{sat}/{date}_truth.sp3"),
        truth_nc=resource_path("simulate/{sat}/{date}_truth.nc"),
        crd=resource_path("simulate/{sat}/{date}.crd"),
    log:
        log_path("simulate/{sat}/{date}.log"),
    benchmark:
        benchmark_path("simulate/{sat}/{date}.tsv")
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
