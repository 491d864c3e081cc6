"""Dummy-particle walls ([TrixiBoundary], "BoundaryModelDummyParticles").

Wall particles are treated like fluid particles in the fluid's momentum and
continuity equations, but they do not move with the flow. What distinguishes
the variants is how the wall particles' pressure and density are found (the
"density calculator"). This module implements:

* ``adami`` -- Adami, Hu & Adams (2012) pressure extrapolation ([TrixiBoundary],
  "AdamiPressureExtrapolation"):

      p_b = sum_f (p_f + rho_f (g - a_b) . r_bf) W_bf / sum_f W_bf,   r_bf = r_b - r_f

  and rho_b from the inverse equation of state. Wall particles with no fluid
  neighbour get p_b = 0 (reference density).
* ``summation`` -- rho_b = sum_j m_j W_bj over fluid and wall neighbours, self
  included ([TrixiBoundary], "SummationDensity"; [Li2022] eq. 7), p_b = EOS(rho_b).
* ``continuity`` -- drho_b/dt = sum_f m_f (v_b - v_f) . grad_b W_bf ([TrixiBoundary],
  "ContinuityDensity"; [Li2022] eq. 8), p_b = EOS(rho_b). The wall density is
  advanced between evaluations by the rate of the previous one (explicit
  Euler over the interval between evaluations). With no slip it keeps this
  density: the Adami pass then supplies only the wall velocity.
* ``zeroing`` -- rho_b = rho0, p_b = p(rho0) ([TrixiBoundary], "PressureZeroing").
* ``mirroring`` -- rho_b = rho0 and, in the momentum equation, p_b = p_a of the
  interacting fluid particle ([TrixiBoundary], "PressureMirroring", after Akinci et
  al. 2012 and Band et al. 2018).

The wall mass is the "hydrodynamic mass" rho0 dx^d of a fluid particle at
the wall spacing ([TrixiBoundary]), independent of any wall material density.

Slip: free slip by default (no viscous wall term). No slip follows Adami et
al. (2012) through the wall velocity ([TrixiBoundary], "No-slip conditions")

      v_w = 2 v_b - sum_f v_f W_bf / sum_f W_bf,

used only in a laminar viscous term with kinematic viscosity nu (by default
the fluid's nu, or alpha h c0 / (2 d + 4) when the fluid uses artificial
viscosity -- the equivalence given in [TrixiBoundary]).
"""

import numpy as np
from numba import prange

from ..eos import eos_density, eos_pressure
from ..errors import ParameterError, require_nonnegative, require_positive
from ..fluid.rates import scheme_tag, tag_value
from ..jit import particle_loop
from ..kernels import kernel_gradient_factor, kernel_shape
from ..neighbors import cell_index, neighbour_range, point_of, reach_plan, reach_range, tag_dim, tag_periodic, separation
from ..pairs import (continuity, gradient_factor, laminar_viscosity, pressure_acceleration, riemann_continuity,
                     riemann_fluid_jump, riemann_momentum_coefficient, riemann_pressure,
                     riemann_wall_jump)
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel, noslip_viscosity, rates_bundle

SLIP_MODES = ("free", "noslip")
DENSITY_CALCULATORS = ("adami", "summation", "continuity", "zeroing", "mirroring")


