"""Material library and the shared SCG strength module."""

import math

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.errors import DeckError
from shockfriction.materials import get_material, material_names
from shockfriction.materials.library import heat_share
from shockfriction.materials.strength import scg_shear_modulus, scg_yield, shear_modulus, yield_stress

REQUIRED = ["Al5083-H111", "AISI321", "Al6061-T6", "SS304", "Cu-OFHC", "Ti-6Al-4V", "Steel4340"]


def test_library_holds_the_required_materials_with_sources():
    names = material_names()
    for name in REQUIRED:
        assert name in names
        m = get_material(name)
        for p in m.parameters.values():
            assert p.source and p.status in ("thesis", "checked", "to verify", "derived")
        assert m.has("eos_c0") and m.has("eos_s") and m.has("eos_gamma0")


def test_thesis_pair_derived_constants_match_the_digest():
    al, st = get_material("Al5083-H111"), get_material("AISI321")
    assert al.heat_capacity == pytest.approx(885, rel=2e-3)   # kappa/(rho alpha), digest 5.2
    assert st.heat_capacity == pytest.approx(500, rel=2e-3)
    assert al.effusivity == pytest.approx(16731, rel=1e-3)
    assert st.effusivity == pytest.approx(7975, rel=1e-3)
    assert heat_share(al, st) == pytest.approx(0.677, abs=1e-3)


def test_unknown_material_is_a_deck_error_listing_the_library():
    with pytest.raises(DeckError, match="unknown material 'Unobtainium'.*Al5083-H111"):
        get_material("Unobtainium")


def test_scg_check_values_from_the_digest():
    al, st = get_material("Al5083-H111"), get_material("AISI321")
    # G/G0 at F_N = 0 / 10 GPa and 300 K (digest part 3, 5.2): 0.9997/1.651 and 0.9999/1.226
    assert shear_modulus(al, 0.0, 300.0) / al.G0 == pytest.approx(0.99975, abs=1e-4)
    assert shear_modulus(al, 10e9, 300.0) / al.G0 == pytest.approx(1.651, abs=1e-3)
    assert shear_modulus(st, 10e9, 300.0) / st.G0 == pytest.approx(1.226, abs=1e-3)
    # melt factor exp(-xi T/(T_F - T)) for Al: 0.942 at 1200 K, 0.30 at 1219 K (digest part 1, 7.3)
    base = lambda T: 1 - al.scg_h * (T - 300)
    assert shear_modulus(al, 0.0, 1200.0) / al.G0 / base(1200.0) == pytest.approx(math.exp(-0.06), rel=1e-12)
    assert shear_modulus(al, 0.0, 1219.0) / al.G0 / base(1219.0) == pytest.approx(0.296, abs=2e-3)
    # tau0 = f Ymax/sqrt(3) G/G0 with f = 0.3 at 10 GPa: 194.5 MPa (Al) and 531 MPa (steel)
    assert 0.3 * yield_stress(al, 1e9, 10e9, 300.0) / math.sqrt(3) == pytest.approx(194.5e6, rel=2e-3)
    assert 0.3 * yield_stress(st, 1e9, 10e9, 300.0) / math.sqrt(3) == pytest.approx(531e6, rel=2e-3)


def test_scg_is_zero_at_and_above_melting_and_never_negative():
    al = get_material("Al5083-H111")
    T = np.array([1219.999, 1220.0, 1500.0])
    assert np.all(shear_modulus(al, 0.0, T) >= 0.0)
    assert shear_modulus(al, 0.0, 1220.0) == 0.0 and shear_modulus(al, 0.0, 2000.0) == 0.0
    assert shear_modulus(al, -1e12, 300.0) == 0.0   # huge tension: clamped, not negative


def test_njit_kernels_agree_with_numpy_wrappers():
    cu = get_material("Cu-OFHC")
    p = cu.scg_params()
    for eps, P, T in [(0.0, 0.0, 300.0), (0.1, 5e9, 600.0), (2.0, 20e9, 1500.0)]:
        assert scg_shear_modulus(P, T, p) == pytest.approx(float(shear_modulus(cu, P, T)), rel=1e-14)
        assert scg_yield(eps, P, T, p) == pytest.approx(float(yield_stress(cu, eps, P, T)), rel=1e-14)
    # hardening saturates at Ymax
    assert scg_yield(1e6, 0.0, 300.0, p) == pytest.approx(cu.Ymax * float(shear_modulus(cu, 0, 300.0)) / cu.G0)


def test_materials_command_lists_and_shows(capsys):
    with pytest.raises(SystemExit) as e:
        main(["materials"])
    assert e.value.code == 0
    assert "Al5083-H111" in capsys.readouterr().out
    with pytest.raises(SystemExit) as e:
        main(["materials", "AISI321"])
    out = capsys.readouterr().out
    assert e.value.code == 0 and "scg_beta" in out and "thesis" in out
    with pytest.raises(SystemExit) as e:
        main(["materials", "nope"])
    assert e.value.code == 2
