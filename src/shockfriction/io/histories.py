"""Probe and energy histories as CSV files, written as the run goes (flushed often),
so that what was written stays readable if a run stops with an error."""

from __future__ import annotations

import csv
from pathlib import Path


class CsvHistory:
    """A CSV file with a header row; ``write(row)`` appends, flushing every ``flush_every`` rows."""

    def __init__(self, path: str | Path, header: list[str], flush_every: int = 200):
        self.path = Path(path)
        self._fh = self.path.open("w", newline="")
        self._writer = csv.writer(self._fh)
        self._writer.writerow(header)
        self._fh.flush()
        self._count = 0
        self._flush_every = flush_every

    def write(self, row) -> None:
        self._writer.writerow([f"{v:.10e}" for v in row])
        self._count += 1
        if self._count % self._flush_every == 0:
            self._fh.flush()

    def close(self) -> None:
        if not self._fh.closed:
            self._fh.flush()
            self._fh.close()
