"""Where a campaign's files go: one folder per campaign under ``results/``, ``resources/`` and
``logs/`` of the working directory, and a download cache shared by the campaigns.

::

    results/<campaign>/<step>/<sat>/<yyyy>-<doy>.*    products (report.html, failed_days.yaml)
    resources/<campaign>/simulate/..., locate/...     simulated and located inputs
    logs/<campaign>/<step>/...                        the jobs' logs (download logs too)
    logs/<campaign>/benchmarks/<step>/...             Snakemake benchmark files
    resources/download/<family>/...                   downloaded products, one file per
                                                      product family and day, shared

``<campaign>`` is the config key ``campaign`` (schema: a letter or digit, then letters,
digits, ``_ . -``), so two campaigns run one after the other in one directory keep all their
files. Downloads are a cache keyed by product (the catalogue family and its day): an archive's
file is the same for every campaign that names it, so it is fetched once. Campaign path
templates name the campaign's own folders with the placeholder ``{campaign}``
(``resources/{campaign}/simulate/{sat}/{date}.rnx``), filled by
:func:`leopod.workflow.campaign.campaign_inputs`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["DOWNLOAD_ROOT", "Layout"]

#: Folder of the downloaded products, shared by the campaigns of a working directory.
DOWNLOAD_ROOT = "resources/download"


@dataclass(frozen=True)
class Layout:
    """The folders of one campaign, relative to the working directory.

    Attributes
    ----------
    campaign : str
        The campaign's name (config key ``campaign``).
    """

    campaign: str

    @classmethod
    def of(cls, config: dict) -> Layout:
        """The layout of a campaign config (its key ``campaign``).

        Raises
        ------
        ValueError
            If the name could leave its folder (empty, ``.``/``..``, a path separator).
        """
        name = str(config.get("campaign") or "")
        if not name or name in (".", "..") or "/" in name or "\\" in name:
            raise ValueError(f"campaign: {name!r} is no folder name (letters, digits, _ . -)")
        return cls(name)

    @property
    def results(self) -> str:
        """``results/<campaign>``: the products."""
        return f"results/{self.campaign}"

    @property
    def resources(self) -> str:
        """``resources/<campaign>``: simulated and located inputs."""
        return f"resources/{self.campaign}"

    @property
    def logs(self) -> str:
        """``logs/<campaign>``: the jobs' logs."""
        return f"logs/{self.campaign}"

    @property
    def benchmarks(self) -> str:
        """``logs/<campaign>/benchmarks``: Snakemake's benchmark files of the jobs."""
        return f"{self.logs}/benchmarks"

    @property
    def report(self) -> str:
        """``results/<campaign>/report.html``: the Snakemake report."""
        return f"{self.results}/report.html"

    @property
    def failed_days(self) -> str:
        """``results/<campaign>/failed_days.yaml``: the days ``leopod run --exclude-failed``
        left out (a campaign overlay)."""
        return f"{self.results}/failed_days.yaml"

