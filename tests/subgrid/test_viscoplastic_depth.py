"""The viscoplastic column continued into the body (issue 10, item 2): the grid, the deck's ``depth`` and its
``"auto"`` value 1.2 c_s(p_max, T0) t_end.  The well-posedness it buys is measured in
test_viscoplastic_wellposed_slow.py."""

import math

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.deck.subgrid import SubgridDeck
from shockfriction.friction.subgrid.column import extend_grid, make_grid
from shockfriction.friction.subgrid.driver import run_subgrid
from shockfriction.materials.library import get_material
from shockfriction.materials.strength import scg_shear_ratio


def test_extension_is_geometric_and_ends_at_the_depth():
    z = extend_grid(make_grid(20e-6, 500), 5e-3, 1.05)
    dz = np.diff(z)
    assert z[-1] == 5e-3 and np.all(dz > 0)
    assert np.allclose(dz[:500], 40e-9)
    r = dz[501:-1] / dz[500:-2]
    assert np.allclose(r, 1.05, rtol=1e-12)
    assert 1.05 <= dz[-1] / dz[-2] < 1.05 * 1.6  # the last cell absorbs the remainder
    k = math.log(1 + (5e-3 - 20e-6) * 0.05 / (40e-9 * 1.05)) / math.log(1.05)  # sum of dz0 r^i = D - h
    assert dz.size - 500 in (math.floor(k), math.ceil(k))
    assert extend_grid(z, 1e-3) is z  # no extension above the end


def deck(**vp):
    return {"model": "viscoplastic", "material": "Al5083-H111", "other_material": "AISI321", "duration": "20 ns",
            "dt": "1 ns", "column": {"thickness": "2 um", "cells": 50},
            "friction": {"mu0": 0.3, "f": 0.7}, "viscoplastic": vp,
            "loading": [{"times": ["0 us"], "slip_velocity": ["200 m/s"], "normal_stress": ["10 GPa"]}]}


@pytest.mark.parametrize("depth, expect", [("auto", None), ("none", 2e-6), ("0.1 mm", 1e-4)])
def test_deck_depth(tmp_path, depth, expect):
    res = run_subgrid(SubgridDeck.model_validate(deck(depth=depth)), tmp_path)
    if expect is None:  # 1.2 c_s(10 GPa, 300 K) x 20 ns
        m = get_material("Al5083-H111")
        r = scg_shear_ratio(10e9, 300.0, m.scg_g, m.scg_h, m.scg_xi, m.melting_temperature)
        expect = 1.2 * math.sqrt(m.G0 * r / m.rho0) * 20e-9
    assert res.z[-1] == pytest.approx(expect, rel=1e-12)
    assert np.all(np.isfinite(res.theta_interface)) and np.all(np.isfinite(res.tau))


def test_bad_depth_exits_2(tmp_path, capsys):
    text = ('model = "viscoplastic"\nmaterial = "Al5083-H111"\nother_material = "AISI321"\nduration = "20 ns"\n'
            'dt = "1 ns"\n[friction]\nmu0 = 0.3\nf = 0.7\n[viscoplastic]\ndepth = "deep"\n'
            '[[loading]]\ntimes = ["0 us"]\nslip_velocity = ["200 m/s"]\nnormal_stress = ["10 GPa"]\n')
    p = tmp_path / "d.toml"
    p.write_text(text)
    with pytest.raises(SystemExit) as exc:
        main(["subgrid", str(p), "--out", str(tmp_path / "o")])
    assert exc.value.code == 2
    assert "depth" in capsys.readouterr().err
