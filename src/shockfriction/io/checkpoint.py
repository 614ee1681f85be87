"""Checkpoints: the complete state of a run in one HDF5 file, for a bit-for-bit restart.

A checkpoint is taken between two cycles (state at t^n, nothing half-updated).  It holds,
walking the run's objects:

* the :class:`~shockfriction.hydro.cycle.Simulation`: node and cell arrays of the
  :class:`~shockfriction.hydro.state.State` (positions, velocities v^{n-1/2}, stresses, plastic
  strain, energies, ...), time, cycle, the coming step dt^{n+1/2} and the last one, the
  energy budget, the cycle's work arrays (previous velocity jumps of the energy audit), the
  history rows (energy and probes) and the wall time so far;
* every registered interface: a slide line's pairing arrays, running sums, record window
  and records; its sub-grid friction (window sums, energy totals, records, profiles) and
  columns (temperature and plastic-strain fields, the lagged plastic heat, the plastic-front
  bounds, the cumulative per-node energies, the last friction and slip, and the step the
  implicit-heat factors were made for; a viscoplastic column's last two enthalpy increments and
  steps, its Picard predictor, the depth of its mechanics window);
* the output writers' positions (bytes of each CSV file, field outputs written, the next
  field time) and the next checkpoint time, and the deck (JSON) it was taken with.

The walk saves every NumPy array, number, string and list of them found in the objects'
attributes; objects reached through :data:`CHILDREN` are walked in turn, other objects
(materials, the mesh, the problem set-up, caches) are rebuilt from the deck.  No random
numbers are drawn anywhere, so nothing else determines the continuation.  The file is written
to a temporary name and moved into place (``os.replace``): a run killed while writing one
keeps the previous checkpoint.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import h5py
import numpy as np

from shockfriction.errors import DeckError

FORMAT = 3  # 3: energy rows with the contact books (friction_heat, column_heat, contact_heat); 2: sub-grid column
# state stored column-innermost (0.3.0); a checkpoint of another format is refused
CHECKPOINT = "checkpoint.h5"
# the objects a checkpoint walks into, by class name and attribute
CHILDREN = {
    "Simulation": ("state",),
    "State": ("energy",),
    "SlideLineInterface": ("line",),
    "SlideLine": ("record", "friction_model"),
    "SubgridFriction": ("columns",),
    "SubgridInterface": ("columns",),
}
# set-up values that a restart takes from the deck and the command line, not from the checkpoint
SKIP = {"Simulation": {"t_end", "max_cycles", "threads", "parallel", "out_dir", "_node_ptr", "_node_corner",
                       "_probes_on_nodes", "_shift_lists"},
        "ViscoplasticColumns": {"_oth"}}  # scratch of the kernel
# arrays that checkpoints of earlier builds hold and this one no longer keeps (scratch): ignored on load
DROPPED = {"Simulation": {"_corner"}}  # the force pass's scratch, now Simulation._force_scratch (a tuple)
# deck fields a restart may change: the end time, the cycle limit and the checkpoint interval
MAY_CHANGE = {("time", "end"), ("time", "max_cycles"), ("output", "checkpoint_interval")}


def _is_float(v) -> bool:
    return isinstance(v, (float, np.floating)) and not isinstance(v, bool)


def _scalar(v) -> bool:
    return v is None or isinstance(v, (bool, int, float, str, np.generic))


def _save_list(grp, name: str, v: list, scalars: dict) -> None:
    if not v:
        scalars[name] = []
    elif all(_is_float(x) for x in v):
        grp.create_dataset(name, data=np.asarray(v, dtype=np.float64)).attrs["kind"] = "floats"
    elif all(isinstance(x, np.ndarray) for x in v) and len({(x.shape, x.dtype) for x in v}) == 1:
        grp.create_dataset(name, data=np.stack(v)).attrs["kind"] = "arrays"
    elif all(isinstance(x, tuple) and all(_is_float(y) for y in x) for x in v) and len({len(x) for x in v}) == 1:
        grp.create_dataset(name, data=np.asarray(v, dtype=np.float64)).attrs["kind"] = "tuples"
    elif all(_scalar(x) for x in v):
        scalars[name] = [x.item() if isinstance(x, np.generic) else x for x in v]
    else:
        raise TypeError(f"checkpoint: list attribute {name!r} holds values of mixed kinds")


def _load_list(ds) -> list:
    data = ds[()]
    kind = ds.attrs["kind"]
    if kind == "floats":
        return [float(x) for x in data]
    if kind == "tuples":
        return [tuple(float(y) for y in row) for row in data]
    return [row.copy() for row in data]


def save_object(grp, obj) -> None:
    """Write the state of ``obj`` (and of its :data:`CHILDREN`) into the HDF5 group ``grp``."""
    cls = type(obj).__name__
    grp.attrs["class"] = cls
    children, skip = CHILDREN.get(cls, ()), SKIP.get(cls, set())
    scalars: dict = {}
    for name, v in vars(obj).items():
        if name in skip:
            continue
        if name in children:
            if v is not None:
                save_object(grp.create_group(name), v)
        elif isinstance(v, np.ndarray):
            grp.create_dataset(name, data=v)
        elif _scalar(v):
            scalars[name] = v.item() if isinstance(v, np.generic) else v
        elif isinstance(v, list):
            if all(_scalar(x) or isinstance(x, (np.ndarray, tuple)) for x in v):
                _save_list(grp, name, v, scalars)
        elif isinstance(v, dict) and v and all(isinstance(x, list) for x in v.values()):
            sub = grp.create_group(name)
            sub.attrs["class"] = "dict"
            sub_scalars: dict = {}
            for key, x in v.items():
                _save_list(sub, key, x, sub_scalars)
            sub.attrs["scalars"] = json.dumps(sub_scalars)
    grp.attrs["scalars"] = json.dumps(scalars)


def load_object(grp, obj, where: str) -> None:
    """Put the state saved by :func:`save_object` back into ``obj`` (arrays copied in place where
    their shape is unchanged, so that other objects holding them see the restored values)."""
    cls = type(obj).__name__
    if grp.attrs["class"] != cls:
        raise DeckError(f"checkpoint {where}: holds a {grp.attrs['class']}, the deck builds a {cls}")
    for name, v in json.loads(grp.attrs["scalars"]).items():
        setattr(obj, name, v)
    dropped = DROPPED.get(cls, set())
    for name, item in grp.items():
        if name in dropped:
            continue
        if isinstance(item, h5py.Group):
            if item.attrs["class"] == "dict":
                d = {key: _load_list(ds) for key, ds in item.items()}
                d.update(json.loads(item.attrs["scalars"]))
                setattr(obj, name, d)
            else:
                child = getattr(obj, name, None)
                if child is None:
                    raise DeckError(f"checkpoint {where}.{name}: the deck builds no such object")
                load_object(item, child, f"{where}.{name}")
        elif "kind" in item.attrs:
            setattr(obj, name, _load_list(item))
        else:
            data = item[()]
            cur = getattr(obj, name, None)
            if isinstance(cur, np.ndarray) and cur.shape == data.shape and cur.dtype == data.dtype:
                cur[...] = data
            else:
                setattr(obj, name, data)


def _deck_dict(deck) -> dict:
    return json.loads(deck.model_dump_json())


def save_checkpoint(out_dir: str | Path, sim, writers: dict) -> Path:
    """Write ``out_dir/checkpoint.h5`` (atomically) from ``sim`` and the writers' positions."""
    from shockfriction import __version__

    path = Path(out_dir) / CHECKPOINT
    tmp = path.with_name(f".{path.name}.tmp")
    with h5py.File(tmp, "w") as h5:
        h5.attrs["format"] = FORMAT
        h5.attrs["version"] = __version__
        h5.attrs["time_s"] = sim.state.t
        h5.attrs["cycle"] = sim.state.cycle
        h5.attrs["threads"] = sim.threads
        h5.create_dataset("deck", data=json.dumps(_deck_dict(sim.problem.deck)))
        h5.create_dataset("writers", data=json.dumps(writers))
        save_object(h5.create_group("simulation"), sim)
        grp = h5.create_group("interfaces")
        for k, obj in enumerate(sim.interfaces):
            save_object(grp.create_group(str(k)), obj)
    with open(tmp, "rb+") as fh:
        os.fsync(fh.fileno())
    os.replace(tmp, path)
    return path