@particle_loop()
def adami_wall_state(layout, xw, vw, aw, xf, vf, pf, rhof, start, order, reach, lo, inv_cell, ncell, period, prm,
                     noslip, clip_negative, pw, rhow, vw_visc, scheme):
    """Adami (2012) extrapolated pressure, density and (no-slip) wall velocity of every wall particle.

    ``reach`` is the fluid cell list's reach mask (``CellList.reach_mask``): a wall particle in a
    cell outside it has no fluid particle in the cells its walk would visit, so the walk is skipped
    and it gets what a walk without neighbours gives (sw = 0): the background pressure, its
    density, and its own velocity as no-slip velocity.
    In the 3D dam break most of the 76k wall particles are such.

    A serial pass sorts the wall particles first: those outside the mask get their values there,
    and the parallel walk runs over the list of the others only. A ``prange`` over all of them
    split the index range evenly between threads, but the wetted walls lie in a few index ranges,
    so one thread got most of the walks (3D dam break, 2 threads: 11.1 ms of wall time for 14.3 ms
    of CPU time; 7.7 ms with the list, docs/performance.md). ``scheme`` is
    :func:`~seawall.fluid.rates.scheme_tag` of ``prm``, for the kernel as a compile-time constant.
    """
    nw = xw.shape[0]
    inv_h = 1.0 / prm.h
    dim_ = tag_dim(layout)   # the serial pass's; the parallel body reads its own below
    rho_none = eos_density(prm.eos, prm.p_background, prm.rho0, prm.c0, prm.gamma, prm.p_background)
    walked = np.empty(nw, dtype=np.int64)
    n_walked = 0
    for b in range(nw):
        p0, p1, p2 = point_of(xw, b, dim_)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] != 0:
            walked[n_walked] = b
            n_walked += 1
            continue
        # no fluid particle within reach: the walk would give sw = 0
        pw[b] = prm.p_background
        rhow[b] = rho_none
        if noslip:
            for a in range(dim_):
                vw_visc[b, a] = vw[b, a]
    for q in prange(n_walked):
        b = walked[q]
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        kernel = tag_value(scheme[0])
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        plan = reach_plan(p0, p1, p2, cx, cy, cz, lo, inv_cell)
        ab0, ab1, ab2 = point_of(aw, b, dim)
        g0 = prm.gx - ab0
        g1 = prm.gy - ab1
        g2 = prm.gz - ab2
        sw = 0.0
        sp = 0.0
        sv0 = sv1 = sv2 = 0.0
        for row in range(nrows):
            for part in range(2 if periodic else 1):
                if periodic:
                    ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                else:  # only the cells the support reaches: the same pairs, fewer candidates
                    ka, kb = reach_range(row, cx, cy, cz, plan, ncell, start, prm.support2)
                for k in range(ka, kb):
                    f = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, f, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    w = kernel_shape(kernel, np.sqrt(r2) * inv_h)
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


