"""End-of-run products of an output folder: the slide-line maps, the column profiles and the CSV tables, each
drawn from the finished record files ``interface.h5`` and ``columns.h5`` alone.

They are independent of each other and of the run's state, so a run that was given n > 1 threads makes them in up
to n worker processes at once, each taking a share of them (the longest first, each to the least loaded worker by
the costs of :data:`PRODUCTS`): fresh interpreters running ``python -m shockfriction.io.products OUT PRODUCT ...``
(no fork of a process whose OpenMP threads run, no re-import of the user's script; the imports, ~1 s, paid once per
worker).  A run on one thread (a sweep's runs, whose pool already fills the cores) makes them one after another in
its own process.  A product that a worker did not report done (an interpreter that cannot import the package, a
killed process) is made again in this process, with a warning: it is lost only where it also fails here, with its
own error.  Measured in docs/theory/threads.md, "Writers off the critical path".
"""

from __future__ import annotations

import logging
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

log = logging.getLogger(__name__)

#: the products and their costs on the cone shot (s, 8 us, one process; the shares' weights), the longest first
PRODUCTS = {"interface_maps": 3.2, "interface_table": 1.7, "subgrid_maps": 1.1, "column_profiles": 0.7,
            "columns_table": 0.3}


def pending(out_dir: str | Path) -> list[str]:
    """The products that the record files in ``out_dir`` call for (maps and table of ``interface.h5``; with
    ``columns.h5``, the sub-grid maps, column profiles and columns table), in the order of :data:`PRODUCTS`."""
    out_dir = Path(out_dir)
    found = []
    if (out_dir / "interface.h5").is_file():
        found += ["interface_maps", "interface_table"]
        if (out_dir / "columns.h5").is_file():
            found += ["subgrid_maps", "column_profiles", "columns_table"]
    return [p for p in PRODUCTS if p in found]


def make(out_dir: str | Path, product: str) -> list[Path]:
    """Make one product in ``out_dir``; return the paths written."""
    out_dir = Path(out_dir)
    if product == "interface_maps":
        from shockfriction.io.interface import read_interface
        from shockfriction.plot.interface import plot_interface

        return plot_interface(read_interface(out_dir / "interface.h5"), out_dir)
    if product == "subgrid_maps":
        from shockfriction.plot.coupled import plot_subgrid_interface

        return plot_subgrid_interface(out_dir / "interface.h5", out_dir)
    if product == "column_profiles":
        from shockfriction.plot.coupled import plot_columns

        return plot_columns(out_dir / "columns.h5", out_dir)
    if product in ("interface_table", "columns_table"):
        from shockfriction.io.tables import write_record_tables

        return write_record_tables(out_dir, only=product.split("_")[0])
    raise ValueError(f"unknown product {product!r}; expected one of {', '.join(PRODUCTS)}")


def shares(products: list[str], workers: int) -> list[list[str]]:
    """``products`` split among at most ``workers`` workers: each, the longest first, to the worker with the least
    cost so far (:data:`PRODUCTS`' costs; ties to the first worker).  No empty share."""
    load = [0.0] * max(1, min(workers, len(products)))
    out: list[list[str]] = [[] for _ in load]
    for p in sorted(products, key=lambda p: -PRODUCTS[p]):
        k = load.index(min(load))
        out[k].append(p)
        load[k] += PRODUCTS[p]
    return [share for share in out if share]


def worker_command(out_dir: Path, share: list[str]) -> list[str]:
    """The command line of a worker that makes the products ``share`` in ``out_dir``."""
    return [sys.executable, "-m", "shockfriction.io.products", str(out_dir), *share]


def _in_worker(out_dir: Path, share: list[str]) -> tuple[dict[str, list[Path]], str | None]:
    """Run one worker: ({product: paths} of those it reported done, None if it exited cleanly else its last
    words)."""
    try:
        proc = subprocess.run(worker_command(out_dir, share), capture_output=True, text=True)
    except OSError as exc:
        return {}, str(exc)
    done: dict[str, list[Path]] = {}
    for line in proc.stdout.splitlines():
        product, _, path = line.partition("\t")
        if product in share:
            done.setdefault(product, []).extend([Path(path)] if path else [])
    if proc.returncode != 0:
        return done, (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
    return done, None


def make_products(out_dir: str | Path, workers: int = 1) -> list[Path]:
    """Make every pending product of ``out_dir``: in this process one after another (``workers`` <= 1), or in up
    to ``workers`` worker processes at once (:func:`shares`), making here any that a worker did not report done.
    Returns the paths written, in the order of :data:`PRODUCTS`."""
    out_dir = Path(out_dir)
    todo = pending(out_dir)
    done: dict[str, list[Path]] = {}
    if workers > 1 and len(todo) > 1:
        parts = shares(todo, workers)
        with ThreadPoolExecutor(len(parts)) as pool:  # the threads only wait on their worker processes
            results = list(pool.map(lambda share: _in_worker(out_dir, share), parts))
        for share, (made, err) in zip(parts, results):
            done.update(made)
            lost = [p for p in share if p not in made]
            if lost:
                log.warning("end-of-run products %s: their worker process failed (%s); making them here",
                            ", ".join(lost), err or "no report")
    for p in todo:
        if p not in done:
            done[p] = make(out_dir, p)
    return [path for p in todo for path in done[p]]


def main(argv: list[str]) -> int:
    """``python -m shockfriction.io.products OUT PRODUCT ...``: make the products one after another (a worker of
    :func:`make_products`), reporting each on stdout when done (``product<TAB>path`` per file, ``product<TAB>``
    when it wrote none)."""
    if len(argv) < 2 or any(p not in PRODUCTS for p in argv[1:]):
        sys.stderr.write(f"usage: python -m shockfriction.io.products OUT_DIR PRODUCT ... "
                         f"(of {', '.join(PRODUCTS)})\n")
        return 2
    for product in argv[1:]:
        paths = make(Path(argv[0]), product)
        sys.stdout.write("".join(f"{product}\t{path}\n" for path in paths) or f"{product}\t\n")
        sys.stdout.flush()  # reported as soon as made: a later failure loses only the rest of the share
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
