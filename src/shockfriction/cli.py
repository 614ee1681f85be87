"""The ``shockfriction`` command line (typer).

Each command lives in its own module of :mod:`shockfriction.commands` and
registers itself through ``register(app)``.  Exit status: the table
:data:`shockfriction.errors.EXIT_STATUS` (docs/cli.md); each error is one message on
stderr, never a traceback; results go to stdout, progress and logs to stderr.
"""

from __future__ import annotations

import importlib
import os
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


_DEBUG = {"on": bool(os.environ.get("SHOCKFRICTION_DEBUG"))}


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_show_version, is_eager=True,
                                 help="print the version and exit"),
    debug: bool = typer.Option(False, "--debug", help="show the traceback of an error"),
) -> None:
    """Metal-on-metal friction under shock loading (after Dambakizi 2009).

    Docs: deck reference, theory and examples in docs/ (mkdocs).
    """
    _DEBUG["on"] = _DEBUG["on"] or debug


for _mod in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
    importlib.import_module(f"{commands.__name__}.{_mod.name}").register(app)


class Terminated(SystemExit):
    """SIGTERM outside the places that handle it themselves (a run's cycle, a sweep's pool): exit 143
    through the ``finally`` blocks, so that scratch folders (gmsh meshing) are removed."""


def _terminated(signum, frame) -> None:
    raise Terminated(128 + signum)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the console script; ``argv`` is for tests."""
    import signal
    import threading

    err = Console(stderr=True)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _terminated)
    try:
        app(args=argv, prog_name="shockfriction")
    except Terminated:
        err.print("[yellow]stopped by SIGTERM[/]", highlight=False)
        sys.exit(143)
    except DeckError as exc:
        text = str(exc)
        sep = "\n" if "\n" in text else ": "  # one error: one line; several: one line each
        err.print(f"[bold red]deck error[/]{sep}{escape(text)}", highlight=False, soft_wrap=True)
        sys.exit(2)
    except UsageError as exc:
        err.print(f"[bold red]usage error[/]: {escape(str(exc))}", highlight=False, soft_wrap=True)
        sys.exit(2)
    except SimulationError as exc:
        text = str(exc)
        sep = "\n" if "\n" in text else ": "
        err.print(f"[bold red]run failed[/]{sep}{escape(text)}", highlight=False, soft_wrap=True)
        sys.exit(3)
    except KeyboardInterrupt:
        err.print("[yellow]interrupted[/]", highlight=False)
        sys.exit(130)
    except Exception as exc:  # last line of defence: the causes are fixed where they arise
        if _DEBUG["on"] or "--debug" in (argv if argv is not None else sys.argv):
            raise
        text = " ".join(str(exc).split())[:300]
        err.print(f"[bold red]run failed[/]\ninternal error {type(exc).__name__}: {escape(text)} "
                  "(please report it; --debug shows the traceback)", highlight=False, soft_wrap=True)
        sys.exit(3)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":  # pragma: no cover
    main()
