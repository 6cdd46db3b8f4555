"""Robust fetching of the inputs of a campaign: products, tables and models from public archives.

- :mod:`~leopod.download.catalogue`: archives and product families (``config/catalogue.yaml``);
- :mod:`~leopod.download.fetch`: HTTP(S)/FTP/local transfers with retries, resume and netrc;
- :mod:`~leopod.download.decompress`: gzip, ``.Z`` and Hatanaka layers, by file name;
- :mod:`~leopod.download.checksums`: digests and archive checksum lists;
- :mod:`~leopod.download.checks`: is what arrived usable (parses, covers the day, no NaN);
- :mod:`~leopod.download.product`: :func:`fetch_product`, the orchestration with fallbacks.

Typical use (one ``download_*`` rule per family)::

    from leopod.download import Catalogue, fetch_product
    cat = Catalogue.from_yaml("config/catalogue.yaml")
    report = fetch_product(cat, "cod_orbit", "2023-189", "resources/cod_orbit/2023-189.sp3")
"""

from leopod.download.catalogue import Archive, Catalogue, Family, Location, Source
from leopod.download.checks import KINDS, CheckError, check_file
from leopod.download.checksums import ChecksumError
from leopod.download.decompress import DecompressError, decompress_file, decompressed_name
from leopod.download.fetch import FetchError, Transfer, download, netrc_credentials
from leopod.download.product import DownloadError, FetchReport, fetch_product

__all__ = [
    "KINDS",
    "Archive",
    "Catalogue",
    "CheckError",
    "ChecksumError",
    "DecompressError",
    "DownloadError",
    "Family",
    "FetchError",
    "FetchReport",
    "Location",
    "Source",
    "Transfer",
    "check_file",
    "decompress_file",
    "decompressed_name",
    "download",
    "fetch_product",
    "netrc_credentials",
]
