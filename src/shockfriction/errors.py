"""Exceptions that the command line turns into clear messages (no traceback)."""

EXIT_CODES = ("Exit status: 0 done; 1 finished with failures (sweep runs failed or pending, fit not converged); "
              "2 deck or usage error (the message names field, value and expectation); "
              "3 run failure (the message says where and when); 130 interrupted (Ctrl-C).")


class ShockfrictionError(Exception):
    """Base class of the errors the package reports to a user."""


class DeckError(ShockfrictionError):
    """A deck (or a material file) is invalid: the message names field, value and expectation."""


class SimulationError(ShockfrictionError):
    """A run went bad (tangled cell, NaN, failed root finder): the message says where and when."""


class UsageError(ShockfrictionError):
    """A command-line option is wrong (``--out`` naming a file, ``--threads -5``): exit status 2."""
