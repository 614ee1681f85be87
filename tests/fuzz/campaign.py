"""A larger fuzzing campaign over the example decks (not part of pytest; one process, modest CPU).

    PYTHONPATH=src python tests/fuzz/campaign.py --cases 400 --timeout 60 --seed 1

Prints the counts of exit codes, tracebacks and hangs, and every case that is not an exit 0/2/3
with a one-line message (the mutation is reproducible from its seed: ``--only SEED``).
"""

from __future__ import annotations

import argparse
import collections
import random
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from deckfuzz import DECKS, MUTATIONS, mutate, run_case


def case(seed: int):
    rnd = random.Random(seed)
    cmd, name = rnd.choice(DECKS)
    kind = rnd.choice(MUTATIONS)
    return cmd, name, kind, mutate(cmd, name, kind, rnd)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=400)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", type=int, default=None)
    a = ap.parse_args()
    seeds = [a.only] if a.only is not None else [a.seed * 1_000_003 + k for k in range(a.cases)]
    codes = collections.Counter()
    bad = []
    internal = []
    numpy_repr = []
    t0 = time.time()
    with tempfile.TemporaryDirectory(prefix="sf-fuzz-") as tmp:
        for k, seed in enumerate(seeds):
            cmd, name, kind, deck = case(seed)
            out = run_case(cmd, deck, Path(tmp) / f"c{k}", a.timeout, name)
            key = "hang" if out.hang else ("traceback" if out.traceback else f"exit {out.code}")
            codes[key] += 1
            line = f"seed {seed} {cmd} {name} {kind}: {key} {out.seconds:.1f}s :: {out.message[:200]}"
            if out.hang or out.traceback or out.code not in (0, 2, 3) or (out.code in (2, 3) and not out.message):
                bad.append(line)
            if "internal error" in out.stderr:
                internal.append(line)
            if "np.float64(" in out.stderr:
                numpy_repr.append(line)
            print(line, flush=True)
    print(f"\n{len(seeds)} cases in {time.time() - t0:.0f} s: " + ", ".join(f"{k}: {v}" for k, v in sorted(codes.items())))
    print(f"tracebacks: {codes['traceback']}, hangs: {codes['hang']}, internal errors (catch-all): {len(internal)}, "
          f"np.float64 in messages: {len(numpy_repr)}")
    for line in bad + internal + numpy_repr:
        print("  ", line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
