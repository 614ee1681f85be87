"""Exceptions that the command line turns into clear messages (no traceback)."""

#: exit status -> meaning: the one table of the exit codes (``--help`` epilogs and docs/cli.md show it,
#: tests/test_cli_conventions.py checks both against it)
EXIT_STATUS = {
    0: "done",
    1: "finished with failures (sweep runs left pending, fit not converged)",
    2: "deck or usage error (the message names field, value and expectation; nothing was run)",
    3: "run failure (a run went non-finite or failed, a sweep with failed runs; the message says where and when)",
    130: "interrupted (Ctrl-C)",
    143: "stopped by SIGTERM (run: outputs finished and a checkpoint written, continue with --restart)",
}

EXIT_CODES = "Exit status: " + "; ".join(f"{code} {text}" for code, text in EXIT_STATUS.items()) + "."


class ShockfrictionError(Exception):
    """Base class of the errors the package reports to a user."""


class DeckError(ShockfrictionError):
    """A deck (or a material file) is invalid: the message names field, value and expectation."""


class SimulationError(ShockfrictionError):
    """A run went bad (tangled cell, NaN, failed root finder): the message says where and when."""


class UsageError(ShockfrictionError):
    """A command-line option is wrong (``--out`` naming a file, ``--threads -5``): exit status 2."""
