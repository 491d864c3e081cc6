"""The fluid's pair terms, written once: small compiled functions inlined into every loop.

The fluid loop (:mod:`seawall.fluid.rates`) and every wall model's loop
(:mod:`seawall.boundary`) call these instead of re-typing the formulas; a wall
model says which of them act across its wall (``WallModel.fluid_terms``).
Each is a :func:`~seawall.jit.loop_helper`: compiled once and inlined into the
loops by LLVM, so a call costs nothing over the hand-written expression (the loops
give the same results bit for bit, docs/architecture.md). The few that branch on a
compile-time switch (the kernel, ``viscosity_acts``, ``density_diffusion``) are
``inline="always"`` instead, so that Numba folds the switch before optimising.

Conventions: i is the particle whose rates are summed, j its neighbour (a
fluid or wall particle), r_ij = r_i - r_j, v_ij = v_i - v_j, and the kernel
gradient is grad_i W_ij = F r_ij with F the *gradient factor* below.
The arithmetic order of each expression is the one the loops had before
(floating-point results are kept bit for bit); do not "simplify" it.
"""

from numba import njit

from .jit import loop_helper
from .kernels import kernel_gradient_factor, kernel_shape

# names of the fluid's pair terms; WallModel.fluid_terms is a set of these
CONTINUITY = "continuity"
PRESSURE = "pressure"
TENSILE = "tensile"
ARTIFICIAL_VISCOSITY = "artificial_viscosity"
LAMINAR_VISCOSITY = "laminar_viscosity"
DENSITY_DIFFUSION = "density_diffusion"
XSPH = "xsph"
#: the wall's particles count in the concentration gradient and the free-surface matrix of particle
#: shifting (seawall.fluid.regularisation; volumes m_b / rho0)
SHIFTING = "shifting"
#: the wall's particles count in the background-pressure sum and the extra stress of the transport
#: velocity ([Adami2013]; seawall.fluid.regularisation)
TRANSPORT_VELOCITY = "transport_velocity"
#: every fluid pair term, in the order the fluid loop applies them (the last two: the regularisation
#: passes after the fluid loop and the walls' terms)
FLUID_TERMS = (CONTINUITY, PRESSURE, TENSILE, ARTIFICIAL_VISCOSITY, LAMINAR_VISCOSITY, DENSITY_DIFFUSION, XSPH,
               SHIFTING, TRANSPORT_VELOCITY)


# ---------------------------------------------------------------- kernel helpers
@njit(cache=True, inline="always")
def gradient_factor(kind, gradient_scale, q):
    """F with grad_i W_ij = F r_ij; ``gradient_scale`` = sigma / h^2, q = |r_ij| / h ([Li2022] eq. 3)."""
    return gradient_scale * kernel_gradient_factor(kind, q)


@njit(cache=True, inline="always")
def kernel_value(kind, sigma, q):
    """W_ij = sigma w(q) ([Li2022] eq. 2-3)."""
    return sigma * kernel_shape(kind, q)


# ---------------------------------------------------------------- continuity
@loop_helper
def continuity(m_j, vr, f):
    """m_j v_ij . grad_i W_ij, with vr = v_ij . r_ij and f the gradient factor ([Li2022] eq. 8)."""
    return m_j * vr * f


# ---------------------------------------------------------------- momentum
@loop_helper
def tensile_coefficient(p, rho):
    """R = eps p / rho^2, eps = 0.01 for p > 0 and -0.2 otherwise ([Li2022] eq. 20; Monaghan 2000)."""
    return (0.01 if p > 0.0 else -0.2) * p / (rho * rho)


@loop_helper
def tensile_term(r_i, r_j, w_ratio):
    """(R_i + R_j) (W_ij / W(dx))^4, added to p_i/rho_i^2 + p_j/rho_j^2 ([Li2022] eq. 20)."""
    w2 = w_ratio * w_ratio
    return (r_i + r_j) * w2 * w2


@njit(cache=True, inline="always")
def viscosity_acts(vr, all_pairs):
    """Whether the artificial viscosity acts on a pair: approaching pairs (v_ij . r_ij < 0, [Li2022]
    eq. 6), or every pair when ``all_pairs`` is set."""
    return all_pairs != 0 or vr < 0.0


