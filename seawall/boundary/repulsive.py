"""Repulsive-particle walls: Monaghan & Kajtar (2009), as [TrixiBoundary] writes it.

The wall is one row of particles on the wall surface, spaced d = dx / beta.
Each pushes a fluid particle a within reach along r_ab = r_a - r_b with the
acceleration ([TrixiBoundary], "Repulsive Particles"; Monaghan & Kajtar 2009 eq. 3.1)

    f~_ab = K / beta^(n-1) * r_ab / (|r_ab| (|r_ab| - d)) * Phi(|r_ab|, h) * 2 m_b / (m_a + m_b)

with n the dimension and Phi(r, h) = w(r/h) the 1D Wendland C4 function
normalised to 1.77 at q = 0:

    w(q) = (1.77/32) (1 + 5/2 q + 2 q^2) (2 - q)^5   for 0 <= q < 2, else 0.

The factor 1/(|r| - d) makes the push grow without bound as a fluid particle
approaches a wall particle to within d, so the fluid cannot reach the wall
row. Where |r| <= d (a particle that a large time step carried past that
barrier) the formula would change sign and pull; there the distance is
floored at 1.01 d so the push stays repulsive and finite. The wall particles
carry no density or pressure; the fluid does not count them in its continuity
equation (the seed gives only the force). Optionally the artificial viscosity
of the pair, -m_b Pi_ab grad_a W_ab with rho_b = rho_a, is added (no slip in
the seed's sense; free slip without it).

K scales the force; Monaghan & Kajtar use g D for a tank of depth D, which is
the default here (D = the fluid's initial vertical extent).

``mass_factor``: ``"pair"`` (default) keeps the factor 2 m_b / (m_a + m_b) of the
formula above ([TrixiBoundary]; [MonaghanKajtar2009] eq. 3.1); ``"none"``
drops it, as TrixiParticles' code does. The two agree when
K_none = K_pair 2 m_b / (m_a + m_b); with seawall's masses (m_a = rho0 dx^n,
m_b = rho0 (dx / beta)^n) that is K_none = 2 K_pair / (1 + beta^n)
(docs/boundaries.md, "Monaghan-Kajtar: the mass factor and K").
"""

from typing import NamedTuple

import numpy as np
from numba import prange

from ..errors import ParameterError, require_nonnegative, require_positive
from ..jit import loop_helper, particle_loop
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..pairs import gradient_factor, monaghan_viscosity, pressure_acceleration, viscosity_acts
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel

#: "pair": 2 m_b / (m_a + m_b) in the force ([TrixiBoundary]); "none": without it (TrixiParticles' code)
MASS_FACTORS = ("pair", "none")

@loop_helper
def wendland_c4_1d(q):
    """Phi of Monaghan & Kajtar: (1.77/32)(1 + 2.5 q + 2 q^2)(2 - q)^5 for q < 2 (1.77 at q = 0)."""
    if q >= 2.0:
        return 0.0
    t = 2.0 - q
    return 1.77 / 32.0 * (1.0 + 2.5 * q + 2.0 * q * q) * t * t * t * t * t


@loop_helper
def repulsive_acceleration_factor(r, h, d, K, beta, dim, m_a, m_b, pair_mass=True):
    """The scalar s with f~_ab = s r_ab ([TrixiBoundary]); the distance in (|r| - d) floored at 1.01 d.

    ``pair_mass``: multiply by 2 m_b / (m_a + m_b) ([TrixiBoundary], [MonaghanKajtar2009] eq. 3.1);
    False drops the factor (TrixiParticles' code).
    """
    rr = r if r > 1.01 * d else 1.01 * d
    s = K / beta ** (dim - 1) / (r * (rr - d)) * wendland_c4_1d(r / h)
    if pair_mass:
        s *= 2.0 * m_b / (m_a + m_b)
    return s


class RepulsiveParams(NamedTuple):
    """The compiled parameters of a Monaghan-Kajtar wall."""

    K: float            # force scale [m^2/s^2]
    beta: float         # fluid spacing / wall spacing
    spacing: float      # wall spacing d = dx / beta
    alpha_wall: float   # artificial viscosity of the fluid-wall pair (0 = free slip)
    pair_mass: int      # 1: factor 2 m_b / (m_a + m_b) (default), 0: without it (TrixiParticles' code)


