"""Dynamic boundaries: DBC (Crespo et al. 2007) and the improved DBC of Li, Zhang & Yuan ([Li2022]).

Wall particles of a dynamic boundary stay put (or move as prescribed) but
carry their own density, advanced by the continuity equation ([Li2022]
eq. 8) from the fluid around them; their pressure follows from an equation
of state, and they push on the fluid through the ordinary SPH momentum
equation ([Li2022] eq. 5, with the tensile correction of eq. 20 and an
artificial viscosity of its own, eq. 6 with ``alpha_wall``).

IDBC ([Li2022] sec. 3) changes three things, each switchable here:

(a) ``order`` -- the pressure used in the fluid-wall pair term is the Tait
    EOS expanded to ``order`` terms in lambda = (rho - rho0)/rho0
    ([Li2022] eq. 21-22)::

        P_N = c0^2 rho0 lambda sum_{k<N} a_k lambda^k,  a = (1, 3, 5, 5, 3, 1, 1/7)

    N = 1 is the linear EOS of plain DBC (eq. 12); N = 7 is the full Tait
    EOS with gamma = 7 (so the wall and the fluid follow the same EOS).
    Both pressures of the pair (fluid and wall particle) use P_N: with
    summation densities of two particles this is exactly eq. 23.
(b) ``rectangular`` -- a boundary particle's support is a rectangle 4h long
    along its wall normal n (|r_1| < 2h) and 2 dx wide along the wall
    (|s| <= dx for each tangential coordinate s); inside it the kernel
    depends on the normal distance only ([Li2022] eq. 26)::

        r_1 = r_ab . n,    (grad_a W_ab)_1 = n dW(|r_1|)/dr_1,

    used in the fluid's and the wall's continuity equations and in the force.
(c) ``correction`` -- with the rectangle, the kernel normalisation is
    multiplied by alpha_DB = 1 / (alpha_D I'), I' the integral of the kernel
    shape over the rectangle ([Li2022] eq. 27-28 and the appendix):
    7 pi h / (30 dx) in 2D and pi h^2 / (6 dx dy) in 3D for the cubic spline.

Choices where the seed is silent or ambiguous (see docs/idbc.md):

* The wall density is advanced inside ``update`` by the trapezoidal rule
  over the time since the previous call; its rate does not depend on the
  wall density itself, so the rule is explicit (second order). The default
  is the seed's rule (eq. 8 with the gradient of eq. 26); the option
  ``wall_density="consistent"`` integrates eq. 8 exactly across the
  rectangle's top-hat edges, which sets still water in motion (docs/idbc.md).
* A fluid particle exactly on the edge of a rectangle (|s| = dx, to 1e-9 dx)
  counts one half, so that a uniform row always weighs exactly two
  particles and an aligned particle sees no jump.
* Rectangles of tilted walls (tank corners) are clipped to the neighbour
  search, which covers at least 2h along every axis.
* XSPH (eq. 10) includes the wall particles (velocity v_b, kernel of the
  pair), since DBC treats them as neighbours like any other.
* The wall mass is the hydrodynamic mass rho0 dx_wall^d (as dummy.py).
* The tensile term uses the uncorrected kernel ratio w(q)/w(dx/h), with q
  the (projected) distance over h.
"""

from typing import NamedTuple

import numpy as np
from numba import njit, prange

from ..eos import eos_density, eos_sound_speed
from ..errors import ParameterError, require_nonnegative
from ..jit import loop_helper, particle_loop
from ..kernels import CUBIC_SPLINE, kernel_shape, kernel_shape_dq
from ..neighbors import cell_index, minimum_image, neighbour_range, point_of, tag_dim, tag_periodic
from ..pairs import (continuity, monaghan_viscosity, pressure_acceleration, tensile_coefficient, tensile_term,
                     viscosity_acts, xsph_weight)
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel, rates_bundle

