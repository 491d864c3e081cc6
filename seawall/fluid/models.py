"""Descriptions of viscosity and density-diffusion models for the fluid.

These objects only hold parameters (validated, with literature defaults);
they compile down to fields of :class:`seawall.fluid.params.Physics`.
"""

from ..errors import ParameterError, require_nonnegative, require_positive
from .params import DIFFUSION_MOLTENI, DIFFUSION_RENORMALISED


class ArtificialViscosity:
    """Monaghan (1992) artificial viscosity, [Li2022] eq. 6, or its all-pairs form of [Huang2019] eq. 5.

    Pi_ij = (-alpha c_ij mu_ij + beta mu_ij^2) / rho_ij,  mu_ij = h v_ij . r_ij / (r_ij^2 + eta^2),
    applied to approaching pairs (v_ij . r_ij < 0) only: Monaghan's switch, [Li2022] eq. 6.
    With ``all_pairs`` it acts on every pair, as the delta-SPH scheme of Marrone
    et al. (2011) writes it ([Huang2019] eq. 5: alpha h c0 rho0 sum pi_ij . grad W V_j
    with pi_ij = v_ji . r_ji / |r_ji|^2 for all neighbours). Only then is it a
    shear viscosity nu = alpha h c0 / (2 (d + 2)) (alpha h c0 / 8 in 2D; derivation
    in docs/formulas.md); with the switch it gives about half that shear stress.

    Parameters
    ----------
    alpha : float
        Linear coefficient; 0.01-0.1 for free-surface flows ([Liu2015] uses
        0.01, [Huang2019] uses 0.02 after Marrone et al. 2011).
    beta : float
        Quadratic coefficient, 0 after Monaghan ([Li2022]).
    all_pairs : bool
        Apply the term to every pair ([Huang2019] eq. 5) instead of approaching
        pairs only (default False, Monaghan's switch). Needs beta = 0: the
        quadratic term is a shock term for approaching pairs and would push
        receding pairs apart.
    """

    def __init__(self, *, alpha=0.02, beta=0.0, all_pairs=False):
        self.alpha = require_nonnegative("alpha", alpha)
        self.beta = require_nonnegative("beta", beta)
        if not isinstance(all_pairs, (bool, int)) or isinstance(all_pairs, int) and all_pairs not in (0, 1):
            raise ParameterError(f"all_pairs must be True or False, got {all_pairs!r}")
        self.all_pairs = bool(all_pairs)
        if self.all_pairs and self.beta > 0.0:
            raise ParameterError(f"beta must be 0 with all_pairs=True (the quadratic term is for approaching "
                                 f"pairs only), got {beta!r}")

    def __repr__(self):
        extra = ", all_pairs=True" if self.all_pairs else ""
        return f"ArtificialViscosity(alpha={self.alpha}, beta={self.beta}{extra})"


class LaminarViscosity:
    """Laminar viscous term of Morris et al. (1997) as written in [Liu2015], eq. 9.

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
        Diffusion coefficient, 0.1 in the literature ([Liu2015], sec. 2).
    """

    kind = DIFFUSION_MOLTENI

    def __init__(self, *, delta=0.1):
        self.delta = require_nonnegative("delta", delta)

    def __repr__(self):
        return f"MolteniColagrossi(delta={self.delta})"


class DeltaSPH(MolteniColagrossi):
    """delta-SPH density diffusion with the renormalised density gradient.

    Antuono et al. (2010), Marrone et al. (2011); [Liu2015] eq. 12-15 and
    [Huang2019] sec. 2.1. The gradient correction makes the term vanish in a
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


class RiemannSolver:
    """Riemann formulation of the fluid's continuity and momentum pair terms ([Zhang2017] sec. 3).

    Each pair i-j is a one-dimensional Riemann problem along the line of
    centres, solved by the linearised (acoustic) solver: interface velocity
    U* and pressure P* replace the central averages,

        drho_i/dt = 2 rho_i sum_j V_j (v_i - v*) . grad_i W_ij,
        dv_i/dt   = -sum_j 2 m_j P* / (rho_i rho_j) grad_i W_ij,

    with P* dissipative only for approaching pairs through the low-dissipation
    limiter beta = min(eta max(U_L - U_R, 0) / c0, 1) (functions
    :func:`seawall.pairs.riemann_pressure`, :func:`seawall.pairs.riemann_continuity`).
    It replaces artificial viscosity and density diffusion; the fluid refuses
    both together with it. Dummy-particle walls (``seawall.boundary.dummy``)
    apply the same pair terms with the wall particle's pressure, density and
    own velocity as the right state, and the mirrored normal velocity jump
    -2 (v_i - v_b) . n_b in the limiter (free slip is not dissipated). Every
    other wall model keeps its central wall terms with a Riemann fluid
    (not measured; the dam-break study, docs/validation-notes.md, used Adami walls).

    Parameters
    ----------
    eta : float
        Limiter coefficient, 3 in [Zhang2017]; larger = more dissipation.
    """

    def __init__(self, *, eta=3.0):
        self.eta = require_positive("eta", eta)

    def __repr__(self):
        return f"RiemannSolver(eta={self.eta})"
