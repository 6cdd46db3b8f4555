# leopod: precise orbit determination of LEO satellites from onboard GNSS.
#   snakemake --cores 2                                   # default campaign (config/config.yaml)
#   snakemake --cores 2 --configfile config/<campaign>.yaml
# Results: results/<campaign>/<step>/<sat>/<YYYY-DDD>.*, logs/<campaign>/<step>/...,
# logs/<campaign>/benchmarks/<step>/..., inputs under resources/<campaign>/
# (leopod.workflow.layout; downloads shared: resources/download/).
from snakemake.utils import min_version

min_version("8.20")


# Jobs import leopod from this checkout (PYTHONPATH; envs/leopod.yaml for --use-conda).
from leopod.workflow.boundary import source_on_python_path

source_on_python_path(workflow.basedir)


# --configfile replaces the default campaign instead of being merged into it
if not config:

    configfile: f"{workflow.basedir}/config/config.yaml"


report: "workflow/report/workflow.rst"


# A local run's script jobs run as forks of one warm process that imported numpy, xarray,
# matplotlib, numba and leopod once (leopod.workflow.worker; LEOPOD_WORKER=off runs each job
# in a process of its own, as cluster executors always do).
from leopod.workflow import worker

WORKER = []


onstart:
    if workflow.local_exec:
        WORKER.append(worker.start(log_path("worker.log")))


onsuccess:
    worker.stop(WORKER.pop() if WORKER else None)


onerror:
    worker.stop(WORKER.pop() if WORKER else None)


include: "workflow/rules/common.smk"
include: "workflow/rules/download.smk"
include: "workflow/rules/locate.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/ingest.smk"
include: "workflow/rules/quality.smk"
include: "workflow/rules/code_bias.smk"
include: "workflow/rules/pod.smk"
include: "workflow/rules/pcv.smk"
include: "workflow/rules/kinematic.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/baseline.smk"
include: "workflow/rules/formation.smk"


rule all:
    default_target: True
    input:
        all_targets(),