#: coefficients a_k of the expanded Tait EOS, [Li2022] eq. 21: (1/7) C(7, k+1)
EXPANSION = np.array([1.0, 3.0, 5.0, 5.0, 3.0, 1.0, 1.0 / 7.0])
MAX_ORDER = 7
WALL_DENSITY_MODES = ("continuity", "consistent")
_EDGE_TOL = 1e-9


@loop_helper
def expanded_pressure(rho, rho0, c0, order, p_background):
    """Tait EOS (gamma = 7) expanded to ``order`` terms ([Li2022] eq. 21); order 1 is eq. 12."""
    lam = (rho - rho0) / rho0
    f = 0.0
    for k in range(order - 1, -1, -1):
        f = f * lam + EXPANSION[k]
    return c0 * c0 * rho0 * lam * f + p_background


@loop_helper
def _window(s, half):
    """Top-hat weight of the rectangle along one tangential axis (edge counts 1/2)."""
    a = abs(s)
    tol = _EDGE_TOL * half
    if a < half - tol:
        return 1.0
    if a <= half + tol:
        return 0.5
    return 0.0


@njit(cache=True, inline="always")
def wall_kernel(kind, rect, dim, d0, d1, d2, nb0, nb1, nb2, ta0, ta1, ta2, tb0, tb1, tb2, half_a, half_b,
                corr, sigma, inv_h, support, support2):
    """Kernel of a fluid particle a and a wall particle b, d = r_a - r_b.

    Returns (shape, W, G, e0, e1, e2, rr, r2): grad_a W = G e with e a unit
    vector; rr = r_ab . e-projected separation times |e| used in mu (v_ab .
    r_eff = (v_ab . e) rr), r2 = |r_eff|^2; shape = w(q) for the tensile term.
    Circular support (DBC): e = d / |d| ([Li2022] eq. 3, 5). Rectangular
    (IDBC): e = sign(r_1) n, r_1 = d . n, |r_1| < support, tangential window
    ([Li2022] eq. 26), kernel times ``corr`` = alpha_DB (eq. 28). shape < 0
    marks a pair outside the support.
    """
    if rect:
        r1 = d0 * nb0 + d1 * nb1 + d2 * nb2
        a1 = abs(r1)
        if a1 >= support:
            return -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        om = _window(d0 * ta0 + d1 * ta1 + d2 * ta2, half_a)
        if dim == 3 and om > 0.0:
            om *= _window(d0 * tb0 + d1 * tb1 + d2 * tb2, half_b)
        if om == 0.0:
            return -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        q = a1 * inv_h
        s = kernel_shape(kind, q)
        g = corr * om * sigma * inv_h * kernel_shape_dq(kind, q)
        sg = 1.0 if r1 >= 0.0 else -1.0
        return s, corr * om * sigma * s, g, sg * nb0, sg * nb1, sg * nb2, a1, r1 * r1
    r2 = d0 * d0 + d1 * d1 + d2 * d2
    if r2 >= support2 or r2 == 0.0:
        return -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    r = np.sqrt(r2)
    q = r * inv_h
    s = kernel_shape(kind, q)
    inv_r = 1.0 / r
    return s, sigma * s, sigma * inv_h * kernel_shape_dq(kind, q), d0 * inv_r, d1 * inv_r, d2 * inv_r, r, r2


