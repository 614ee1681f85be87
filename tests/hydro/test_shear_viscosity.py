"""Kernel properties of the deviatoric shear viscosity (shockfriction.hydro.shear_viscosity):
dissipative (sum F.v <= 0 for any velocities, equal to -2 eta D':D' V), momentum-free in plane
strain, silent for rigid motions and for a plane longitudinal wave (phi = 0), active for a plane
shear wave (phi = 1)."""

import numpy as np
import pytest

from shockfriction.hydro.geometry import bvec_axi, bvec_planar
from shockfriction.hydro.shear_viscosity import shear_viscosity_forces

CONN = np.array([[0, 1, 2, 3]])
X = np.array([0.0, 1.0, 1.1, -0.1]) * 1e-3 + 2e-3
Y = np.array([0.0, 0.1, 1.0, 0.9]) * 1e-3


def _forces(vx, vy, axi=False, elastic_only=False, sxx=0.0, yld=1e9):
    *_, area = bvec_planar(*X, *Y)
    if axi:
        *b, vol = bvec_axi(*X, *Y)
    else:
        b, vol = list(bvec_planar(*X, *Y)[:8]) + [0.0] * 4, area
    on, *f = shear_viscosity_forces(26e9, 2700.0, sxx, 0.0, 0.0, yld, elastic_only, 0.15, 1.0, area, vol, 1.0 / vol,
                                    np.sqrt(area), tuple(b[0:4]), tuple(b[4:8]), tuple(b[8:12]),
                                    tuple(vx), tuple(vy))
    f = np.array(f)
    assert on == bool(np.any(f != 0.0))
    return f[:4], f[4:]


@pytest.mark.parametrize("axi", [False, True])
def test_dissipative_for_random_velocities(axi):
    rng = np.random.default_rng(1)
    active = 0
    for _ in range(50):
        vx, vy = rng.normal(0, 100, 4), rng.normal(0, 100, 4)
        fx, fy = _forces(vx, vy, axi)
        scale = np.abs(fx).sum() + np.abs(fy).sum()
        active += scale > 0.0      # phi = 1 - (tr L)^2/|L|^2 <= 0 (expansion-like gradients): no forces
        assert fx @ vx + fy @ vy <= 1e-12 * scale * 100
        if not axi:
            assert abs(fx.sum()) + abs(fy.sum()) <= 1e-9 * scale
    assert active > 10


def test_rigid_motion_and_plane_longitudinal_wave_are_left_alone():
    w = 1e4
    for vx, vy in ((np.full(4, 30.0), np.full(4, -5.0)), (-w * Y, w * X)):
        fx, fy = _forces(vx, vy)
        assert np.abs(fx).max() + np.abs(fy).max() < 1e-9
    # plane longitudinal wave along y: v = (0, a y)
    fx, fy = _forces(np.zeros(4), 1e5 * Y)
    assert np.abs(fx).max() + np.abs(fy).max() < 1e-6


def test_plane_shear_wave_is_damped_unless_yielding():
    vx, vy = 1e5 * Y, np.zeros(4)          # v = (a y, 0): pure shear, phi = 1
    fx, fy = _forces(vx, vy)
    assert fx @ vx < 0.0
    fx, fy = _forces(vx, vy, elastic_only=True, sxx=1e9, yld=1.0e9)   # at yield: off
    assert np.abs(fx).max() == 0.0
    fx, fy = _forces(vx, vy, elastic_only=True, sxx=1e8, yld=1.0e9)   # elastic: on
    assert fx @ vx < 0.0
