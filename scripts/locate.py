"""Snakemake script of rule locate: link an input named by path in the config into resources/."""

import os
from pathlib import Path

from leopod.workflow.log import configure_logging


def main(source, entry, dest, log):
    source = Path(source)
    if not source.is_file():
        raise FileNotFoundError(f"input file {source} does not exist (config entry {entry}, "
                                f"working directory {Path.cwd()})")
    dest = Path(dest)
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_name(f".{dest.name}.link")
    tmp.unlink(missing_ok=True)
    tmp.symlink_to(source.resolve())
    os.replace(tmp, dest)
    log.info("%s: %s -> %s (%d bytes)", entry, dest, source.resolve(), source.stat().st_size)


if __name__ == "__main__":
    log = configure_logging(snakemake)  # noqa: F821 (injected by Snakemake)
    sm = snakemake  # noqa: F821
    main(sm.params.source, sm.wildcards.entry, sm.output[0], log)
