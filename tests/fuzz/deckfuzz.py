"""Mutated example decks, run in-process through the command line (shared by the test and the campaign).

A case is (example deck, mutation): delete a key, change a value's type or unit, set it to zero,
a negative, NaN, inf or a huge number, use an unknown name, add an unknown key, truncate the text,
insert garbage bytes or a non-UTF-8 byte.  ``run_case`` runs ``shockfriction CMD DECK`` inside
this process with a time box (SIGALRM) and returns its exit code, stderr and whether a traceback
or a hang happened.  The run decks are shortened first (``time.end`` <= 50 ns, subgrid duration
20 ns) so that a valid mutated deck ends quickly; the mutation may then change those values too.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import random
import signal
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

# (command, deck): run decks, sub-grid decks, sweep/fit files validated with --dry-run
DECKS = [
    ("run", "plate_impact_al_250ms.toml"),
    ("run", "pressure_shear_steel.toml"),
    ("run", "pressure_shear_strip.toml"),
    ("run", "taylor_anvil_cu.toml"),
    ("run", "cone_impact_axi.toml"),
    ("run", "cone_in_cylinder.toml"),
    ("subgrid", "subgrid/ball_al_200ms.toml"),
    ("subgrid", "subgrid/prakash_9702.toml"),
    ("sweep", "calibration/ball_mu0_f_grid.toml"),
    ("sweep", "calibration/plate_impact_velocity_sweep.toml"),
]

MUTATIONS = ("delete", "type", "unit", "zero", "negative", "nan", "inf", "huge", "tiny", "unknown_name",
             "unknown_key", "truncate", "garbage", "non_utf8", "empty_list", "duplicate_list_item")

UNIT_SWAPS = ["3 kg", "5 m/s", "2 GPa", "7 us", "300 K", "4 mm", "12", "1 furlong/fortnight", "m/s", ""]


def toml_text(d: dict) -> str:
    """TOML of a dict: every top-level key as ``"key" = <inline value>`` (any nesting)."""
    def v(x):
        if isinstance(x, bool):
            return "true" if x else "false"
        if isinstance(x, str):
            return json.dumps(x)
        if isinstance(x, float):
            if math.isnan(x):
                return "nan"
            if math.isinf(x):
                return "inf" if x > 0 else "-inf"
            return repr(x)
        if isinstance(x, int):
            return repr(x)
        if isinstance(x, list):
            return "[" + ", ".join(v(y) for y in x) + "]"
        if isinstance(x, dict):
            return "{" + ", ".join(f"{json.dumps(str(k))} = {v(y)}" for k, y in x.items()) + "}"
        raise TypeError(type(x))
    return "".join(f"{json.dumps(str(k))} = {v(x)}\n" for k, x in d.items())


def _shorten(cmd: str, d: dict) -> dict:
    if cmd == "run":
        d.setdefault("time", {})["end"] = "50 ns"
        d.get("output", {}).pop("field_interval", None)
        for sl in d.get("slide_lines", []):
            if isinstance(sl, dict) and "record_interval" in sl:
                sl["record_interval"] = "10 ns"
    elif cmd == "subgrid":
        d["duration"] = "20 ns"
        d["dt"] = "1 ns"
        d["output_times"] = ["10 ns"]
        d.setdefault("column", {})["cells"] = 100
        for ld in d.get("loading", []):
            ld["times"] = ld["times"][:1]
            for k in ("slip_velocity", "normal_stress", "heat_flux"):
                if k in ld:
                    ld[k] = ld[k][:1]
    return d


def _leaves(node, path=()):
    """Every (path, value) of a nested dict/list, containers included."""
    out = []
    if isinstance(node, dict):
        for k, x in node.items():
            out.append((path + (k,), x))
            out += _leaves(x, path + (k,))
    elif isinstance(node, list):
        for i, x in enumerate(node):
            out.append((path + (i,), x))
            out += _leaves(x, path + (i,))
    return out


def _set(d, path, value=..., delete=False):
    cur = d
    for k in path[:-1]:
        cur = cur[k]
    if delete:
        del cur[path[-1]]
    else:
        cur[path[-1]] = value


def _scaled(x, how: str, rnd: random.Random):
    """A value of ``x``'s kind made zero, negative, NaN, inf, huge or tiny (unit kept)."""
    if isinstance(x, bool):
        return not x
    if isinstance(x, (int, float)):
        return {"zero": 0, "negative": -abs(x) - 1, "nan": float("nan"), "inf": float("inf"),
                "huge": rnd.choice([10**9, 10**18, 1e300]), "tiny": 1e-300}[how]
    if isinstance(x, str):
        parts = x.split(maxsplit=1)
        unit = parts[1] if len(parts) == 2 else ""
        num = {"zero": "0", "negative": "-" + parts[0].lstrip("-") if parts else "-1", "nan": "nan", "inf": "inf",
               "huge": rnd.choice(["1e300", "1e30", "1e12"]), "tiny": "1e-300"}[how]
        return f"{num} {unit}".strip()
    return x