def _differences(a, b, path=()) -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for key in sorted(set(a) | set(b)):
            if path + (key,) not in MAY_CHANGE:
                out += _differences(a.get(key), b.get(key), path + (key,))
        return out
    return [] if a == b else [".".join(str(p) for p in path)]


def load_checkpoint(out_dir: str | Path, sim) -> dict:
    """Restore ``sim`` (built from the same deck) from ``out_dir/checkpoint.h5``; return the
    writers' positions saved with it (plus ``time_s``, ``cycle``, ``threads``)."""
    path = Path(out_dir) / CHECKPOINT
    if not path.is_file():
        raise DeckError(f"--restart: no checkpoint in {out_dir} (expected {path.name}; set "
                        "[output] checkpoint_interval to write one)")
    try:
        h5 = h5py.File(path, "r")
    except OSError as exc:
        raise DeckError(f"--restart: {path} cannot be read as HDF5 ({exc})") from None
    with h5:
        if int(h5.attrs.get("format", -1)) != FORMAT:
            raise DeckError(f"--restart: {path} has checkpoint format {h5.attrs.get('format')}, expected {FORMAT}")
        diff = _differences(json.loads(h5["deck"][()]), _deck_dict(sim.problem.deck))
        if diff:
            raise DeckError(f"--restart: deck fields {', '.join(diff)} differ from the deck the checkpoint was "
                            "taken with; expected the same deck (only time.end, time.max_cycles and "
                            "output.checkpoint_interval may change)")
        grp = h5["interfaces"]
        if len(grp) != len(sim.interfaces):
            raise DeckError(f"--restart: the checkpoint holds {len(grp)} interfaces, the deck builds "
                            f"{len(sim.interfaces)}")
        load_object(h5["simulation"], sim, "simulation")
        for k, obj in enumerate(sim.interfaces):
            load_object(grp[str(k)], obj, f"interfaces[{k}]")
        info = json.loads(h5["writers"][()])
        info.update(time_s=float(h5.attrs["time_s"]), cycle=int(h5.attrs["cycle"]), threads=int(h5.attrs["threads"]))
    return info
