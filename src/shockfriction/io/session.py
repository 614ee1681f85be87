"""The outputs of one run, kept complete at every output time (kill-safe) and checkpoints.

:class:`RunOutputs` owns the writers of a run's output folder: ``energy.csv`` and
``probes.csv`` (a row per history sample), ``fields.h5`` + ``fields.xmf``, ``interface.h5``
and ``columns.h5`` (:class:`~shockfriction.io.records.RecordWriter`), ``summary.json`` and
``checkpoint.h5``.  The cycle calls it (never the reverse): history rows through
``Simulation.observers``, and between two cycles through ``Simulation.between_cycles``, where
an *output* happens when a field output was written, a checkpoint is due, slide lines closed
record windows (at most one such output per second of wall time), or 10 s of wall time
passed.  At an output the CSV files are flushed, the new records appended to the HDF5 files
(flushed) and ``summary.json`` replaced atomically with ``completed: false``; at the end of the
run ``completed`` becomes true.

With ``signals=True`` (the ``run`` command; not for library calls, sweeps or fits, where
SIGINT stays a KeyboardInterrupt and the outputs are finished as on failure), SIGTERM and
SIGINT (Ctrl-C) set a flag that stops the run at the end of the current cycle: a
checkpoint is written, then the outputs are finished as at the end of a run, with
``completed: false`` and ``interrupted: "SIGTERM"`` (or ``"SIGINT"``); the command exits with
128 + the signal number (143, 130).  A second signal interrupts at once (no checkpoint).
"""

from __future__ import annotations

import math
import signal
import threading
import time
import warnings
from pathlib import Path

from shockfriction.errors import DeckError
from shockfriction.io.atomic import atomic_write_json
from shockfriction.io.checkpoint import load_checkpoint, save_checkpoint

WALL_FLUSH_S = 10.0  # an output at least this often (wall time), for the CSV files and summary.json
RECORD_FLUSH_S = 1.0  # new slide-line records make an output at most this often (wall time)


class RunInterrupted(Exception):
    """A run stopped by a signal at a cycle boundary; ``exit_code`` = 128 + the signal number."""

    def __init__(self, signame: str, t: float, cycle: int):
        self.signame, self.t, self.cycle = signame, t, cycle
        self.exit_code = 128 + int(getattr(signal, signame))
        super().__init__(f"{signame} received: stopped at cycle {cycle}, t = {t:.6e} s")


