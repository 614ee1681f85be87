"""Checks of command-line outputs and counts: refuse to mix a new run into an old folder.

``prepare_out_dir(path, force, restart)`` is the one place that decides what an
existing output folder may hold, for every command that writes one (``run``, ``subgrid``,
``fit``, ``sweep``) and for the Python API (``run(..., out_dir, force=...)``,
``run_subgrid``, ``fit``'s ``write_outputs``): a new or empty folder is used, a non-empty one
is refused unless ``force``.  A sweep's folder that already holds that sweep (its ``plan.json``)
is resumed into (``resume``).
"""

from __future__ import annotations

import logging
import shutil
from pathlib import Path

from shockfriction.errors import UsageError

log = logging.getLogger(__name__)

#: files that shockfriction commands write into an output folder (``--force`` removes these only)
OUTPUT_PATTERNS = (
    "probes.csv", "energy.csv", "summary.json", "fields.h5", "fields.xmf",          # run
    "interface.h5", "interface_*.png", "columns.h5", "columns_*.png", "subgrid_*.png",  # slide lines
    "history.csv", "history_*.csv", "profiles.csv", "profiles_*.csv",               # subgrid
    "interface.png", "profiles.png",
    "restart*.h5", "checkpoint*.h5",                                                  # restart files
    "interface.csv", "columns.csv",                                                   # record tables
    "fit.json", "fit.png", "computed.csv", "computed_*.csv", "evaluations.csv",       # fit
    "sweep.csv", "records.h5", "plan.json",                                           # sweep (and runs/)
)
#: folders a command writes into its output folder (``--force`` removes these too)
OUTPUT_FOLDERS = ("runs",)


def check_out_path(path: str | Path, option: str = "--out") -> Path:
    """``path`` must be a folder or not exist yet; a file there is a usage error."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(f"{option} = '{path}' is a file; expected a folder (existing or new)")
    return path


def previous_outputs(path: Path) -> list[Path]:
    """The files of ``path`` (not recursive) that match :data:`OUTPUT_PATTERNS`."""
    found = {p for pattern in OUTPUT_PATTERNS for p in path.glob(pattern) if p.is_file()}
    if (path / "plan.json").is_file():  # a sweep's journal goes with its plan
        found |= {path / d for d in OUTPUT_FOLDERS if (path / d).is_dir() and not (path / d).is_symlink()}
    return sorted(found)


def out_dir_state(path: str | Path, force: bool = False, restart: bool = False, resume: bool = False) -> str:
    """What :func:`prepare_out_dir` would do with ``path`` (for ``--dry-run``), in words."""
    path = Path(path)
    if not path.exists():
        return "new, would be created"
    entries = list(path.iterdir())
    if not entries:
        return "empty, would be used"
    if restart:
        return "kept for --restart"
    if resume and (path / "plan.json").is_file():
        return "holds a sweep, would be resumed"
    if force:
        return f"not empty: --force would delete its {len(previous_outputs(path))} previous output(s)"
    return f"not empty ({len(entries)} entries): refused without --force"


def prepare_out_dir(path: str | Path, force: bool = False, restart: bool = False, option: str = "--out",
                    resume: bool = False) -> Path:
    """Make ``path`` ready for a new run and return it.

    A missing folder is created and an empty one used as is.  A non-empty folder is
    refused (:class:`~shockfriction.errors.UsageError`, exit status 2) unless
    ``force`` (the previous shockfriction outputs, :data:`OUTPUT_PATTERNS`, are
    deleted; other files stay) or ``restart`` (the folder is kept untouched for a
    run that continues from it).
    """
    path = check_out_path(path, option)
    if force and restart:
        raise UsageError("--force and --restart exclude each other: --force clears the outputs a restart needs")
    if not path.exists():
        path.mkdir(parents=True)
        return path
    if restart:
        return path
    entries = list(path.iterdir())
    if not entries:
        return path
    if resume and not force and (path / "plan.json").is_file():
        return path
    if not force:
        raise UsageError(f"{option} = '{path}' is not empty ({len(entries)} entries); "
                         "use --force to replace its previous outputs, or choose a new folder")
    old = previous_outputs(path)
    for p in old:
        if p.is_dir():
            shutil.rmtree(p)
        else:
            p.unlink()
    kept = len(entries) - len(old)
    log.info("--force: removed %d previous output file(s) from %s%s", len(old), path,
             f", kept {kept} other entries" if kept else "")
    return path


def check_workers(workers: int | None, option: str = "--workers") -> int | None:
    """A pool size must be at least 1 (None: the default)."""
    if workers is not None and workers < 1:
        raise UsageError(f"{option} = {workers}: expected a positive number of workers")
    return workers


def check_threads(threads: int | None, option: str = "--threads") -> int | None:
    """None (the deck's value), 0 (all cores) or a positive count, as the deck's ``threads``."""
    if threads is not None and threads < 0:
        raise UsageError(f"{option} = {threads}: expected a positive number of threads, or 0 for all cores")
    return threads
