"""The flat bundle of scalars compiled loops read: kernel, EOS, viscosity, diffusion.

Python objects (kernels, EOS, viscosity models) describe a simulation; this
named tuple is what they compile down to. Numba types it once (all fields
are int or float), so one compiled function serves every combination.
"""

from typing import NamedTuple

# density diffusion models
DIFFUSION_NONE = 0
DIFFUSION_MOLTENI = 1      # Molteni & Colagrossi (2009)
DIFFUSION_RENORMALISED = 2  # Antuono et al. (2010) / Marrone et al. (2011): delta-SPH


class Physics(NamedTuple):
    dim: int
    kernel: int
    h: float
    sigma: float          # kernel normalisation sigma_d(h)
    support2: float       # squared support radius
    eta2: float           # (0.1 h)^2, regularises 1/r^2 terms
    rho0: float
    eos: int
    c0: float
    gamma: float
    p_background: float
    alpha: float          # Monaghan artificial viscosity, fluid-fluid
    beta: float
    nu: float             # laminar kinematic viscosity [m^2/s]
    diffusion: int
    delta: float
    lagged_gradient: int  # delta-SPH: use the previous evaluation's <grad rho>^L (one pass)
    tensile: int          # Monaghan (2000) tensile correction on/off
    inv_w_dx: float       # 1 / W(dx) for the tensile correction
    xsph: float           # XSPH epsilon (0 = off)
    gx: float
    gy: float
    gz: float
    # artificial viscosity on every pair (1, Marrone et al. 2011 / [Huang2019] eq. 5) or only on
    # approaching pairs v_ij . r_ij < 0 (0, Monaghan 1992 / [Li2022] eq. 6); last with a default so
    # that every existing construction keeps Monaghan's switch
    alpha_all_pairs: int = 0
    # Riemann formulation of the continuity and momentum pair terms ([Zhang2017]; 0 = the central terms)
    # and the eta of its low-dissipation limiter
    riemann: int = 0
    riemann_eta: float = 3.0
    # pressure by the EDAC equation ([Ramachandran2019]; 0 = the equation of state of the density) and its
    # damping viscosity nu_edac = alpha h c0 / 8 [m^2/s]
    edac: int = 0
    edac_nu: float = 0.0