class RunOutputs:
    """Writers of the output folder ``out`` of ``sim``; ``restart``: continue from its checkpoint."""

    def __init__(self, sim, out: str | Path, restart: bool = False, summarize=None, headers=None,
                 signals: bool = False):
        from shockfriction.contact.build import interface_lines
        from shockfriction.io.fields import FieldWriter
        from shockfriction.io.histories import CsvHistory
        from shockfriction.io.records import RecordWriter

        self.sim = sim
        self.out = Path(out)
        self.out.mkdir(parents=True, exist_ok=True)
        self._summarize = summarize
        self.started = time.perf_counter()
        deck = sim.problem.deck
        self.interval = deck.output.checkpoint_interval
        self.restart_info = load_checkpoint(self.out, sim) if restart else None
        info = self.restart_info or {}
        if restart and info["threads"] != sim.threads:
            warnings.warn(f"restart with {sim.threads} threads from a checkpoint taken with {info['threads']}: "
                          "the continuation is bit for bit only with the same thread count", stacklevel=2)
        energy_header, probe_header = headers
        keep = tuple(info["fields"]) if info.get("fields") else None
        try:
            self.fields = FieldWriter.from_output(self.out, sim, keep=keep)
        except (OSError, KeyError) as exc:  # restart: fields.h5 missing, damaged or from another run
            if keep is None:
                raise
            raise DeckError(f"--restart: {self.out / 'fields.h5'} does not hold the field outputs the checkpoint "
                            f"counts ({exc}); this run cannot be continued: rerun it from the start") from None
        self.energy_csv = CsvHistory(self.out / "energy.csv", energy_header, resume_at=info.get("energy_csv"))
        self.probes_csv = CsvHistory(self.out / "probes.csv", probe_header, resume_at=info.get("probes_csv"))
        lines = interface_lines(sim)
        self.records = RecordWriter(self.out, lines, sim.state.geometry_factor) if lines else None
        self._lines = lines
        self._n_records = self._count_records()
        self._n_fields = self.fields.position[0] if self.fields is not None else 0
        if self.interval is not None:
            self.next_checkpoint = info.get("next_checkpoint") or self.interval
            while self.next_checkpoint <= sim.state.t * (1 + 1e-12):
                self.next_checkpoint += self.interval
        else:
            self.next_checkpoint = math.inf
        self.last_checkpoint = info.get("time_s")
        self.interrupted: str | None = None
        self._wall0 = sim.wall_time  # wall time before this segment (restart)
        self._stop: str | None = None
        self._last_flush = time.perf_counter()
        sim.out_dir = self.out
        sim.observers.append(self._row)
        if self.fields is not None:
            sim.observers.append(self.fields.maybe_write)
        sim.between_cycles.append(self.between_cycles)
        self._old_handlers = {}
        if signals and threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGTERM, signal.SIGINT):
                self._old_handlers[sig] = signal.signal(sig, self._on_signal)
        self.write_summary(completed=False)

    # ------------------------------------------------------------------ hooks the cycle calls
    def _row(self, sim) -> None:
        self.energy_csv.write(sim.energy_rows[-1])
        if sim.probe_rows:
            self.probes_csv.write(sim.probe_rows[-1])

    def _on_signal(self, signum, frame) -> None:
        if self._stop is not None:  # second signal: stop now
            raise KeyboardInterrupt
        self._stop = signal.Signals(signum).name

    def _count_records(self) -> int:
        n = sum(len(ln.record.t) for ln in self._lines)
        return n + sum(len(ln.friction_model.profile_t) for ln in self._lines if ln.friction_model is not None)

    def between_cycles(self, sim) -> None:
        """Outputs and checkpoints between two cycles; stop here after a signal."""
        if self._stop is not None:
            raise RunInterrupted(self._stop, sim.state.t, sim.state.cycle)
        if sim.state.t >= self.next_checkpoint * (1 - 1e-12):
            while self.next_checkpoint <= sim.state.t * (1 + 1e-12):
                self.next_checkpoint += self.interval
            self.checkpoint()
            return
        n_rec = self._count_records()
        n_fields = self.fields.position[0] if self.fields is not None else 0
        wall = time.perf_counter() - self._last_flush
        if n_fields != self._n_fields or (n_rec != self._n_records and wall > RECORD_FLUSH_S) or wall > WALL_FLUSH_S:
            self.flush()

    # ------------------------------------------------------------------ outputs
    def flush(self, completed: bool = False) -> dict:
        """Flush the CSV files, append the new records, replace summary.json; return the write positions."""
        pos = {"energy_csv": self.energy_csv.flush(), "probes_csv": self.probes_csv.flush(),
               "fields": list(self.fields.position) if self.fields is not None else None}
        if self.records is not None:
            self.records.append()
        self._n_records = self._count_records()
        self._n_fields = pos["fields"][0] if pos["fields"] else 0
        # the summary, then the field index: a kill between the two atomic writes leaves the index one
        # flush behind the summary (its grids all in fields.h5), never ahead of it
        self.write_summary(completed)
        if self.fields is not None:
            self.fields.write_index()
        self._last_flush = time.perf_counter()
        return pos

    def checkpoint(self) -> Path:
        """An output, then ``checkpoint.h5`` with the positions of that output."""
        pos = self.flush()
        pos["next_checkpoint"] = self.next_checkpoint if math.isfinite(self.next_checkpoint) else None
        wall = self.sim.wall_time  # the cycle adds this segment's time at its end: count it in the checkpoint
        self.sim.wall_time = self._wall0 + time.perf_counter() - self.started
        try:
            path = save_checkpoint(self.out, self.sim, pos)
        finally:
            self.sim.wall_time = wall
        self.last_checkpoint = self.sim.state.t
        self.write_summary(False)
        return path

    def write_summary(self, completed: bool) -> dict:
        summary = self._summarize(self.sim) if self._summarize is not None else {}
        summary["completed"] = bool(completed)
        summary["interrupted"] = self.interrupted
        summary["total_wall_time_s"] = time.perf_counter() - self.started
        summary["checkpoint_time_s"] = self.last_checkpoint
        if self.restart_info is not None:
            summary["restarted_from_s"] = self.restart_info["time_s"]
        atomic_write_json(self.out / "summary.json", summary)
        return summary

    def finish(self, exc: BaseException | None) -> None:
        """End of the run (also on failure or interruption): finish every file; restore the signal handlers.

        An interruption writes a checkpoint first (before the slide lines close their last,
        partial record windows, which a restart does not see)."""
        from shockfriction.contact.build import write_interface_outputs

        for sig, old in self._old_handlers.items():
            signal.signal(sig, old)
        self._old_handlers = {}
        if isinstance(exc, RunInterrupted):
            self.interrupted = exc.signame
            self.checkpoint()
        elif isinstance(exc, KeyboardInterrupt):
            self.interrupted = "SIGINT"
        self.energy_csv.close()
        self.probes_csv.close()
        if self.fields is not None:
            self.fields.close(self.sim)
        write_interface_outputs(self.sim, self.out, self.records)  # interface.h5, columns.h5, maps, CSV tables
        sim = self.sim
        done = exc is None and sim.state.t >= sim.t_end * (1 - 1e-12)
        self.write_summary(completed=done)