@particle_loop()
def wall_summation_density(layout, xw, mw, start_w, order_w, xf, mf, start_f, order_f, lo, inv_cell, ncell,
                           period, prm, clip_negative, rhow, pw):
    """rho_b = sum_j m_j W_bj over wall (self included) and fluid neighbours; p_b = EOS(rho_b).

    [TrixiBoundary] "SummationDensity"; [Li2022] eq. 7. With ``clip_negative`` the
    pressure is floored at the background pressure: the outer wall layers
    miss neighbours beyond the wall, so their summed density is below rho0
    (990 and 763 kg/m^3 in layers 2 and 3 at h = 1.3 dx) and unclipped they
    suck the nearest fluid into the wall.
    """
    nw = xw.shape[0]
    inv_h = 1.0 / prm.h
    for b in prange(nw):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        acc = 0.0
        for which in range(2):
            for row in range(nrows):
                for part in range(2):
                    if which == 0:
                        ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_w)
                    else:
                        ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_f)
                    for k in range(ka, kb):
                        j = order_w[k] if which == 0 else order_f[k]
                        if which == 0:
                            d0, d1, d2, r2 = separation(p0, p1, p2, xw, j, dim, periodic, period)
                        else:
                            d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                        if r2 >= prm.support2:
                            continue
                        mj = mw[j] if which == 0 else mf[j]
                        acc += mj * prm.sigma * kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
        rhow[b] = acc
        pb = eos_pressure(prm.eos, acc, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        if clip_negative and pb < prm.p_background:
            pb = prm.p_background
        pw[b] = pb


@particle_loop()
def wall_continuity_rate(layout, xw, vw, rhow, xf, vf, mf, start, order, lo, inv_cell, ncell, period, prm,
                         drhow, pw):
    """drho_b/dt = sum_f m_f (v_b - v_f) . grad_b W_bf and p_b = EOS(rho_b).

    [TrixiBoundary] "ContinuityDensity"; [Li2022] eq. 8 written for wall particle b.
    """
    nw = xw.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for b in prange(nw):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vb0, vb1, vb2 = point_of(vw, b, dim)
        dr = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    f = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, f, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    fac = gradient_scale * kernel_gradient_factor(prm.kernel, np.sqrt(r2) * inv_h)
                    u0, u1, u2 = point_of(vf, f, dim)
                    dr += mf[f] * ((vb0 - u0) * d0 + (vb1 - u1) * d1 + (vb2 - u2) * d2) * fac
        drhow[b] = dr
        pw[b] = eos_pressure(prm.eos, rhow[b], prm.rho0, prm.c0, prm.gamma, prm.p_background)


@particle_loop()
def dummy_wall_forces(fluid, wall, cells, prm, mirror, wall_nu, rates, scheme):
    """Add the dummy wall's terms to the fluid's rates (pair terms of :mod:`seawall.pairs`).

    continuity:  drho_i += m_b (v_i - v_b) . grad_i W_ib, v_b the wall's own velocity
                 (Adami et al. 2012, eq. 24 form; [Li2022] eq. 8 with b a wall particle)
    momentum:    dv_i -= m_b (p_i/rho_i^2 + p_b/rho_b^2) grad_i W_ib    ([Li2022] eq. 5)
                 with p_b = p_i, rho_b = rho0 when ``mirror`` ([TrixiBoundary], PressureMirroring)
    Riemann fluid (``prm.riemann``, [Zhang2017] sec. 3): both terms through the pair Riemann problem
                 with the wall particle's p_b, rho_b and own velocity v_b as the right state
                 (seawall.pairs.riemann_*; V_b = m_b / rho_b); the limiter's velocity jump is the
                 mirrored normal one, -2 (v_i - v_b) . n_b (riemann_wall_jump), so free slip stays free
                 (a wall without normals: the jump along the line of centres)
    no slip:     dv_i += m_b nu (rho_i + rho_b)/(rho_i rho_b) (v_i - v_w) (r_ib . grad W)/(r^2 + eta^2)
                 when wall_nu > 0 ([Liu2015] eq. 9 form with the Adami wall velocity v_w = wall.v_visc)

    ``cells`` is the wall's CellView with its reach mask: fluid particles in other cells are skipped.
    ``scheme`` is :func:`~seawall.fluid.rates.scheme_tag` of ``prm``: the kernel and the Riemann switch
    are compile-time constants, as in the fluid loop.
    """
    layout = cells.layout
    xf = fluid.x
    vf = fluid.v
    rhof = fluid.rho
    pf = fluid.p
    xw = wall.x
    vw = wall.v
    vw_visc = wall.v_visc
    rhow = wall.rho
    pw = wall.p
    mw = wall.m
    normals = wall.normal
    # the mirrored normal jump needs the wall's normals; a wall without them uses the line of centres
    has_normals = normals.shape[0] == xw.shape[0]
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    dv = rates.dv
    drho = rates.drho
    nf = xf.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    eta2 = prm.eta2
    rho0c0 = prm.rho0 * prm.c0
    for i in prange(nf):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        kernel = tag_value(scheme[0])
        riemann = tag_value(scheme[1]) != 0
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        plan = reach_plan(p0, p1, p2, cx, cy, cz, lo, inv_cell)
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = rhof[i]
        pr_i = pf[i] / (rhoi * rhoi)
        a0 = a1 = a2 = 0.0
        dr = 0.0
        for row in range(nrows):
            for part in range(2 if periodic else 1):
                if periodic:
                    ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                else:  # only the cells the support reaches: the same pairs, fewer candidates
                    ka, kb = reach_range(row, cx, cy, cz, plan, ncell, start, prm.support2)
                for k in range(ka, kb):
                    b = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xw, b, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    f = gradient_factor(kernel, gradient_scale, r * inv_h)
                    mb = mw[b]
                    vb0, vb1, vb2 = point_of(vw, b, dim)
                    vrb = (vi0 - vb0) * d0 + (vi1 - vb1) * d1 + (vi2 - vb2) * d2
                    if mirror:
                        pb = pf[i]
                        rhob = prm.rho0
                    else:
                        pb = pw[b]
                        rhob = rhow[b]
                    if riemann:
                        dr += riemann_continuity(rhoi, mb / rhob, vrb, pf[i], pb, r, rho0c0, f)
                        if has_normals:
                            n0, n1, n2 = point_of(normals, b, dim)
                            du = riemann_wall_jump((vi0 - vb0) * n0 + (vi1 - vb1) * n1 + (vi2 - vb2) * n2)
                        else:
                            du = riemann_fluid_jump(vrb, r)
                        coef = riemann_momentum_coefficient(
                            riemann_pressure(pf[i], pb, du, rho0c0, prm.c0, prm.riemann_eta), rhoi, rhob)
                    else:
                        dr += continuity(mb, vrb, f)
                        coef = pr_i + pb / (rhob * rhob)
                    s = pressure_acceleration(mb, coef, f)
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
                    if wall_nu > 0.0:
                        w0, w1, w2 = point_of(vw_visc, b, dim)
                        lam = laminar_viscosity(mb, wall_nu, rhoi, rhob, f, r2, eta2)
                        a0 += lam * (vi0 - w0)
                        a1 += lam * (vi1 - w1)
                        a2 += lam * (vi2 - w2)
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr


class DummyParticles(WallModel):
    """Dummy-particle wall with one of the five density calculators of [TrixiBoundary].

    Parameters
    ----------
    density : {"adami", "summation", "continuity", "zeroing", "mirroring"}
        How the wall particles' pressure and density are found (default
        ``adami``, the one [TrixiBoundary] recommends).
    slip : {"free", "noslip"}
        Free slip (default, no viscous wall term) or no slip through the
        Adami wall velocity 2 v_wall - (Shepard average of fluid velocity).
    nu : float, optional
        Kinematic viscosity of the no-slip wall term [m^2/s]; default: the
        fluid's laminar nu, else alpha h c0 / (2d + 4) from its artificial
        viscosity ([TrixiBoundary]).
    clip_negative_pressure : bool, optional
        Clip negative wall pressure to the background pressure. Default: off
        for ``adami`` (as in [TrixiBoundary]), on for ``summation`` (see
        :func:`wall_summation_density` for why); ignored by the others.
    eos : seawall.Tait | seawall.Linear, optional
        Equation of state of the wall particles (density <-> pressure);
        default: the fluid's ([TrixiBoundary]: "inherited from the fluid unless given").
    kernel : seawall kernel, optional
        Kernel of the fluid-wall interaction; default: the fluid's.
    smoothing_length : float, optional
        Smoothing length of the fluid-wall interaction [m]; default: the
        fluid's. Its support must not exceed the fluid's, for which the
        neighbour grid is built.
    """

    #: pairwise_momentum (see WallModel): one symmetric pressure term
    #: m_b (p_i/rho_i^2 + p_b/rho_b^2) grad_i W_ib ([Li2022] eq. 5) and viscous pair term per
    #: wall particle b, with b's state set in update; central. With pressure mirroring p_b is
    #: i's own pressure: still one term per pair.
    pairwise_momentum = True
    #: the wall's hydrodynamic masses count in a summation-density fluid ([TrixiBoundary])
    joins_summation_density = True

    @property
    def integrated_arrays(self):
        """The continuity calculator advances the wall density in ``update``."""
        return ("rho",) if self.density == "continuity" else ()

    @property
    def fluid_terms(self):
        """Continuity and pressure; with no slip a laminar term with the wall's own nu (not the fluid's)."""
        terms = {"continuity", "pressure", "shifting", "transport_velocity"}
        if self.slip == "noslip":
            terms.add("laminar_viscosity")
        return frozenset(terms)

    def __init__(self, *, density="adami", slip="free", nu=None, clip_negative_pressure=None, eos=None,
                 kernel=None, smoothing_length=None):
        from ..eos import EquationOfState
        from ..kernels import Kernel

        if eos is not None and not isinstance(eos, EquationOfState):
            raise ParameterError(f"eos must be seawall.Tait or seawall.Linear, got {type(eos).__name__}")
        if kernel is not None and not isinstance(kernel, Kernel):
            raise ParameterError(f"kernel must be a seawall kernel, got {kernel!r}")
        self.eos = eos
        self.kernel = kernel
        self.smoothing_length = None if smoothing_length is None else require_positive("smoothing_length",
                                                                                        smoothing_length)
        self._overrides = {}
        if density not in DENSITY_CALCULATORS:
            raise ParameterError(f"density must be one of {', '.join(DENSITY_CALCULATORS)}; got {density!r}")
        if slip not in SLIP_MODES:
            raise ParameterError(f"slip must be one of {', '.join(SLIP_MODES)}; got {slip!r}")
        self.density = density
        self.slip = slip
        self.nu = None if nu is None else require_nonnegative("nu", nu)
        if clip_negative_pressure is None:
            clip_negative_pressure = density == "summation"
        self.clip_negative_pressure = bool(clip_negative_pressure)
        self.name = density if slip == "free" else f"{density}-noslip"
        self._wall_nu = 0.0
        self._last_time = None

    def _own_physics(self, physics):
        """The fluid's compiled parameters with this wall's EOS / kernel / smoothing length, if given."""
        from ..kernels import KERNELS

        changes = {}
        if self.eos is not None:
            changes.update(eos=self.eos.kind, c0=self.eos.c0, gamma=self.eos.gamma,
                           p_background=self.eos.background_pressure)
        if self.kernel is not None or self.smoothing_length is not None:
            kernel = self.kernel or next(k for k in KERNELS.values() if k.kind == physics.kernel)()
            h = self.smoothing_length or physics.h
            support = kernel.support(h)
            if support * support > physics.support2 * (1.0 + 1e-12):
                raise ParameterError(
                    f"the wall's kernel support {support:g} m exceeds the fluid's {physics.support2 ** 0.5:g} m "
                    "(the neighbour grid is built for the fluid): give a smaller smoothing_length")
            changes.update(kernel=kernel.kind, h=h, sigma=kernel.sigma(h, physics.dim), support2=support * support,
                           eta2=0.01 * h * h)
        return changes

    def _physics(self, physics):
        return physics._replace(**self._overrides) if self._overrides else physics

    def check(self, fluid, physics):
        """No slip needs a viscosity (given, or the fluid's)."""
        if self.slip == "noslip":
            noslip_viscosity(self.nu, physics._replace(**self._own_physics(physics)))

    def prepare(self, wall, fluid, physics):
        self._overrides = self._own_physics(physics)
        physics = self._physics(physics)
        n = wall.n
        pa = wall.particles
        pa["p"] = np.full(n, physics.p_background)
        pa["rho"] = np.full(n, physics.rho0)
        pa["m"] = np.full(n, physics.rho0 * wall.spacing ** wall.dim)
        pa["v_visc"] = pa["v"].copy()
        if self.density == "continuity":
            pa["drho"] = np.zeros(n)
        if self.slip == "noslip":
            self._wall_nu = noslip_viscosity(self.nu, physics)

    def update(self, wall, fluid, ctx):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        cells = ctx.fluid_cells
        prm = self._physics(ctx.physics)
        noslip = self.slip == "noslip"
        if self.density == "adami" or noslip:
            # the Adami pass also yields the no-slip wall velocity for every calculator; the other
            # calculators keep their own density, so its pressure and density go to scratch arrays
            # (otherwise `continuity` + no slip would restart from Adami's density every evaluation)
            own = self.density == "adami"
            p_out = pa["p"] if own else np.empty(wall.n)
            rho_out = pa["rho"] if own else np.empty(wall.n)
            adami_wall_state(g.layout, pa["x"], pa["v"], pa["a"], fp["x"], fp["v"], fp["p"], fp["rho"],
                             cells.start, cells.order, cells.reach_mask(g), g.lo, g.inv_cell, g.ncell, g.period,
                             prm, noslip,
                             self.clip_negative_pressure, p_out, rho_out, pa["v_visc"], scheme_tag(prm))
        if self.density == "summation":
            wall_summation_density(g.layout, pa["x"], pa["m"], wall.cells.start, wall.cells.order, fp["x"],
                                   fp["m"], cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period,
                                   prm, self.clip_negative_pressure, pa["rho"], pa["p"])
        elif self.density == "continuity":
            if self._last_time is not None:
                dt = ctx.time - self._last_time
                pa["rho"] += dt * pa["drho"]
            self._last_time = ctx.time
            wall_continuity_rate(g.layout, pa["x"], pa["v"], pa["rho"], fp["x"], fp["v"], fp["m"], cells.start,
                                 cells.order, g.lo, g.inv_cell, g.ncell, g.period, prm, pa["drho"], pa["p"])
        elif self.density in ("zeroing", "mirroring"):
            pa["rho"][:] = prm.rho0
            pa["p"][:] = prm.p_background

    def interact(self, fluid, wall, ctx, dv, drho):
        prm = self._physics(ctx.physics)
        dummy_wall_forces(fluid_view(fluid.particles), wall_view(wall.particles, v_visc="v_visc"),
                          cell_view(ctx.grid, wall.cells, reach=True), prm,
                          self.density == "mirroring", self._wall_nu, rates_bundle(fluid, ctx, dv, drho),
                          scheme_tag(prm))

    def state(self):
        """Model state that a checkpoint must keep (continuity's last evaluation time)."""
        return {"last_time": self._last_time}

    def set_state(self, state):
        self._last_time = state.get("last_time")

    def describe(self):
        return self.name