@loop_helper
def monaghan_viscosity(alpha, beta, mu, c_ab, rho_ab):
    """Pi_ij = (-alpha c_ij mu_ij + beta mu_ij^2) / rho_ij, mu_ij = h v_ij . r_ij / (r_ij^2 + eta^2)
    (Monaghan 1992; [Li2022] eq. 6). The caller checks :func:`viscosity_acts`."""
    return (-alpha * c_ab * mu + beta * mu * mu) / rho_ab


@loop_helper
def pressure_acceleration(m_j, coef, f):
    """s with dv_i += s r_ij for -m_j (p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij) grad_i W_ij ([Li2022] eq. 5);
    ``coef`` is the bracket."""
    return -m_j * coef * f


@loop_helper
def laminar_viscosity(m_j, nu, rho_i, rho_j, f, r2, eta2):
    """lam with dv_i += lam v_ij: the Morris et al. (1997) term as written in [Liu2015] eq. 9,

        m_j (mu_i + mu_j) / (rho_i rho_j) v_ij (r_ij . grad_i W_ij) / (r_ij^2 + eta^2),  mu = rho nu.
    """
    return m_j * nu * (rho_i + rho_j) / (rho_i * rho_j) * f * r2 / (r2 + eta2)


# ---------------------------------------------------------------- Riemann formulation
@loop_helper
def riemann_pressure(p_i, p_j, du, rho0c0, c0, eta):
    """Interface pressure P* of the linearised Riemann problem between i (left) and j (right) with the
    low-dissipation limiter ([Zhang2017] sec. 3.1-3.2):

        P* = (p_i + p_j)/2 + beta rho0 c0 du/2,   beta = min(eta max(du, 0) / c0, 1),

    du = U_L - U_R the jump of the velocity component along the line from i to j, positive when
    they approach (the only case that gets dissipation); eta = 3 in [Zhang2017]. Between fluid
    particles du = -v_ij . r_ij / |r_ij| (:func:`riemann_fluid_jump`); against a wall the right
    state mirrors i's normal velocity (:func:`riemann_wall_jump`). The impedance is the reference
    one, rho0 c0 (weakly compressible: rho c differs from it by O(Mach))."""
    beta = min(eta * max(du, 0.0) / c0, 1.0)
    return 0.5 * (p_i + p_j) + 0.5 * beta * rho0c0 * du


@loop_helper
def riemann_fluid_jump(vr, r):
    """U_L - U_R = (v_i - v_j) . e, e = r_ji / r the direction from i to j: -v_ij . r_ij / r ([Zhang2017] sec. 3.1)."""
    return -vr / r


@loop_helper
def riemann_wall_jump(vn):
    """U_L - U_R against a wall particle with the mirrored right state of [Zhang2017] (wall section):
    U_R = -U_L + 2 u_w along the wall normal, so U_L - U_R = -2 (v_i - v_w) . n, ``vn`` = (v_i - v_w) . n
    with n the wall's unit normal into the fluid. Only the normal velocity enters: sliding along a
    free-slip wall is not dissipated."""
    return -2.0 * vn


@loop_helper
def riemann_momentum_coefficient(p_star, rho_i, rho_j):
    """The bracket of :func:`pressure_acceleration` for the Riemann momentum equation
    dv_i/dt = -sum_j 2 m_j P* / (rho_i rho_j) grad_i W_ij ([Zhang2017] sec. 3.1)."""
    return 2.0 * p_star / (rho_i * rho_j)


@loop_helper
def riemann_continuity(rho_i, vol_j, vr, p_i, p_j, r, rho0c0, f):
    """drho_i/dt term 2 rho_i V_j (v_i - v*) . grad_i W_ij of [Zhang2017] sec. 3.1, with the
    interface velocity v* = (v_i + v_j)/2 + (U* - (U_L + U_R)/2) e of the linearised Riemann
    problem, U* - (U_L + U_R)/2 = (p_i - p_j) / (2 rho0 c0) (no limiter on U*, [Zhang2017] sec. 3.2).
    With grad_i W = f r_ij and e . r_ij = -r this is

        rho_i V_j f (v_ij . r_ij + (p_i - p_j) r / (rho0 c0)):

    the central continuity term plus a pressure (density) diffusion. ``vr`` = v_ij . r_ij."""
    return rho_i * vol_j * f * (vr + (p_i - p_j) * r / rho0c0)


