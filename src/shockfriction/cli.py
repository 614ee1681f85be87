"""The ``shockfriction`` command line (typer).

Each command lives in its own module of :mod:`shockfriction.commands` and
registers itself through ``register(app)``.  Deck errors exit with status 2,
failed runs with status 3, each with one message and no traceback.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import sys

import typer
from rich.console import Console
from rich.markup import escape

from shockfriction import commands
from shockfriction.errors import DeckError, SimulationError

app = typer.Typer(
    name="shockfriction",
    help="Metal-on-metal friction under shock loading (after Dambakizi 2009).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)



_DEBUG = {"on": bool(os.environ.get("SHOCKFRICTION_DEBUG"))}


@app.callback()
def _root(debug: bool = typer.Option(False, "--debug", help="show the traceback of an error")) -> None:
    """Metal-on-metal friction under shock loading (after Dambakizi 2009)."""
    _DEBUG["on"] = _DEBUG["on"] or debug


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
    except SimulationError as exc:
        err.print(f"[bold red]run failed[/]\n{escape(str(exc))}", highlight=False, soft_wrap=True)
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


if __name__ == "__main__":  # pragma: no cover
    main()
