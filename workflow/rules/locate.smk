# locate: the inputs a campaign names by path (products.*, satellites.<sat>.observations, ...)
# are linked into resources/<campaign>/locate/<entry>/ by this rule. A missing file then fails
# its own job, with a message naming the file and the config entry, instead of stopping the whole
# campaign before any job runs; the days that have their files go on (--keep-going).
rule locate:
    input:
        existing_locate_source,
    output:
        resource_path("locate/{entry}/{path}"),
    log:
        log_path("locate/{entry}/{path}.log"),
    localrule: True
    conda:
        "../../envs/leopod.yaml"
    params:
        source=locate_source,
    script:
        "../../scripts/locate.py"