# ---------------------------------------------------------------- density diffusion
@njit(cache=True, inline="always")
def density_diffusion(coef, vol_j, rho_i, rho_j, f, renormalised, g_dot_r):
    """delta h c0 V_j psi_ij . grad_i W_ij, ``coef`` = delta h c0 ([Liu2015] eq. 12), with
    psi_ij = 2 (rho_j - rho_i) r_ji / |r_ji|^2 (Molteni & Colagrossi 2009) and, when
    ``renormalised``, minus (<grad rho>_i^L + <grad rho>_j^L) ([Liu2015] eq. 13); ``g_dot_r`` is
    (<grad rho>_i^L + <grad rho>_j^L) . r_ij."""
    psi_dot = -2.0 * (rho_j - rho_i) * f
    if renormalised:
        psi_dot -= g_dot_r * f
    return coef * vol_j * psi_dot


# ---------------------------------------------------------------- XSPH
@loop_helper
def xsph_weight(w, m_j, rho_i, rho_j):
    """m_j W_ij / rho_ij with rho_ij = (rho_i + rho_j)/2; dx_i/dt gets eps * weight * (v_j - v_i)
    ([Li2022] eq. 10, Monaghan 1989)."""
    return w * m_j / (0.5 * (rho_i + rho_j))


# ---------------------------------------------------------------- EDAC pressure equation
@loop_helper
def edac_divergence(c2, rho_i, vol_j, vr, f):
    """The compressibility term of the EDAC pressure equation, -rho_i c^2 (div v)_i, for one pair
    ([Ramachandran2019] sec. 3, the pressure equation; the divergence in the difference form
    (div v)_i = -sum_j V_j v_ij . grad_i W_ij):

        dp_i/dt += c^2 rho_i V_j v_ij . grad_i W_ij,   ``vr`` = v_ij . r_ij, grad_i W = f r_ij, c2 = c0^2.

    It is c0^2 rho_i / rho_j times the continuity term (:func:`continuity`); it vanishes for a uniform flow."""
    return c2 * rho_i * vol_j * vr * f


@loop_helper
def edac_diffusion(vol_i, vol_j, inv_m_i, rho_i, rho_j, nu, p_i, p_j, f, r2, eta2):
    """The damping term nu_edac lap(p) of the EDAC pressure equation for one pair ([Ramachandran2019]
    sec. 3; the Laplacian in the form of [Morris1997] / [Adami2013] that the paper uses for its viscous
    term, with eta = rho nu_edac):

        dp_i/dt += (1/m_i) (V_i^2 + V_j^2) eta_ij (p_i - p_j) (r_ij . grad_i W_ij) / (r_ij^2 + eta^2),
        eta_ij = 2 eta_i eta_j / (eta_i + eta_j).

    Antisymmetric in i, j once multiplied by m_i, so sum_i m_i p_i is conserved by it; with a uniform
    density it is 2 nu V_j (p_i - p_j) F r^2/(r^2 + eta^2), the [Morris1997] Laplacian."""
    eta_ij = 2.0 * nu * rho_i * rho_j / (rho_i + rho_j)
    return (vol_i * vol_i + vol_j * vol_j) * inv_m_i * eta_ij * (p_i - p_j) * f * r2 / (r2 + eta2)


@loop_helper
def edac_pressure_advection(vol_j, p_i, p_j, f, tr):
    """The transport-velocity term of the EDAC pressure equation for one pair: the pressure followed along
    the transport velocity v~ instead of v ([Ramachandran2019] sec. 3, the EDAC-TVF pressure equation,
    d~p/dt = dp/dt + (v~ - v) . grad p; [Adami2013] for v~), with grad p in the difference form
    (grad p)_i = sum_j V_j (p_j - p_i) grad_i W_ij, which vanishes for a uniform p:

        dp_i/dt += V_j (p_j - p_i) (v~_i - v_i) . grad_i W_ij,   ``tr`` = (v~_i - v_i) . r_ij, grad_i W = f r_ij.

    The same form as the density term of the transport velocity (seawall.fluid.regularisation)."""
    return vol_j * (p_j - p_i) * f * tr