@particle_loop()
def dbc_wall_rate(layout, xw, vw, nw_, t1w, t2w, xf, vf, xsph, mf, start, order, lo, inv_cell, ncell, period,
                  prm, rect, corr, half_a, half_b, drho_w, sum_w, drift_w):
    """Continuity rate of every wall particle ([Li2022] eq. 8, with eq. 26 when ``rect``).

    drho_w[b] = sum_f m_f (v_f - v_b) . grad_f W_fb  (= sum_f m_f (v_b - v_f) . grad_b W_bf, eq. 8)
    sum_w[b]  = sum_f m_f W_bf                       (eq. 7 over the fluid)
    drift_w[b] = -sum_f m_f xsph_f . grad_f W_fb     (what eq. 8 misses of d(sum_w)/dt when the
                 fluid moves with the XSPH velocity v + xsph, eq. 10)
    """
    n = xw.shape[0]
    inv_h = 1.0 / prm.h
    support = np.sqrt(prm.support2)
    for b in prange(n):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        n0, n1, n2 = point_of(nw_, b, dim)
        a0, a1, a2 = point_of(t1w, b, dim)
        c0_, c1_, c2_ = point_of(t2w, b, dim)
        vb0, vb1, vb2 = point_of(vw, b, dim)
        acc = 0.0
        sw = 0.0
        dr = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    f = order[k]
                    q0, q1, q2 = point_of(xf, f, dim)
                    d0 = (minimum_image(q0 - p0, period[0]) if periodic else q0 - p0)
                    d1 = (minimum_image(q1 - p1, period[1]) if periodic else q1 - p1)
                    d2 = (minimum_image(q2 - p2, period[2]) if periodic else q2 - p2)
                    s, w, g, e0, e1, e2, rr, r2 = wall_kernel(prm.kernel, rect, dim, d0, d1, d2, n0, n1, n2,
                                                              a0, a1, a2, c0_, c1_, c2_, half_a, half_b,
                                                              corr, prm.sigma, inv_h, support, prm.support2)
                    if s < 0.0:
                        continue
                    u0, u1, u2 = point_of(vf, f, dim)
                    mg = mf[f] * g
                    acc += mg * ((u0 - vb0) * e0 + (u1 - vb1) * e1 + (u2 - vb2) * e2)
                    sw += mf[f] * w
                    z0, z1, z2 = point_of(xsph, f, dim)
                    dr -= mg * (z0 * e0 + z1 * e1 + z2 * e2)
        drho_w[b] = acc
        sum_w[b] = sw
        drift_w[b] = dr


class DynamicParams(NamedTuple):
    """The compiled parameters of a dynamic boundary ([Li2022] sec. 3)."""

    eos_order: int      # terms of the expanded Tait EOS in the pair (eq. 21-23)
    rectangular: int    # rectangular support of eq. 26
    corr: float         # alpha_DB of eq. 28 (1 without the correction)
    half_a: float       # half widths of the rectangle along the two tangents
    half_b: float
    alpha_wall: float   # artificial viscosity alpha of fluid-wall pairs (eq. 6)


