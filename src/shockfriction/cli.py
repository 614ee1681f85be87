"""The ``shockfriction`` command line (typer).

Each command lives in its own module of :mod:`shockfriction.commands` and
registers itself through ``register(app)``.  Exit status (docs/cli.md): 0 done,
1 finished with failures (a sweep with failed runs, a fit that did not converge),
2 deck or usage error, 3 run failure, 130 interrupted; each error is one message,
never a traceback.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys

import typer
from rich.console import Console
from rich.markup import escape

from shockfriction import __version__, commands
from shockfriction.errors import EXIT_CODES, DeckError, SimulationError, UsageError

app = typer.Typer(
    name="shockfriction",
    help="Metal-on-metal friction under shock loading (after Dambakizi 2009).",
    epilog=EXIT_CODES,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _show_version(value: bool) -> None:
    if value:
        typer.echo(f"shockfriction {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_show_version, is_eager=True,
                                 help="print the version and exit"),
) -> None:
    """Metal-on-metal friction under shock loading (after Dambakizi 2009).

    Docs: deck reference, theory and examples in docs/ (mkdocs).
    """


for _mod in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
    importlib.import_module(f"{commands.__name__}.{_mod.name}").register(app)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the console script; ``argv`` is for tests."""
    err = Console(stderr=True)
    try:
        app(args=argv, prog_name="shockfriction")
    except DeckError as exc:
        err.print(f"[bold red]deck error[/]\n{escape(str(exc))}", highlight=False, soft_wrap=True)
        sys.exit(2)
    except UsageError as exc:
        err.print(f"[bold red]usage error[/]: {escape(str(exc))}", highlight=False, soft_wrap=True)
        sys.exit(2)
    except SimulationError as exc:
        err.print(f"[bold red]run failed[/]\n{escape(str(exc))}", highlight=False, soft_wrap=True)
        sys.exit(3)
    except KeyboardInterrupt:
        err.print("[yellow]interrupted[/]", highlight=False)
        sys.exit(130)


if __name__ == "__main__":  # pragma: no cover
    main()
