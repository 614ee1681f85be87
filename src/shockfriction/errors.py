"""Exceptions that the command line turns into clear messages (no traceback)."""


class ShockfrictionError(Exception):
    """Base class of the errors the package reports to a user."""


class DeckError(ShockfrictionError):
    """A deck (or a material file) is invalid: the message names field, value and expectation."""


class SimulationError(ShockfrictionError):
    """A run went bad (tangled cell, NaN, failed root finder): the message says where and when."""
