"""Atomic file replacement: write a temporary file next to the target, then ``os.replace``.

A reader (or a run killed at any instant) sees either the previous complete file or the new
complete file, never a truncated one (POSIX rename is atomic within a file system).
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


def output_mode() -> int:
    """The mode ``open(path, "w")`` gives a new file: 0666 less the process's umask (0644 usually)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write_text(path: str | Path, text: str, sync: bool = False) -> Path:
    """Replace ``path`` by a file holding ``text`` (a temporary file next to it + ``os.replace``).

    Safe against the process being killed; ``sync`` also forces the data to disk first (fsync),
    against a crash of the machine (a few ms more)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, output_mode())  # mkstemp makes 0600; outputs are 0644 (less the umask) like open()
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
            if sync:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def atomic_write_json(path: str | Path, data) -> Path:
    """``data`` as indented JSON, atomically (see :func:`atomic_write_text`)."""
    return atomic_write_text(path, json.dumps(data, indent=2) + "\n")
