"""Descriptions of viscosity and density-diffusion models for the fluid.

These objects only hold parameters (validated, with literature defaults);
they compile down to fields of :class:`seawall.fluid.params.Physics`.
"""

from ..errors import require_nonnegative, require_positive
from .params import DIFFUSION_MOLTENI, DIFFUSION_RENORMALISED


class ArtificialViscosity:
    """Monaghan (1992) artificial viscosity, seed 000 eq. 6.

    Parameters
    ----------
    alpha : float
        Linear coefficient; 0.01-0.1 for free-surface flows (seed 003 uses
        0.01, seed 001 uses 0.02 after Marrone et al. 2011).
    beta : float
        Quadratic coefficient, 0 after Monaghan (seed 000).
    """

    def __init__(self, *, alpha=0.02, beta=0.0):
        self.alpha = require_nonnegative("alpha", alpha)
        self.beta = require_nonnegative("beta", beta)

    def __repr__(self):
        return f"ArtificialViscosity(alpha={self.alpha}, beta={self.beta})"


class LaminarViscosity:
    """Laminar viscous term of Morris et al. (1997) as written in seed 003, eq. 9.

    Parameters
    ----------
    nu : float
        Kinematic viscosity [m^2/s] (1e-6 for water at 20 C).
    """

    def __init__(self, *, nu=1e-6):
        self.nu = require_positive("nu", nu)

    def __repr__(self):
        return f"LaminarViscosity(nu={self.nu})"


class MolteniColagrossi:
    """Density diffusion of Molteni & Colagrossi (2009): psi_ij = 2 (rho_j - rho_i) r_ji / r^2.

    Parameters
    ----------
    delta : float
        Diffusion coefficient, 0.1 in the literature (seed 003, sec. 2).
    """

    kind = DIFFUSION_MOLTENI

    def __init__(self, *, delta=0.1):
        self.delta = require_nonnegative("delta", delta)

    def __repr__(self):
        return f"MolteniColagrossi(delta={self.delta})"


class DeltaSPH(MolteniColagrossi):
    """delta-SPH density diffusion with the renormalised density gradient.

    Antuono et al. (2010), Marrone et al. (2011); seed 003 eq. 12-15 and
    seed 001 sec. 2.1. The gradient correction makes the term vanish in a
    linear (hydrostatic) density field, so it does not disturb still water.

    Parameters
    ----------
    delta : float
        Diffusion coefficient, 0.1 (Antuono et al. 2010).
    lagged_gradient : bool
        True (default): <grad rho>^L is accumulated in the rates pass and used
        at the next evaluation (one step old), which saves one of the two
        neighbour passes (-34 % time per step). False: it is computed in a
        separate pass before the rates, as written. Measured difference:
        hydrostatic wall pressure means within 0.006 % points, collapse front
        within 2e-4 (docs/performance.md).
    """

    kind = DIFFUSION_RENORMALISED

    def __init__(self, *, delta=0.1, lagged_gradient=True):
        super().__init__(delta=delta)
        self.lagged_gradient = bool(lagged_gradient)

    def __repr__(self):
        return f"DeltaSPH(delta={self.delta}, lagged_gradient={self.lagged_gradient})"
