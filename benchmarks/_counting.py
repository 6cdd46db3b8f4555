"""Counting helper shared by the POD benchmarks: orbit integrations and force evaluations.

Every integration logs one DEBUG record on ``leopod.dynamics.integrator`` with its number of
force evaluations (:func:`leopod.dynamics.integrator.integrate`); :class:`IntegrationCounter`
listens to them, so the library needs no global counters.
"""

from __future__ import annotations

import logging

_LOGGER = "leopod.dynamics.integrator"


class IntegrationCounter(logging.Handler):
    """While active (``with IntegrationCounter() as c``): ``c.integrations``,
    ``c.evaluations`` and ``c.compiled`` (integrations through the compiled force model)."""

    def __init__(self):
        super().__init__(level=logging.DEBUG)
        self.integrations = self.evaluations = self.compiled = 0

    def emit(self, record: logging.LogRecord) -> None:
        if record.msg.startswith("integrated"):
            self.integrations += 1
            self.evaluations += int(record.args[2])
            self.compiled += record.args[3] == "compiled"

    def __enter__(self) -> IntegrationCounter:
        logger = logging.getLogger(_LOGGER)
        self._saved = logger.level, logger.propagate
        logger.setLevel(logging.DEBUG)
        logger.propagate = False          # its DEBUG records are counted, not printed
        logger.addHandler(self)
        return self

    def __exit__(self, *exc) -> None:
        logger = logging.getLogger(_LOGGER)
        logger.removeHandler(self)
        logger.level, logger.propagate = self._saved

    def __str__(self) -> str:
        return (f"{self.integrations} integrations ({self.compiled} compiled), "
                f"{self.evaluations} force evaluations")
