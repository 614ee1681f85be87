"""The column kernels compile one version whatever the caller hands in.

numba compiles a kernel once per argument type, and a read-only array, a broadcast scalar (stride 0) and a
writable contiguous array are three types: before ``column.per_column`` the columns' step passed the caller's
arrays through, and the test suite compiled the chapter 8 solve three times and the viscoplastic column kernel
eleven times (~40 s and ~11 s apiece on the 2-core machine).  Here each model steps once with writable arrays
(the kernels compile or load their version), then with read-only arrays, broadcast scalars and read-only views:
no kernel may gain a version.  (Dropping the copy for read-only inputs in ``per_column`` fails it.)"""

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

from shockfriction.friction.subgrid import (column, excess_layer, inertial_column, interface, thermoelastic,
                                            thermoelastoplastic, viscoplastic)
from shockfriction.friction.subgrid.column import per_column
from shockfriction.friction.subgrid.interface import SubgridInterface

MODULES = (column, excess_layer, inertial_column, interface, thermoelastic, thermoelastoplastic, viscoplastic)


def _versions() -> dict[str, int]:
    out = {}
    for mod in MODULES:
        for name, obj in vars(mod).items():
            if isinstance(obj, CPUDispatcher):
                out[f"{mod.__name__}.{name}"] = len(obj.signatures)
    return out


def _readonly(a):
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@pytest.mark.parametrize("model, options", [("thermoelastoplastic", None),
                                            ("viscoplastic", {"far_end": "excess"}),
                                            ("viscoplastic", {"far_end": "impedance"})])
def test_the_column_kernels_compile_one_version_whatever_the_inputs(model, options):
    n = 4
    sg = SubgridInterface(n, "Al5083-H111", "AISI321", thickness=10e-6, n_cells=40, model=model, mu0=0.5, f=0.7,
                          viscoplastic=options)
    sig = np.full(n, 5e9)
    v = np.array([0.0, 200.0, 400.0, 800.0])
    mass = np.full(n, 1e-3)
    sg.step(sig, v, v.copy(), mass, mass.copy(), np.ones(n), 1e-9)  # writable arrays: the version every run uses
    before = _versions()
    sg.step(_readonly(sig), _readonly(v), _readonly(v), _readonly(mass), _readonly(mass), _readonly(np.ones(n)), 1e-9)
    sg.step(5e9, _readonly(v), v[::-1][::-1], 1e-3, np.broadcast_to(np.float64(1e-3), (n,)), 1.0, 1e-9)
    after = _versions()
    grew = {k: (before.get(k, 0), m) for k, m in after.items() if m > before.get(k, 0)}
    assert not grew, f"kernels compiled again for read-only or broadcast inputs: {grew}"


def test_per_column_passes_a_writable_array_and_copies_the_rest():
    a = np.arange(3.0)
    assert per_column(a, 3) is a
    for x in (_readonly(a), np.broadcast_to(2.0, (3,)), 2.0, np.arange(6.0)[::2], [1, 2, 3]):
        b = per_column(x, 3)
        assert b.shape == (3,) and b.dtype == np.float64 and b.flags.c_contiguous and b.flags.writeable
        assert np.array_equal(b, np.broadcast_to(np.asarray(x, float), (3,)))
