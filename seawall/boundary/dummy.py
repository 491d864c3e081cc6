"""Dummy-particle walls (seed 004, "BoundaryModelDummyParticles").

Wall particles are treated like fluid particles in the fluid's momentum and
continuity equations, but they do not move with the flow. What distinguishes
the variants is how the wall particles' pressure and density are found (the
"density calculator"). This module implements:

* ``adami`` -- Adami, Hu & Adams (2012) pressure extrapolation (seed 004,
  "AdamiPressureExtrapolation"):

      p_b = sum_f (p_f + rho_f (g - a_b) . r_bf) W_bf / sum_f W_bf,   r_bf = r_b - r_f

  and rho_b from the inverse equation of state. Wall particles with no fluid
  neighbour get p_b = 0 (reference density).

The wall mass is the "hydrodynamic mass" rho0 dx^d of a fluid particle at
the wall spacing (seed 004), independent of any wall material density.

Slip: free slip by default (no viscous wall term). No slip follows Adami et
al. (2012) through the wall velocity (seed 004, "No-slip conditions")

      v_w = 2 v_b - sum_f v_f W_bf / sum_f W_bf,

used only in a laminar viscous term with kinematic viscosity nu (by default
the fluid's nu, or alpha h c0 / (2 d + 4) when the fluid uses artificial
viscosity -- the equivalence given in seed 004).
"""

import numpy as np
from numba import njit, prange

from ..eos import eos_density
from ..errors import ParameterError, require_nonnegative
from ..kernels import kernel_gradient_factor, kernel_shape
from ..neighbors import cell_index, minimum_image, neighbour_range, point_of, tag_dim, tag_periodic
from .base import WallModel

SLIP_MODES = ("free", "noslip")