@particle_loop()
def dbc_fluid_forces(fluid, wall, tangent1, tangent2, cells, prm, dyn, terms, rates):
    """Add the wall's terms to the fluid's rates (pair terms of :mod:`seawall.pairs`).

    continuity: drho_a += m_b (v_a - v_b) . grad_a W_ab                       ([Li2022] eq. 8)
    momentum:   dv_a -= m_b (P_N(rho_a)/rho_a^2 + P_N(rho_b)/rho_b^2 + Pi_ab + f_ten) grad_a W_ab
                ([Li2022] eq. 5 with the expanded EOS of eq. 21; eq. 23 for two particles)
    Pi_ab = -alpha_wall c_ab mu_ab / rho_ab for v_ab . r_ab < 0                ([Li2022] eq. 6)
    f_ten = (R_a + R_b) (w(q)/w(dx/h))^4, R = eps P/rho^2                     ([Li2022] eq. 20)
    rates.mu_max[a] is raised to |mu_ab| for the time-step rule ([Li2022] eq. 11).
    XSPH:       rates.xsph_a += eps m_b / rho_ab (v_b - v_a) W_ab  ([Li2022] eq. 10: the wall particles
                are neighbours like any other in DBC)
    The tensile and XSPH terms act when the fluid has them and ``terms`` (CrossTerms) lets them across.
    """
    layout = cells.layout
    xf = fluid.x
    vf = fluid.v
    rhof = fluid.rho
    cf = fluid.c
    xw = wall.x
    vw = wall.v
    nw_ = wall.normal
    rhow = wall.rho
    mw = wall.m
    t1w = tangent1
    t2w = tangent2
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    eos_order = dyn.eos_order
    rect = dyn.rectangular
    corr = dyn.corr
    half_a = dyn.half_a
    half_b = dyn.half_b
    alpha_wall = dyn.alpha_wall
    dv = rates.dv
    drho = rates.drho
    mu_max = rates.mu_max
    xsph = rates.xsph
    n = xf.shape[0]
    h = prm.h
    inv_h = 1.0 / h
    support = np.sqrt(prm.support2)
    rho0 = prm.rho0
    c0 = prm.c0
    tensile = prm.tensile and terms.tensile
    w_dx = prm.inv_w_dx * prm.sigma  # 1 / w(dx/h)
    eps = prm.xsph
    use_xsph = eps > 0.0 and terms.xsph
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue   # no wall particle in the cells this particle searches (CellList.reach_mask)
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = rhof[i]
        pa = expanded_pressure(rhoi, rho0, c0, eos_order, prm.p_background)
        pr_a = pa / (rhoi * rhoi)
        ra = tensile_coefficient(pa, rhoi)
        a0 = a1 = a2 = 0.0
        dr = 0.0
        x0 = x1 = x2 = 0.0
        mumax = mu_max[i]
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    q0, q1, q2 = point_of(xw, b, dim)
                    d0 = (minimum_image(p0 - q0, period[0]) if periodic else p0 - q0)
                    d1 = (minimum_image(p1 - q1, period[1]) if periodic else p1 - q1)
                    d2 = (minimum_image(p2 - q2, period[2]) if periodic else p2 - q2)
                    n0, n1, n2 = point_of(nw_, b, dim)
                    ta0, ta1, ta2 = point_of(t1w, b, dim)
                    tb0, tb1, tb2 = point_of(t2w, b, dim)
                    s, w, g, e0, e1, e2, rr, r2 = wall_kernel(prm.kernel, rect, dim, d0, d1, d2, n0, n1, n2,
                                                              ta0, ta1, ta2, tb0, tb1, tb2, half_a, half_b,
                                                              corr, prm.sigma, inv_h, support, prm.support2)
                    if s < 0.0:
                        continue
                    mb = mw[b]
                    vb0, vb1, vb2 = point_of(vw, b, dim)
                    ve = (vi0 - vb0) * e0 + (vi1 - vb1) * e1 + (vi2 - vb2) * e2
                    # grad_a W = g e: the continuity term with the unit direction e and factor g
                    dr += continuity(mb, ve, g)
                    rhob = rhow[b]
                    pb = expanded_pressure(rhob, rho0, c0, eos_order, prm.p_background)
                    pr_b = pb / (rhob * rhob)
                    coef = pr_a + pr_b
                    if tensile:
                        coef += tensile_term(ra, tensile_coefficient(pb, rhob), s * w_dx)
                    mu = h * ve * rr / (r2 + prm.eta2)
                    if abs(mu) > mumax:
                        mumax = abs(mu)
                    if alpha_wall > 0.0 and viscosity_acts(ve, terms.all_pairs):
                        cb = eos_sound_speed(prm.eos, rhob, rho0, c0, prm.gamma)
                        coef += monaghan_viscosity(alpha_wall, 0.0, mu, 0.5 * (cf[i] + cb), 0.5 * (rhoi + rhob))
                    sc = pressure_acceleration(mb, coef, g)
                    a0 += sc * e0
                    a1 += sc * e1
                    a2 += sc * e2
                    if use_xsph:
                        wx = xsph_weight(w, mb, rhoi, rhob)
                        x0 -= wx * (vi0 - vb0)
                        x1 -= wx * (vi1 - vb1)
                        x2 -= wx * (vi2 - vb2)
        if use_xsph:
            xsph[i, 0] += eps * x0
            xsph[i, 1] += eps * x1
            if dim == 3:
                xsph[i, 2] += eps * x2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr
        mu_max[i] = mumax


