"""``shockfriction schema run|subgrid|sweep|fit``: print the JSON schema of a deck kind."""

from __future__ import annotations

import typer

from shockfriction.cli_options import QUIET, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("schema", epilog=EXIT_CODES)
    def schema(
        kind: str = typer.Argument(..., help="deck kind: run, subgrid, sweep or fit"),
        markdown: bool = typer.Option(False, "--markdown", help="print the markdown reference instead"),
        verbose: int = VERBOSE,
        quiet: bool = QUIET,
    ) -> None:
        """Print the JSON schema of a deck (unit fields: strings with "x-dimension" and "x-si-unit")."""
        from shockfriction.deck.schema import DECKS, json_text, markdown_reference
        from shockfriction.errors import UsageError
        from shockfriction.log import configure_logging, verbosity

        configure_logging(verbosity(verbose, quiet))

        if kind not in DECKS:
            raise UsageError(f"schema {kind!r}: expected one of {', '.join(DECKS)}")
        typer.echo(markdown_reference(kind) if markdown else json_text(kind))
