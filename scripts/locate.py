"""Rule locate: link an input named by path in the config into resources/<campaign>/locate/."""

from leopod.workflow.worker import hand_off

hand_off(globals())  # run in the warm worker process of this run, if it has one

import logging
import os
from pathlib import Path

from leopod.workflow.log import configure_logging

log = logging.getLogger(__name__)


def main(source, entry: str, dest) -> None:
    """Link ``dest`` to the file ``source`` of the config entry ``entry`` (atomically).

    Raises
    ------
    FileNotFoundError
        Naming the file, the config entry and the working directory.
    """
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


def run(sm) -> None:
    """Call :func:`main` with the job's files."""
    configure_logging(sm)
    main(sm.params.source, sm.wildcards.entry, sm.output[0])


if __name__ == "__main__":
    # the default campaign locates nothing: call main() by hand, or run through Snakemake
    run(snakemake)  # noqa: F821 (injected by Snakemake)