@particle_loop()
def repulsive_wall_forces(fluid, wall, cells, prm, rep, terms, dv):
    """Add the Monaghan-Kajtar wall acceleration (and optional viscosity) to the fluid's dv.

    The viscosity is the pair's Monaghan term with rho_b = rho_a and c_ab = c_a
    (:func:`seawall.pairs.monaghan_viscosity`, [Li2022] eq. 6), alpha = ``rep.alpha_wall``.
    """
    layout = cells.layout
    xf = fluid.x
    vf = fluid.v
    rhof = fluid.rho
    cf = fluid.c
    mf = fluid.m
    xw = wall.x
    vw = wall.v
    mw = wall.m
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    K = rep.K
    beta = rep.beta
    spacing = rep.spacing
    alpha_wall = rep.alpha_wall
    pair_mass = rep.pair_mass != 0
    h = prm.h
    inv_h = 1.0 / h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(xf.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        vi0, vi1, vi2 = point_of(vf, i, dim)
        a0 = a1 = a2 = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xw, b, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    s = repulsive_acceleration_factor(r, h, spacing, K, beta, dim, mf[i], mw[b], pair_mass)
                    if alpha_wall > 0.0:
                        vb0, vb1, vb2 = point_of(vw, b, dim)
                        vr = (vi0 - vb0) * d0 + (vi1 - vb1) * d1 + (vi2 - vb2) * d2
                        if viscosity_acts(vr, terms.all_pairs):
                            mu = h * vr / (r2 + prm.eta2)
                            pi_ab = monaghan_viscosity(alpha_wall, 0.0, mu, cf[i], rhof[i])
                            s += pressure_acceleration(mw[b], pi_ab, gradient_factor(prm.kernel, gradient_scale,
                                                                                     r * inv_h))
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2


class MonaghanKajtar(WallModel):
    """Repulsive wall particles of Monaghan & Kajtar (2009), [TrixiBoundary].

    Parameters
    ----------
    K : float, optional
        Force scale [m^2/s^2]; default g D with D the fluid's initial depth
        (Monaghan & Kajtar's choice for tanks).
    beta : float
        Fluid spacing / wall spacing, 3 by default (Monaghan & Kajtar, sec. 4).
    alpha_wall : float
        Artificial viscosity of the fluid-wall pair (0 = free slip).
    mass_factor : {"pair", "none"}
        ``pair`` (default): the force carries 2 m_b / (m_a + m_b) ([TrixiBoundary]);
        ``none``: without it, as TrixiParticles' code (see the module doc for K).

    The wall must be a single row of particles on the surface at spacing
    dx / beta: :func:`seawall.shapes.tank_surface` (the tank cases build it
    when this model is chosen).
    """

    #: pairwise_momentum (see WallModel): one central repulsive force per wall particle
    #: (Monaghan & Kajtar 2009 eq. 3.1).
    pairwise_momentum = True

    name = "monaghan-kajtar"
    #: the cases build a single surface row at dx / beta for this model
    layout = "surface"
    #: the row's masses rho0 d^n count in a summation-density fluid (as they always did)
    joins_summation_density = True

    @property
    def fluid_terms(self):
        """Only the pair's artificial viscosity (with alpha_wall), when alpha_wall > 0."""
        return frozenset({"artificial_viscosity"}) if self.alpha_wall > 0.0 else frozenset()

    def __init__(self, *, K=None, beta=3.0, alpha_wall=0.0, mass_factor="pair"):
        self.K = None if K is None else require_positive("K", K)
        self.beta = require_positive("beta", beta)
        self.alpha_wall = require_nonnegative("alpha_wall", alpha_wall)
        if mass_factor not in MASS_FACTORS:
            raise ParameterError(f"mass_factor must be one of {', '.join(MASS_FACTORS)}; got {mass_factor!r}")
        self.mass_factor = mass_factor
        self._K = 0.0

    def check(self, fluid, physics):
        """Without gravity K has no default (g D)."""
        if self.K is None and physics.gx == 0.0 and physics.gy == 0.0 and physics.gz == 0.0:
            raise ParameterError("monaghan-kajtar: without gravity give K explicitly (--set K=...)")

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        expected = fluid.spacing / self.beta
        if abs(wall.spacing - expected) > 1e-6 * expected:
            raise ParameterError(
                f"monaghan-kajtar needs wall particles spaced dx / beta = {expected:g} m, got {wall.spacing:g} m "
                f"(build the wall with seawall.shapes.tank_surface)")
        pa["m"] = np.full(wall.n, physics.rho0 * wall.spacing ** wall.dim)
        if self.K is not None:
            self._K = self.K
        else:
            g = float(np.sqrt(physics.gx ** 2 + physics.gy ** 2 + physics.gz ** 2))
            x = fluid.particles["x"]
            depth = float(x[:, -1].max() - x[:, -1].min()) + fluid.spacing
            self._K = g * depth
            if self._K <= 0.0:
                raise ParameterError("monaghan-kajtar: without gravity give K explicitly (--set K=...)")

    def update(self, wall, fluid, ctx):
        """Repulsive particles carry no state to update."""

    def interact(self, fluid, wall, ctx, dv, drho):
        rep = RepulsiveParams(self._K, self.beta, wall.spacing, self.alpha_wall, int(self.mass_factor == "pair"))
        repulsive_wall_forces(fluid_view(fluid.particles), wall_view(wall.particles),
                              cell_view(ctx.grid, wall.cells, reach=True), ctx.physics, rep,
                              self.cross_terms(ctx.physics), dv)

    def describe(self):
        return self.name if self.mass_factor == "pair" else f"{self.name} (mass_factor {self.mass_factor})"
