"""Per-body material rows for the numba kernels (one float64 row per body).

The kernels read a 2D array ``props[body, column]`` with the columns below, and
``isentrope[body, :]`` (the reference isentrope energy e_s(mu) used for the
temperature, see :mod:`shockfriction.hydro.eos`).
"""

from __future__ import annotations

import numpy as np

# EOS kinds
EOS_MIE_GRUNEISEN = 0
EOS_IDEAL_GAS = 1
# strength kinds
STRENGTH_NONE = 0
STRENGTH_EPP = 1
STRENGTH_SCG = 2

# columns
P_EOS = 0
P_RHO0 = 1
P_C0 = 2
P_S = 3
P_GAMMA0 = 4
P_GAMMA = 5  # ideal-gas ratio of specific heats
P_CV = 6
P_T0 = 7
P_STRENGTH = 8
P_G0 = 9
P_Y0 = 10  # yield of the elastic-perfectly-plastic model
P_G_CONST = 11  # 1: elastic predictor with G0 (thesis); 0: with G(P, T) (Steinberg)
P_PMIN = 12  # pressure floor (spall cut-off), -inf for none
P_MU_LO = 13  # isentrope table range in mu = rho/rho0 - 1
P_MU_HI = 14
P_SCG = 15  # 9 SCG parameters in materials.library.SCG_ORDER
N_PROPS = P_SCG + 9

N_TABLE = 2049


def empty_props(n: int) -> np.ndarray:
    """n rows with safe defaults (no strength, no floor)."""
    p = np.zeros((n, N_PROPS))
    p[:, P_PMIN] = -np.inf
    p[:, P_GAMMA] = 1.4
    p[:, P_CV] = 1.0
    return p
