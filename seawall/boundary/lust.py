"""Local uniform stencil (LUST) walls of [Fourtakas2019] (Fourtakas, Dominguez, Vacondio & Rogers 2019).

The idea ([Fourtakas2019], as summarised in [Li2022] sec. 1 and 4.2): a fluid
particle whose kernel support is cut by a solid wall gets the missing part of
its support back from a *local uniform stencil* of fictitious particles of its
own. The stencil is a lattice at the particle spacing dx anchored on the fluid
particle,

    y_k = x_i + dx k,   k in Z^d,   0 < |dx k| < support,

and the nodes that lie inside the solid become virtual particles of particle i
(the nodes on the fluid side are discarded: fluid particles are there). They
act on i alone, through the fluid's own pair terms (:mod:`seawall.pairs`), so
near a wall i sees a complete, uniform neighbourhood: the kernel sum
sum_j V_j W_ij and the gradient sum sum_j V_j grad W_ij are those of the
interior (zeroth- and first-order consistency of the stencil; for a fluid
particle on the fluid's lattice the union of fluid and stencil is the full
lattice).

State of a virtual node k of fluid particle i (choices where the published
description we could read is not explicit are listed in docs/boundaries.md,
"LUST"):

* pressure, the wall's Neumann condition with the hydrostatic term, integrated
  from the fluid particle to the node (``pressure="hydrostatic"``, default)::

      p_k = p_i + rho_i (g - a_w) . (y_k - x_i)

  which continues a hydrostatic field exactly (the form of [Adami2012] eq. 27
  for one fluid particle); ``pressure="copy"`` gives p_k = p_i;
* density rho_k = EOS^-1(p_k); mass m_k = m_i (the node is a fluid particle
  continued into the wall: its volume is m_i / rho_k);
* velocity relative to the wall, u = v_i - v_w: free slip mirrors the normal
  component, v_k = v_w + u - 2 (u . n) n; no slip mirrors both,
  v_k = v_w - u. The continuity term always uses the free-slip mirror (the
  wall is impermeable; its tangential motion does not compress the fluid).

Which nodes are solid: seawall's walls are particles in layers behind the
surface, each with its closest surface point s_b and unit normal n_b into
the fluid (:mod:`seawall.shapes`). A node is solid when its nearest wall
particle b within one kernel support exists and (y_k - s_b) . n_b < 0, the
signed distance the wall guard uses (:func:`seawall.diagnostics.signed_wall_distance`).
The wall particles are only this geometry: they carry no state and never
act on the fluid themselves (apart from counting as solid volume in particle
shifting and the transport velocity).

Terms across the wall: continuity ([Li2022] eq. 8) and the symmetric
pressure term ([Li2022] eq. 5) with the fluid's artificial viscosity
(Monaghan 1992, [Li2022] eq. 6; ``alpha_wall`` overrides its alpha) and laminar
viscosity ([Liu2015] eq. 9); no density diffusion (the node densities carry
the hydrostatic jump), no tensile correction, no XSPH.
"""

import math

import numpy as np
from numba import njit, prange

from ..eos import eos_density, eos_sound_speed
from ..errors import ParameterError
from ..jit import particle_loop
from ..kernels import kernel_shape
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..pairs import continuity, gradient_factor, laminar_viscosity, monaghan_viscosity, pressure_acceleration, \
    viscosity_acts
from .base import WallModel, rates_bundle

SLIP_MODES = ("free", "noslip")
PRESSURE_MODES = ("hydrostatic", "copy")


def stencil_offsets(dim, spacing, support):
    """The local uniform stencil: lattice vectors dx k (k in Z^d) with 0 < |dx k| < support, as an (n, 3) array.

    Axes are the global coordinate axes (docs/boundaries.md, "LUST", choice 1); the third
    column is zero in 2D. Ordered by k (the summation order of the compiled loops).
    """
    reach = int(math.ceil(support / spacing))
    rng = range(-reach, reach + 1)
    out = []
    for kz in (rng if dim == 3 else (0,)):
        for ky in rng:
            for kx in rng:
                r2 = (kx * kx + ky * ky + kz * kz) * spacing * spacing
                if 0 < r2 < support * support:
                    out.append((kx * spacing, ky * spacing, kz * spacing))
    return np.ascontiguousarray(np.array(out, dtype=np.float64).reshape(-1, 3))


