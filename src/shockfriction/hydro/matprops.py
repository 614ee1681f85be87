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
EOS_MG_CUBIC = 2  # Mie-Grueneisen with the cubic tension branch (docs/theory/spall-and-tension.md)
# strength kinds
STRENGTH_NONE = 0
STRENGTH_EPP = 1
STRENGTH_SCG = 2
# spall (failure) models
SPALL_NONE = 0
SPALL_CUTOFF = 1  # fails when P < -p_spall
SPALL_TULER_BUTCHER = 2  # fails when int (sigma_1 - sigma_0)^lambda dt >= K

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
P_SPALL = P_SCG + 9  # spall model (SPALL_*)
P_PSPALL = P_SPALL + 1  # spall strength p_spall > 0 (cut-off)
P_TB_SIGMA0 = P_SPALL + 2  # Tuler-Butcher threshold sigma_0
P_TB_LAMBDA = P_SPALL + 3  # Tuler-Butcher exponent lambda
P_TB_K = P_SPALL + 4  # Tuler-Butcher damage constant K (Pa^lambda s)
N_PROPS = P_SPALL + 5

N_TABLE = 2049


def empty_props(n: int) -> np.ndarray:
    """n rows with safe defaults (no strength, no floor)."""
    p = np.zeros((n, N_PROPS))
    p[:, P_PMIN] = -np.inf
    p[:, P_GAMMA] = 1.4
    p[:, P_CV] = 1.0
    return p
