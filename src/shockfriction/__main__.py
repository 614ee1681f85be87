"""``python -m shockfriction`` is the same as the ``shockfriction`` command."""

from shockfriction.cli import main

main()
