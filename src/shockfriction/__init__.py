"""shockfriction: friction under shock loading (after Dambakizi 2009).

SI units everywhere inside the package; decks carry unit strings that are
converted once, at the edge, by :mod:`shockfriction.units`.
"""

__version__ = "0.3.0"  #: the one source of the version (pyproject reads it)
