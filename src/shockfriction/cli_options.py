"""Options shared by the commands, spelled once so that they mean the same everywhere
(docs/cli.md): ``-v``/``--verbose`` (count), ``-q``/``--quiet``, ``-f``/``--force``, ``--dry-run``,
``--allow-geo``."""

from __future__ import annotations

import typer

VERBOSE = typer.Option(0, "--verbose", "-v", count=True, help="more log messages on stderr (-vv: debug)")
QUIET = typer.Option(False, "--quiet", "-q", help="no progress on stderr; log errors only")
FORCE = typer.Option(False, "--force", "-f",
                     help="reuse a non-empty output folder: delete its previous shockfriction outputs first")
DRY_RUN = typer.Option(False, "--dry-run",
                       help="load and validate everything, print what would run (stdout); run and write nothing")
ALLOW_GEO = typer.Option(False, "--allow-geo",
                         help="let a deck mesh a gmsh .geo script (a program: it can run commands and write "
                              "files); .msh files need no flag")