@particle_loop()
def wall_pressures(rho, rho0, c0, order, p_background, p):
    for b in prange(rho.shape[0]):
        p[b] = expanded_pressure(rho[b], rho0, c0, order, p_background)


def alpha_db(h, dx, dy=None, kernel=CUBIC_SPLINE, dim=2):
    """Correction factor alpha_DB of the rectangular support ([Li2022] eq. 28, appendix e-k).

    alpha_DB = 1 / (alpha_D I'), I' = integral of W/alpha_D over the rectangle
    = (2 dx) [(2 dy)] 2 h int_0^Q w(q) dq. For the cubic spline int_0^2 w = 3/4,
    giving 7 pi h / (30 dx) in 2D and pi h^2 / (6 dx dy) in 3D.
    """
    from ..kernels import kernel_sigma

    dy = dx if dy is None else dy
    if kernel == CUBIC_SPLINE:
        line = 0.75
    else:
        qmax = 3.0 if kernel in (1, 4) else 2.0
        q = np.linspace(0.0, qmax, 20001)
        vals = np.array([kernel_shape(kernel, float(v)) for v in q])
        line = float(np.sum(0.5 * (vals[1:] + vals[:-1]) * np.diff(q)))
    area = 2.0 * dx if dim == 2 else 4.0 * dx * dy
    integral = area * 2.0 * h * line  # int over the rectangle of w(|r_1|/h)
    sigma = kernel_sigma(kernel, h, dim)
    return 1.0 / (sigma * integral)


def tangent_frames(normals):
    """Two unit tangent vectors per unit normal (2D: t1 = (-n_y, n_x), t2 = 0).

    In 3D t1 is the coordinate axis least aligned with n, made orthogonal to
    n (so for axis-aligned walls the rectangle's sides follow the lattice),
    and t2 = n x t1.
    """
    n = np.asarray(normals, dtype=np.float64)
    if n.shape[1] == 2:
        t1 = np.stack([-n[:, 1], n[:, 0]], axis=1)
        return np.ascontiguousarray(t1), np.zeros_like(n)
    k = np.argmin(np.abs(n), axis=1)
    e = np.zeros_like(n)
    e[np.arange(n.shape[0]), k] = 1.0
    t1 = e - np.sum(e * n, axis=1)[:, None] * n
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    t2 = np.cross(n, t1)
    return np.ascontiguousarray(t1), np.ascontiguousarray(t2)


