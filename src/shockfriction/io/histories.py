"""Probe and energy histories as CSV files, written as the run goes (flushed at every output
and every ``flush_every`` rows), so that what was written stays readable if a run stops or is killed."""

from __future__ import annotations

import csv
import os
from pathlib import Path

from shockfriction.errors import DeckError


class CsvHistory:
    """A CSV file with a header row; ``write(row)`` appends, flushing every ``flush_every`` rows."""

    def __init__(self, path: str | Path, header: list[str], flush_every: int = 200, resume_at: int | None = None):
        self.path = Path(path)
        if resume_at is None:
            self._fh = self.path.open("w", newline="")
            self._writer = csv.writer(self._fh)
            self._writer.writerow(header)
        else:  # restart: keep the first resume_at bytes (the rows up to the checkpoint), append after them
            size = self.path.stat().st_size if self.path.is_file() else -1
            if size < resume_at:
                raise DeckError(f"--restart: {self.path} holds {max(size, 0)} bytes, fewer than the {resume_at} "
                                "written at the checkpoint (the outputs do not belong to this checkpoint)")
            os.truncate(self.path, resume_at)
            self._fh = self.path.open("a", newline="")
            self._writer = csv.writer(self._fh)
        self._fh.flush()
        self._count = 0
        self._flush_every = flush_every

    def write(self, row) -> None:
        self._writer.writerow([f"{v:.10e}" for v in row])
        self._count += 1
        if self._count % self._flush_every == 0:
            self._fh.flush()

    def flush(self) -> int:
        """Flush to the file; return its size in bytes (the write position a checkpoint keeps)."""
        self._fh.flush()
        return self._fh.tell()

    def close(self) -> None:
        if not self._fh.closed:
            self._fh.flush()
            self._fh.close()
