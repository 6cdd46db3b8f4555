# locate: the inputs a campaign names by path (products.*, satellites.<sat>.observations, ...)
# are linked into resources/locate/<entry>/ by this rule. A missing file then fails its own
# job, with a message naming the file and the config entry, instead of stopping the whole
# campaign before any job runs; the days that have their files go on (--keep-going).
rule locate:
    localrule: True
    params:
        source=locate_source,
    input:
        existing_locate_source,
    output:
        "resources/locate/{entry}/{path}",
    log:
        "logs/locate/{entry}/{path}.log",
    conda:
        "../../envs/leopod.yaml"
    script:
        "../../scripts/locate.py"