@njit(cache=True, inline="always")
def solid_marker(y0, y1, y2, dim, periodic, xw, surface, normal, start, order, lo, inv_cell, ncell, period, radius2):
    """The wall particle that makes the point y solid, or -1 if y is on the fluid side.

    y is solid when its nearest wall particle b within sqrt(radius2) exists and
    (y - s_b) . n_b < 0 (behind b's surface; s_b, n_b from seawall.shapes).
    Searches the 5^d cells around y's cell (cells are half a support wide).
    """
    cx, cy, cz = cell_index(y0, y1, y2, lo, inv_cell, ncell)
    nrows = 25 if dim == 3 else 5
    best = radius2
    b_best = -1
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                b = order[kk]
                d0, d1, d2, r2 = separation(y0, y1, y2, xw, b, dim, periodic, period)
                if r2 < best:
                    best = r2
                    b_best = b
    if b_best < 0:
        return -1
    s0, s1, s2, _ = separation(y0, y1, y2, surface, b_best, dim, periodic, period)
    n0, n1, n2 = point_of(normal, b_best, dim)
    if s0 * n0 + s1 * n1 + s2 * n2 < 0.0:
        return b_best
    return -1


@particle_loop()
def lust_kernel_sums(layout, xf, vol, xw, surface, normal, start, order, reach, lo, inv_cell, ncell, period, prm,
                     offsets, count, shepard, gradient):
    """Per fluid particle i, the kernel sums of its virtual (solid) stencil nodes, volumes ``vol[i]``:

    ``count[i]`` nodes, ``shepard[i]`` = sum_k V_i W_ik, ``gradient[i]`` = sum_k V_i grad_i W_ik
    ([Fourtakas2019]: the stencil completes i's kernel support; tests and diagnostics).
    """
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(xf.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        count[i] = 0
        shepard[i] = 0.0
        for c in range(dim):
            gradient[i, c] = 0.0
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        n = 0
        sw = 0.0
        g0 = g1 = g2 = 0.0
        for k in range(offsets.shape[0]):
            o0 = offsets[k, 0]
            o1 = offsets[k, 1]
            o2 = offsets[k, 2]
            b = solid_marker(p0 + o0, p1 + o1, p2 + o2, dim, periodic, xw, surface, normal, start, order, lo,
                             inv_cell, ncell, period, prm.support2)
            if b < 0:
                continue
            q = np.sqrt(o0 * o0 + o1 * o1 + o2 * o2) * inv_h
            n += 1
            sw += vol[i] * prm.sigma * kernel_shape(prm.kernel, q)
            f = vol[i] * gradient_factor(prm.kernel, gradient_scale, q)
            # grad_i W_ik = F r_ik, r_ik = x_i - y_k = -offset
            g0 -= f * o0
            g1 -= f * o1
            g2 -= f * o2
        count[i] = n
        shepard[i] = sw
        gradient[i, 0] = g0
        gradient[i, 1] = g1
        if dim == 3:
            gradient[i, 2] = g2


@particle_loop()
def lust_forces(layout, fluid, xw, vw, aw, surface, normal, start, order, reach, lo, inv_cell, ncell, period, prm,
                offsets, hydrostatic, noslip, alpha, nu, rates):
    """Add the virtual stencil nodes' terms to the fluid's rates ([Fourtakas2019]; formulas in the module doc).

    For every fluid particle i within reach of the wall and every solid node k of its stencil:

        drho_i/dt += m_i (v_i - v_k^slip) . grad_i W_ik                       ([Li2022] eq. 8)
        dv_i/dt   -= m_i (p_i/rho_i^2 + p_k/rho_k^2 + Pi_ik) grad_i W_ik       ([Li2022] eq. 5-6)
        dv_i/dt   += laminar term with v_k                                      ([Liu2015] eq. 9)

    with p_k, rho_k, v_k of the module doc. ``alpha`` and ``nu`` are 0 where the term does not act.
    """
    xf = fluid.x
    vf = fluid.v
    dv = rates.dv
    drho = rates.drho
    h = prm.h
    inv_h = 1.0 / h
    gradient_scale = prm.sigma * inv_h * inv_h
    eta2 = prm.eta2
    beta = prm.beta
    for i in prange(xf.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = fluid.rho[i]
        pi = fluid.p[i]
        mi = fluid.m[i]
        pr_i = pi / (rhoi * rhoi)
        ci = fluid.c[i]
        a0 = a1 = a2 = 0.0
        dr = 0.0
        for k in range(offsets.shape[0]):
            o0 = offsets[k, 0]
            o1 = offsets[k, 1]
            o2 = offsets[k, 2]
            b = solid_marker(p0 + o0, p1 + o1, p2 + o2, dim, periodic, xw, surface, normal, start, order, lo,
                             inv_cell, ncell, period, prm.support2)
            if b < 0:
                continue
            # r_ik = x_i - y_k = -offset
            d0 = -o0
            d1 = -o1
            d2 = -o2
            r2 = o0 * o0 + o1 * o1 + o2 * o2
            f = gradient_factor(prm.kernel, gradient_scale, np.sqrt(r2) * inv_h)
            # node state: Neumann pressure with the hydrostatic term, EOS density, i's mass
            pk = pi
            if hydrostatic:
                b0, b1, b2 = point_of(aw, b, dim)
                pk += rhoi * ((prm.gx - b0) * o0 + (prm.gy - b1) * o1 + (prm.gz - b2) * o2)
            rhok = eos_density(prm.eos, pk, prm.rho0, prm.c0, prm.gamma, prm.p_background)
            # velocity relative to the wall, its normal part mirrored (free slip) or all of it (no slip)
            w0, w1, w2 = point_of(vw, b, dim)
            n0, n1, n2 = point_of(normal, b, dim)
            u0 = vi0 - w0
            u1 = vi1 - w1
            u2 = vi2 - w2
            un2 = 2.0 * (u0 * n0 + u1 * n1 + u2 * n2)
            # v_i - v_k with the free-slip mirror: 2 (u . n) n; it is the continuity term's
            dr += continuity(mi, un2 * (n0 * d0 + n1 * d1 + n2 * d2), f)
            if noslip:
                e0 = 2.0 * u0
                e1 = 2.0 * u1
                e2 = 2.0 * u2
            else:
                e0 = un2 * n0
                e1 = un2 * n1
                e2 = un2 * n2
            vr = e0 * d0 + e1 * d1 + e2 * d2
            coef = pr_i + pk / (rhok * rhok)
            if alpha > 0.0 and viscosity_acts(vr, prm.alpha_all_pairs):
                ck = eos_sound_speed(prm.eos, rhok, prm.rho0, prm.c0, prm.gamma)
                coef += monaghan_viscosity(alpha, beta, h * vr / (r2 + eta2), 0.5 * (ci + ck), 0.5 * (rhoi + rhok))
            s = pressure_acceleration(mi, coef, f)
            a0 += s * d0
            a1 += s * d1
            a2 += s * d2
            if nu > 0.0:
                lam = laminar_viscosity(mi, nu, rhoi, rhok, f, r2, eta2)
                a0 += lam * e0
                a1 += lam * e1
                a2 += lam * e2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr


def _choice(name, value, allowed):
    text = str(value).strip()
    if text not in allowed:
        raise ParameterError(f"{name} must be one of {', '.join(allowed)} for lust; got {value!r}")
    return text


class LocalUniformStencil(WallModel):
    """Local uniform stencil (LUST) wall of [Fourtakas2019].

    Parameters
    ----------
    slip : {"free", "noslip"}
        Velocity of the virtual nodes in the viscous terms: the normal component
        relative to the wall mirrored (free slip, default) or the whole relative
        velocity (no slip; needs a fluid with artificial or laminar viscosity).
    pressure : {"hydrostatic", "copy"}
        Node pressure p_i + rho_i (g - a_w) . (y_k - x_i) (default) or p_i.
    alpha_wall : float, optional
        Artificial viscosity alpha between a fluid particle and its nodes;
        default: the fluid's alpha.
    """

    name = "lust"
    layout = "layers"
    #: not pairwise: a node's state is its own fluid particle's (pressure, velocity), and which nodes
    #: exist depends on the whole local wall geometry; there is no pair force between a fluid
    #: particle and a wall particle (the wall particles only mark the solid)
    pairwise_momentum = False
    #: the virtual nodes are not wall particles the fluid's summation could see
    joins_summation_density = False

    @property
    def fluid_terms(self):
        """Continuity and pressure, the fluid's viscosities; the wall particles count as solid volume
        in shifting and the transport velocity."""
        return frozenset({"continuity", "pressure", "artificial_viscosity", "laminar_viscosity", "shifting",
                          "transport_velocity"})

    def __init__(self, *, slip="free", pressure="hydrostatic", alpha_wall=None):
        self.slip = _choice("slip", slip, SLIP_MODES)
        self.pressure = _choice("pressure", pressure, PRESSURE_MODES)
        if alpha_wall is not None:
            try:
                alpha_wall = float(alpha_wall)
            except (TypeError, ValueError):
                raise ParameterError(f"alpha_wall must be a number >= 0, got {alpha_wall!r}") from None
            if not (alpha_wall >= 0.0 and math.isfinite(alpha_wall)):
                raise ParameterError(f"alpha_wall must be a number >= 0, got {alpha_wall!r}")
        self.alpha_wall = alpha_wall
        self.name = "lust" if self.slip == "free" else "lust-noslip"
        self._offsets = None

    def check(self, fluid, physics):
        if fluid.density_mode != "continuity":
            raise ParameterError("lust needs a fluid with density='continuity' (its stencil nodes are not "
                                 "particles a summation density could count)")
        if self.slip == "noslip" and self._alpha(physics) <= 0.0 and physics.nu <= 0.0:
            raise ParameterError("lust slip='noslip' needs a fluid with artificial or laminar viscosity "
                                 "(alpha_wall > 0 or nu > 0)")

    def _alpha(self, physics):
        return physics.alpha if self.alpha_wall is None else self.alpha_wall

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        if "surface" not in pa or "normal" not in pa:
            raise ParameterError(f"lust wall {wall.name!r} needs surface points and normals "
                                 "(build it with seawall.shapes.tank or polyline_wall)")
        # the wall particles are solid volume for shifting / transport velocity (rho0 dx^d each)
        pa["m"] = np.full(wall.n, physics.rho0 * wall.spacing ** wall.dim)
        self._offsets = stencil_offsets(wall.dim, fluid.spacing, math.sqrt(physics.support2))

    def offsets(self, fluid, physics):
        """The stencil (see :func:`stencil_offsets`) for ``fluid``'s spacing."""
        if self._offsets is None:
            self._offsets = stencil_offsets(fluid.dim, fluid.spacing, math.sqrt(physics.support2))
        return self._offsets

    def update(self, wall, fluid, ctx):
        """Nothing to set: a node's state is computed from its fluid particle in :meth:`interact`."""

    def interact(self, fluid, wall, ctx, dv, drho):
        from ..views import fluid_view

        g = ctx.grid
        pa = wall.particles
        cells = wall.cells
        prm = ctx.physics
        nu = prm.nu
        lust_forces(g.layout, fluid_view(fluid.particles), pa["x"], pa["v"], pa["a"], pa["surface"], pa["normal"],
                    cells.start, cells.order, cells.reach_mask(g), g.lo, g.inv_cell, g.ncell, g.period, prm,
                    self.offsets(fluid, prm), self.pressure == "hydrostatic", self.slip == "noslip",
                    self._alpha(prm), nu, rates_bundle(fluid, ctx, dv, drho))

    def kernel_sums(self, fluid, wall, ctx):
        """(count, shepard, gradient) of every fluid particle's virtual nodes (:func:`lust_kernel_sums`),
        with node volume m_i / rho_i."""
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        n = fp.n
        count = np.zeros(n, dtype=np.int64)
        shepard = np.zeros(n)
        gradient = np.zeros((n, wall.dim))
        cells = wall.cells
        lust_kernel_sums(g.layout, fp["x"], fp["m"] / fp["rho"], pa["x"], pa["surface"], pa["normal"], cells.start,
                         cells.order, cells.reach_mask(g), g.lo, g.inv_cell, g.ncell, g.period, ctx.physics,
                         self.offsets(fluid, ctx.physics), count, shepard, gradient)
        return count, shepard, gradient

    def describe(self):
        parts = [f"{self.slip} slip", f"{self.pressure} pressure"]
        if self.alpha_wall is not None:
            parts.append(f"alpha_wall {self.alpha_wall:g}")
        return f"lust ({', '.join(parts)})"


__all__ = ["LocalUniformStencil", "lust_forces", "lust_kernel_sums", "solid_marker", "stencil_offsets",
           "SLIP_MODES", "PRESSURE_MODES"]