@njit(cache=True, parallel=True, fastmath=True)
def adami_wall_state(layout, xw, vw, aw, xf, vf, pf, rhof, start, order, lo, inv_cell, ncell, period, prm,
                     noslip, clip_negative, pw, rhow, vw_visc):
    """Adami (2012) extrapolated pressure, density and (no-slip) wall velocity of every wall particle."""
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nw = xw.shape[0]
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    for b in prange(nw):
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        ab0, ab1, ab2 = point_of(aw, b, dim)
        g0 = prm.gx - ab0
        g1 = prm.gy - ab1
        g2 = prm.gz - ab2
        sw = 0.0
        sp = 0.0
        sv0 = sv1 = sv2 = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    f = order[k]
                    q0, q1, q2 = point_of(xf, f, dim)
                    d0 = (minimum_image(p0 - q0, period[0]) if periodic else p0 - q0)
                    d1 = (minimum_image(p1 - q1, period[1]) if periodic else p1 - q1)
                    d2 = (minimum_image(p2 - q2, period[2]) if periodic else p2 - q2)
                    r2 = d0 * d0 + d1 * d1 + d2 * d2
                    if r2 >= prm.support2:
                        continue
                    w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    sw += w
                    sp += (pf[f] + rhof[f] * (g0 * d0 + g1 * d1 + g2 * d2)) * w
                    if noslip:
                        u0, u1, u2 = point_of(vf, f, dim)
                        sv0 += u0 * w
                        sv1 += u1 * w
                        sv2 += u2 * w
        pb = sp / sw if sw > 0.0 else prm.p_background
        if clip_negative and pb < prm.p_background:
            pb = prm.p_background
        pw[b] = pb
        rhow[b] = eos_density(prm.eos, pb, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        if noslip:
            vb0, vb1, vb2 = point_of(vw, b, dim)
            if sw > 0.0:
                vw_visc[b, 0] = 2.0 * vb0 - sv0 / sw
                vw_visc[b, 1] = 2.0 * vb1 - sv1 / sw
                if dim == 3:
                    vw_visc[b, 2] = 2.0 * vb2 - sv2 / sw
            else:
                vw_visc[b, 0] = vb0
                vw_visc[b, 1] = vb1
                if dim == 3:
                    vw_visc[b, 2] = vb2


@njit(cache=True, parallel=True, fastmath=True)
def dummy_wall_forces(layout, xf, vf, rhof, pf, xw, vw, vw_visc, rhow, pw, mw, start, order, lo, inv_cell,
                      ncell, period, prm, mirror, wall_nu, dv, drho):
    """Add the dummy wall's terms to the fluid's rates.

    continuity:  drho_i += m_b (v_i - v_b) . grad_i W_ib, v_b the wall's own velocity
                 (Adami et al. 2012, eq. 24 form; seed 000 eq. 8 with b a wall particle)
    momentum:    dv_i -= m_b (p_i/rho_i^2 + p_b/rho_b^2) grad_i W_ib    (seed 000 eq. 5)
                 with p_b = p_i, rho_b = rho0 when ``mirror`` (seed 004, PressureMirroring)
    no slip:     dv_i += m_b nu (rho_i + rho_b)/(rho_i rho_b) (v_i - v_w) (r_ib . grad W)/(r^2 + eta^2)
                 when wall_nu > 0 (seed 003 eq. 9 form with the Adami wall velocity v_w)
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = xf.shape[0]
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    gradient_scale = prm.sigma * inv_h * inv_h
    eta2 = prm.eta2
    for i in prange(nf):
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = rhof[i]
        pr_i = pf[i] / (rhoi * rhoi)
        a0 = a1 = a2 = 0.0
        dr = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    q0, q1, q2 = point_of(xw, b, dim)
                    d0 = (minimum_image(p0 - q0, period[0]) if periodic else p0 - q0)
                    d1 = (minimum_image(p1 - q1, period[1]) if periodic else p1 - q1)
                    d2 = (minimum_image(p2 - q2, period[2]) if periodic else p2 - q2)
                    r2 = d0 * d0 + d1 * d1 + d2 * d2
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    f = gradient_scale * kernel_gradient_factor(prm.kernel, r * inv_h)
                    mb = mw[b]
                    vb0, vb1, vb2 = point_of(vw, b, dim)
                    dr += mb * ((vi0 - vb0) * d0 + (vi1 - vb1) * d1 + (vi2 - vb2) * d2) * f
                    if mirror:
                        coef = pr_i + pf[i] / (prm.rho0 * prm.rho0)
                        rhob = prm.rho0
                    else:
                        rhob = rhow[b]
                        coef = pr_i + pw[b] / (rhob * rhob)
                    s = -mb * coef * f
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
                    if wall_nu > 0.0:
                        w0, w1, w2 = point_of(vw_visc, b, dim)
                        lam = mb * wall_nu * (rhoi + rhob) / (rhoi * rhob) * f * r2 / (r2 + eta2)
                        a0 += lam * (vi0 - w0)
                        a1 += lam * (vi1 - w1)
                        a2 += lam * (vi2 - w2)
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr


class DummyParticles(WallModel):
    """Dummy-particle wall with Adami pressure extrapolation (seed 004).

    Parameters
    ----------
    slip : {"free", "noslip"}
        Free slip (default, no viscous wall term) or no slip through the
        Adami wall velocity 2 v_wall - (Shepard average of fluid velocity).
    nu : float, optional
        Kinematic viscosity of the no-slip wall term [m^2/s]; default: the
        fluid's laminar nu, else alpha h c0 / (2d + 4) from its artificial
        viscosity (seed 004).
    clip_negative_pressure : bool
        Clip negative extrapolated wall pressure to the background pressure
        (off by default, as in seed 004).
    """

    name = "adami"

    def __init__(self, *, slip="free", nu=None, clip_negative_pressure=False):
        if slip not in SLIP_MODES:
            raise ParameterError(f"slip must be one of {', '.join(SLIP_MODES)}; got {slip!r}")
        self.slip = slip
        self.nu = None if nu is None else require_nonnegative("nu", nu)
        self.clip_negative_pressure = bool(clip_negative_pressure)
        self.name = "adami" if slip == "free" else "adami-noslip"
        self._wall_nu = 0.0

    def prepare(self, wall, fluid, physics):
        n = wall.n
        pa = wall.particles
        pa["p"] = np.zeros(n)
        pa["rho"] = np.full(n, physics.rho0)
        pa["m"] = np.full(n, physics.rho0 * wall.spacing ** wall.dim)
        pa["v_visc"] = pa["v"].copy()
        if self.slip == "noslip":
            if self.nu is not None:
                self._wall_nu = self.nu
            elif physics.nu > 0.0:
                self._wall_nu = physics.nu
            else:
                self._wall_nu = physics.alpha * physics.h * physics.c0 / (2 * physics.dim + 4)
            if self._wall_nu <= 0.0:
                raise ParameterError("slip='noslip' needs a viscosity: give nu or use a fluid with viscosity")

    def update(self, wall, fluid, ctx):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        adami_wall_state(g.layout, pa["x"], pa["v"], pa["a"], fp["x"], fp["v"], fp["p"], fp["rho"],
                         ctx.fluid_cells.start, ctx.fluid_cells.order, g.lo, g.inv_cell, g.ncell,
                         g.period, ctx.physics, self.slip == "noslip", self.clip_negative_pressure,
                         pa["p"], pa["rho"], pa["v_visc"])

    def interact(self, fluid, wall, ctx, dv, drho):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        dummy_wall_forces(g.layout, fp["x"], fp["v"], fp["rho"], fp["p"], pa["x"], pa["v"], pa["v_visc"],
                          pa["rho"], pa["p"], pa["m"], wall.cells.start, wall.cells.order, g.lo,
                          g.inv_cell, g.ncell, g.period, ctx.physics, False, self._wall_nu, dv, drho)

    def describe(self):
        return self.name
