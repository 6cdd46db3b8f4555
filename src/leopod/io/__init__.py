"""Readers (and writers) of the file formats of GNSS precise orbit determination.

One module per format; each reader returns an :class:`xarray.Dataset` in SI units with a
schema documented in its docstring, and raises :class:`leopod.io.FormatError` (a
``ValueError``) naming file, line and field on bad input.
"""

from leopod.io._text import FormatError, read_lines, write_text

__all__ = ["FormatError", "read_lines", "write_text"]
