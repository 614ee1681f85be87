"""Logging of the command line: one rich handler on stderr for the ``shockfriction`` loggers.

Library modules log with ``logging.getLogger(__name__)`` and never print; the
command line chooses the level: ``--quiet`` errors only, default warnings,
``--verbose`` information, ``-vv`` debugging.
"""

from __future__ import annotations

import logging

LEVELS = {-1: logging.ERROR, 0: logging.WARNING, 1: logging.INFO}


def verbosity(verbose: int = 0, quiet: bool = False) -> int:
    """-1 quiet, 0 default, 1 verbose, 2 debug."""
    return -1 if quiet else min(int(verbose), 2)


def configure_logging(level: int = 0) -> logging.Logger:
    """Send the package's log records to stderr through rich at ``level`` (see :func:`verbosity`)."""
    from rich.console import Console
    from rich.logging import RichHandler

    logger = logging.getLogger("shockfriction")
    for h in list(logger.handlers):
        if getattr(h, "_shockfriction_cli", False):
            logger.removeHandler(h)
    handler = RichHandler(console=Console(stderr=True), show_time=level >= 2, show_path=level >= 2,
                          markup=False, rich_tracebacks=False)
    handler._shockfriction_cli = True
    logger.addHandler(handler)
    logger.setLevel(LEVELS.get(level, logging.DEBUG))
    logger.propagate = False
    return logger