class ImprovedDynamicBoundary(WallModel):
    """Dynamic boundary particles, DBC or IDBC ([Li2022] sec. 3), each improvement switchable.

    Parameters
    ----------
    order : int, 1..7
        Terms of the expanded Tait EOS in the fluid-wall pair ([Li2022] eq.
        21-23); 1 = plain DBC (eq. 12), 7 = full EOS. Default 7.
    rectangular : bool
        Rectangular support with the normal projection of eq. 26 (default True).
    correction : bool, optional
        Kernel correction alpha_DB of eq. 28 (needs ``rectangular``);
        default: same as ``rectangular``.
    alpha_wall : float
        Artificial viscosity alpha of fluid-wall pairs ([Li2022] eq. 6); default 0.
    initial_pressure : callable, optional
        Function of the (N, d) wall positions giving the initial wall
        pressure [Pa] (e.g. hydrostatic); the density follows from the full
        Tait EOS. Default: reference density.
    wall_density : {"continuity", "consistent"}, optional
        How the wall density is advanced: the continuity equation of [Li2022]
        (eq. 8 with the kernel gradient of eq. 26 for the rectangle; default)
        or ``consistent``, its exact time integral that keeps the jumps at the
        rectangle's edges (better for one particle bouncing in a box, but it
        sets still water in motion); see :meth:`update` and docs/idbc.md.
    """

    #: pairwise_momentum (see WallModel): wall particles enter the fluid's momentum equation
    #: as fluid particles do, one symmetric pair term each ([Li2022] eq. 5); central.
    pairwise_momentum = True

    name = "idbc"
    #: DBC treats wall particles as neighbours like any other ([Li2022] sec. 2): the tensile
    #: correction and XSPH of the fluid act across the wall; the artificial viscosity is the wall's
    #: own (alpha_wall); no laminar viscosity or density diffusion
    fluid_terms = frozenset({"continuity", "pressure", "tensile", "artificial_viscosity", "xsph", "shifting",
                             "transport_velocity"})
    #: the wall's masses count in a summation-density fluid
    joins_summation_density = True

    @property
    def integrated_arrays(self):
        """The wall density (``continuity``) or the integral of the XSPH drift (``consistent``)."""
        return ("rho",) if self.wall_density == "continuity" else ("drift_int",)

    def __init__(self, *, order=7, rectangular=True, correction=None, alpha_wall=0.0, initial_pressure=None,
                 wall_density=None):
        try:
            order_i = int(str(order).strip()) if not isinstance(order, (int, np.integer)) else int(order)
        except (TypeError, ValueError):
            raise ParameterError(f"order must be an integer 1..7, got {order!r}") from None
        if isinstance(order, bool) or not 1 <= order_i <= MAX_ORDER:
            raise ParameterError(f"order must be an integer 1..7, got {order!r}")
        self.order = order_i
        self.rectangular = bool(rectangular)
        if correction is None:
            correction = self.rectangular
        if correction and not self.rectangular:
            raise ParameterError("correction=True (alpha_DB, [Li2022] eq. 28) needs rectangular=True")
        self.correction = bool(correction)
        self.alpha_wall = require_nonnegative("alpha_wall", alpha_wall)
        self.initial_pressure = initial_pressure
        if wall_density is None:
            wall_density = "continuity"  # [Li2022] sec. 3.2: eq. 8 with eq. 26 (docs/idbc.md, choice 3)
        if wall_density not in WALL_DENSITY_MODES:
            raise ParameterError(f"wall_density must be one of {', '.join(WALL_DENSITY_MODES)}; got {wall_density!r}")
        self.wall_density = wall_density
        self._t_last = None
        self._corr = 1.0
        self._half = (1.0, 1.0)

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        n = wall.n
        dim = wall.dim
        if "normal" not in pa:
            if self.rectangular:
                raise ParameterError(f"wall {wall.name!r} has no normals: the rectangular support needs them "
                                     "(use shapes.tank or shapes.polyline_wall)")
            pa["normal"] = np.zeros((n, dim))
        normals = pa["normal"]
        t1, t2 = tangent_frames(normals) if self.rectangular else (np.zeros((n, dim)), np.zeros((n, dim)))
        pa["tangent1"] = t1
        pa["tangent2"] = t2
        dx = wall.spacing
        self._half = (dx, dx)
        self._corr = alpha_db(physics.h, dx, dx, physics.kernel, dim) if self.correction else 1.0
        rho0 = physics.rho0
        if self.initial_pressure is not None:
            p0 = np.asarray(self.initial_pressure(pa["x"].copy()), dtype=np.float64).reshape(n)
            rho = np.array([eos_density(physics.eos, float(p) + physics.p_background, rho0, physics.c0,
                                        physics.gamma, physics.p_background) for p in p0])
        else:
            rho = np.full(n, rho0)
        pa["rho"] = rho
        pa["p"] = np.zeros(n)
        pa["drho"] = np.zeros(n)
        pa["drift"] = np.zeros(n)
        pa["m"] = np.full(n, rho0 * dx ** dim)
        self._t_last = None
        pa["drift_int"] = np.zeros(n)

    def update(self, wall, fluid, ctx):
        """Advance the wall density to ctx.time and set the wall pressure (order-N EOS).

        ``wall_density="continuity"``: trapezoidal rule on eq. 8 over the time
        since the previous call. ``"consistent"``: rho_b = rho_b(t0) +
        [sum_f m_f W_bf](t) - [sum_f m_f W_bf](t0) + integral of the XSPH
        drift -- eq. 8 integrated exactly, including the jumps of the
        rectangular support's top-hat edges, which the pointwise gradient of
        eq. 26 cannot see (docs/idbc.md).
        """
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        n = wall.n
        rate = np.empty(n)
        total = np.empty(n)
        drift = np.empty(n)
        if ctx.rates is not None:
            xsph = ctx.rates.xsph  # the fluid's XSPH correction of the previous evaluation
        else:
            xsph = fp["xsph"] if "xsph" in fp else np.zeros_like(fp["v"])
        dbc_wall_rate(g.layout, pa["x"], pa["v"], pa["normal"], pa["tangent1"], pa["tangent2"], fp["x"], fp["v"],
                      xsph, fp["m"], ctx.fluid_cells.start, ctx.fluid_cells.order, g.lo, g.inv_cell, g.ncell,
                      g.period, ctx.physics, self.rectangular, self._corr, self._half[0], self._half[1], rate,
                      total, drift)
        t = float(ctx.time)
        first = self._t_last is None or t < self._t_last
        if first:
            if "drift_int" not in pa:
                pa["drift_int"] = np.zeros(n)
            pa["rho_base"] = pa["rho"] - total - pa["drift_int"]
        elif t > self._t_last:
            step = t - self._t_last
            if self.wall_density == "continuity":
                pa["rho"] += step * 0.5 * (pa["drho"] + rate)
            else:
                pa["drift_int"] += step * 0.5 * (pa["drift"] + drift)
        if self.wall_density == "consistent":
            pa["rho"] = pa["rho_base"] + total + pa["drift_int"]
        self._t_last = t
        pa["drho"] = rate
        pa["drift"] = drift
        prm = ctx.physics
        wall_pressures(pa["rho"], prm.rho0, prm.c0, self.order, prm.p_background, pa["p"])

    def state(self):
        """Time of the last update (the wall density is advanced from it); kept in checkpoints."""
        return {"t_last": self._t_last}

    def set_state(self, state):
        self._t_last = state.get("t_last")

    def interact(self, fluid, wall, ctx, dv, drho):
        pa = wall.particles
        dyn = DynamicParams(self.order, int(self.rectangular), self._corr, self._half[0], self._half[1],
                            self.alpha_wall)
        dbc_fluid_forces(fluid_view(fluid.particles), wall_view(pa), pa["tangent1"], pa["tangent2"],
                         cell_view(ctx.grid, wall.cells, reach=True), ctx.physics, dyn, self.cross_terms(ctx.physics),
                         rates_bundle(fluid, ctx, dv, drho))

    def describe(self):
        parts = [f"order {self.order}", "rectangular" if self.rectangular else "circular"]
        if self.correction:
            parts.append("alpha_DB")
        if self.wall_density != "continuity":
            parts.append(f"wall density {self.wall_density}")
        if self.alpha_wall > 0:
            parts.append(f"alpha_wall {self.alpha_wall:g}")
        return f"{self.name} ({', '.join(parts)})"


class DynamicBoundary(ImprovedDynamicBoundary):
    """Plain DBC (Crespo, Gomez-Gesteira & Dalrymple 2007) as [Li2022] sec. 2-3 describes it.

    Circular support, linear EOS in the wall pair ([Li2022] eq. 12), no
    alpha_DB: ``ImprovedDynamicBoundary(order=1, rectangular=False)``.
    The switches stay available to build the intermediate variants of the
    seed's Fig. 4.
    """

    name = "dbc"

    def __init__(self, *, order=1, rectangular=False, correction=None, alpha_wall=0.0, initial_pressure=None,
                 wall_density=None):
        super().__init__(order=order, rectangular=rectangular, correction=correction, alpha_wall=alpha_wall,
                         initial_pressure=initial_pressure, wall_density=wall_density)


__all__ = ["DynamicBoundary", "ImprovedDynamicBoundary", "expanded_pressure", "alpha_db", "tangent_frames",
           "EXPANSION"]
