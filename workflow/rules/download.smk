# download_<family>: one rule per product family the campaign names as "download:<family>"
# (leopod.download; catalogue config/catalogue.yaml). Each fetches, decompresses and checks
# one file into resources/download/<family>/ (a cache shared by the campaigns), trying local
# mirrors, then the archives in order.
# The download settings are read from the config by the script, not passed as params, so
# that editing mirrors or the catalogue does not fetch finished files again; an identical
# file fetched again does not rerun anything either (profiles: max-checksum-file-size).
for family in DOWNLOADS:

    rule:
        name:
            f"download_{family}"
        output:
            destination_template(CATALOGUE.family(family)),
        log:
            download_log(family),
        localrule: True
        conda:
            "../../envs/leopod.yaml"
        resources:
            downloads=1,
        params:
            family=family,
            default_catalogue=DEFAULT_CATALOGUE,
        script:
            "../../scripts/download.py"