def mutate(cmd: str, name: str, kind: str, rnd: random.Random) -> bytes:
    """The bytes of a mutated copy of example ``name`` (mutation ``kind``, choices from ``rnd``)."""
    d = _shorten(cmd, tomllib.loads((EXAMPLES / name).read_text()))
    leaves = _leaves(d)
    path, _ = rnd.choice(leaves)
    scalars = [(p, x) for p, x in leaves if not isinstance(x, (dict, list))] or leaves
    sp, sv = rnd.choice(scalars)
    if kind == "delete":
        _set(d, path, delete=True)
    elif kind == "type":
        _set(d, sp, rnd.choice([[sv], {"x": sv}, True, 7, 2.5, "text", []]))
    elif kind == "unit":
        strings = [(p, x) for p, x in scalars if isinstance(x, str)] or scalars
        p, _ = rnd.choice(strings)
        _set(d, p, rnd.choice(UNIT_SWAPS))
    elif kind in ("zero", "negative", "nan", "inf", "huge", "tiny"):
        _set(d, sp, _scaled(sv, kind, rnd))
    elif kind == "unknown_name":
        named = [(p, x) for p, x in scalars if p[-1] in ("material", "body", "name", "other_material", "law",
                                                        "model", "kind", "geometry", "eos", "strength", "method")]
        p, _ = rnd.choice(named or scalars)
        _set(d, p, rnd.choice(["Unobtainium", "../../etc/passwd", "a/b", "", "x" * 300, "flyer"]))
    elif kind == "unknown_key":
        tables = [(p, x) for p, x in leaves if isinstance(x, dict)] + [((), d)]
        p, t = rnd.choice(tables)
        t[rnd.choice(["colour", "end_time", "velocty", "nx ", "mass"])] = rnd.choice([1, "1 m", [1, 2]])
    elif kind == "empty_list":
        lists = [(p, x) for p, x in leaves if isinstance(x, list)]
        if lists:
            _set(d, rnd.choice(lists)[0], [])
    elif kind == "duplicate_list_item":
        lists = [(p, x) for p, x in leaves if isinstance(x, list) and x]
        if lists:
            p, x = rnd.choice(lists)
            _set(d, p, x + [x[0]])
    text = toml_text(d).encode()
    if kind == "truncate":
        text = text[: rnd.randrange(len(text))]
    elif kind == "garbage":
        k = rnd.randrange(len(text))
        text = text[:k] + bytes(rnd.randrange(256) for _ in range(rnd.randint(1, 8))) + text[k:]
    elif kind == "non_utf8":
        k = rnd.randrange(len(text))
        text = text[:k] + b"\xff\xfe" + text[k:]
    return text


@dataclass
class Outcome:
    code: int | None
    stderr: str
    seconds: float
    traceback: bool
    hang: bool

    @property
    def message(self) -> str:
        lines = [ln for ln in self.stderr.splitlines() if ln.strip()]
        return lines[-1] if lines else ""


class _TimeBox(BaseException):
    """Raised by SIGALRM when a case exceeds its time box (a BaseException: nothing may swallow it)."""


def run_case(cmd: str, deck: bytes, folder: Path, timeout_s: float, name: str = "deck") -> Outcome:
    """Run ``shockfriction CMD deck`` in this process (output folder inside ``folder``), time-boxed."""
    from shockfriction.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    # a mutated sweep/fit file keeps its references: it sits beside the example it came from
    path = (EXAMPLES / name).parent / f".fuzz_{folder.name}.toml" if cmd == "sweep" else folder / "deck.toml"
    path.write_bytes(deck)
    argv = [cmd, str(path), "--out", str(folder / "out")] + (["--dry-run"] if cmd == "sweep" else [])
    err = io.StringIO()
    code, tb, hang = None, False, False

    def alarm(signum, frame):
        raise _TimeBox()

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, timeout_s)
    t0 = time.perf_counter()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            main(argv)
        code = 0
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except _TimeBox:
        hang = True
    except BaseException as exc:  # noqa: BLE001 - an escaped exception is a traceback for the user
        tb = True
        err.write(f"\nTraceback (most recent call last): escaped {type(exc).__name__}: {exc}\n")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        if cmd == "sweep":
            path.unlink(missing_ok=True)
    text = err.getvalue()
    return Outcome(code, text, time.perf_counter() - t0, tb or "Traceback (most recent call last)" in text, hang)
