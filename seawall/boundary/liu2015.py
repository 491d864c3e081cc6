"""The dummy-particle wall of Liu, Qiang, Chen, Han & Fan (2015), [Liu2015] sec. 3.

Three to four layers of dummy particles continue the fluid's lattice behind
the wall (the wall surface lies half a spacing in front of the first layer).
Their density is constant (rho_b = rho0, [Liu2015] sec. 3.2); their pressure
and velocity are interpolated from the fluid every evaluation; they act on
the fluid only conditionally:

* continuity ([Liu2015] eq. 21): the wall changes a fluid particle's density
  only through the *normal* relative motion,

      (drho_i/dt)_b = m_b [(v_ib . n_b) n_b] . grad_i W_ib,

  so a particle sliding along the wall gets no density change from it (the
  extracted eq. 21 reads "m_b v_ib . grad W if v_ib . n_b != 0, else 0"; see
  docs/liu2015.md for why the projected form is used, and
  ``continuity="conditional"`` for the literal one);
* momentum ([Liu2015] eq. 22): a purely normal, purely repulsive push,

      (dv_i/dt)_b = -m_b (P_i + P_b) / (rho_i rho_b) (n_b . grad_i W_ib) n_b   if P_i + P_b > 0, else 0;

* dummy pressure ([Liu2015] eq. 23-27): each fluid neighbour j gives a Taylor
  estimate of the pressure at b with the normal gradient of eq. 25,

      <P_b>_j = P_j + rho_j c_s (v_j - v_w) . n_out + rho_j (g - a_b) . (r_b - r_j)      (eq. 26)

  (n_out = -n_b points out of the fluid into the wall: ours point into the
  fluid, see docs/liu2015.md; v_w and a_b are the wall's velocity and
  acceleration, zero for a fixed wall; a wall whose particles stay put -- a
  sliding lid with only a prescribed velocity -- has v_w . n = 0), and P_b is their CSPM average
  (eq. 27), sum_j V_j <P_b>_j W_bj / sum_j V_j W_bj, V_j = m_j / rho_j;
* dummy velocity (eq. 28-29): free slip uses the wall's velocity v_w; no slip
  uses v_b = 2 v_w - <v_b>, <v_b> the CSPM average of the fluid velocity. With
  no slip, v_b enters the laminar viscous term of eq. 9 between fluid particle
  i and dummy b (mu_b = mu of the fluid, rho_b = rho0); eq. 21 takes the
  dummy's normal velocity, 2 v_w . n - <v_b> . n (v_w . n with free slip),
  with v_w . n = 0 for a wall whose particles stay put. ``normal_velocity="wall"``
  gives eq. 21 the wall's own v_w . n with no slip as well (eq. 29 then acts only
  through the viscous term): the mirrored normal velocity over-presses the first
  fluid column next to a no-slip wall (docs/liu2015.md, choice 13).

Dummy particles with no fluid neighbour get P_b = background pressure and
v_b = v_w. Each dummy particle needs its unit wall normal (from the geometry:
``Shape.normals``, oriented into the fluid).
"""

import numpy as np
from numba import prange

from ..errors import ParameterError, require_nonnegative
from ..jit import particle_loop
from ..kernels import kernel_shape
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..pairs import continuity, gradient_factor, laminar_viscosity
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel, noslip_viscosity

SLIP_MODES = ("free", "noslip")
#: "normal": eq. 21 as the normal projection of v_ib; "conditional": eq. 21 literally
#: (the full term whenever |v_ib . n_b| > 1e-9 |v_ib|, else nothing)
CONTINUITY_MODES = ("normal", "conditional", "off")
#: the dummy's normal velocity in the normal form of eq. 21 with no slip: "mirror" = eq. 29's
#: (2 v_w - <v>) . n, as the paper writes it; "wall" = the wall's own v_w . n
NORMAL_VELOCITIES = ("mirror", "wall")


@particle_loop()
def liu2015_wall_state(layout, xw, vw, aw, nw, xf, vf, pf, rhof, mf, start, order, lo, inv_cell, ncell, period,
                       prm, noslip, mirror_normal, surface_moves, pw, vb, vbn):
    """Dummy pressure by eq. 26-27 and dummy velocity by eq. 28-29 of [Liu2015] for every wall particle.

    ``nw`` are the wall normals pointing into the fluid; eq. 26's normal points
    out of the fluid, hence the minus sign of the c_s term here. ``vbn`` gets
    the dummy's normal velocity v_b . n_b used by eq. 21: with no slip and
    ``mirror_normal`` the normal part of eq. 29's v_b, else the wall's own; when the wall's
    particles do not move (``surface_moves`` false, e.g. a sliding lid) the
    wall's normal velocity is zero whatever its prescribed (tangential) velocity.
    """
    n = xw.shape[0]
    inv_h = 1.0 / prm.h
    cs = prm.c0
    for b in prange(n):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xw, b, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        n0, n1, n2 = point_of(nw, b, dim)
        w0, w1, w2 = point_of(vw, b, dim)
        wn = (w0 * n0 + w1 * n1 + w2 * n2) if surface_moves else 0.0
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
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, f, dim, periodic, period)  # r_b - r_f
                    if r2 >= prm.support2:
                        continue
                    rj = rhof[f]
                    wv = mf[f] / rj * kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    u0, u1, u2 = point_of(vf, f, dim)
                    vn = u0 * n0 + u1 * n1 + u2 * n2 - wn
                    est = pf[f] - rj * cs * vn + rj * (g0 * d0 + g1 * d1 + g2 * d2)
                    sw += wv
                    sp += est * wv
                    if noslip:
                        sv0 += u0 * wv
                        sv1 += u1 * wv
                        sv2 += u2 * wv
        if sw > 0.0:
            pw[b] = sp / sw
        else:
            pw[b] = prm.p_background
        if noslip and sw > 0.0:
            vb[b, 0] = 2.0 * w0 - sv0 / sw
            vb[b, 1] = 2.0 * w1 - sv1 / sw
            if dim == 3:
                vb[b, 2] = 2.0 * w2 - sv2 / sw
            if mirror_normal:
                # the mirror of the fluid's normal velocity about the wall's
                vbn[b] = 2.0 * wn - (sv0 * n0 + sv1 * n1 + sv2 * n2) / sw
            else:
                vbn[b] = wn
        else:
            vb[b, 0] = w0
            vb[b, 1] = w1
            if dim == 3:
                vb[b, 2] = w2
            vbn[b] = wn


@particle_loop()
def liu2015_wall_forces(fluid, wall, vbn, rho_b, cells, prm, continuity_mode, wall_nu, dv, drho):
    """Add [Liu2015] eq. 21 (density), eq. 22 (pressure) and, with ``wall_nu`` > 0, the eq. 9 viscous term.

    ``wall.v`` holds the dummy velocities v_b, ``vbn`` their normal components (eq. 21);
    continuity_mode: 0 = normal projection, 1 = literal conditional form, 2 = none.
    """
    layout = cells.layout
    xf = fluid.x
    vf = fluid.v
    rhof = fluid.rho
    pf = fluid.p
    xw = wall.x
    nw = wall.normal
    vb = wall.v
    pw = wall.p
    mw = wall.m
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    nf = xf.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    eta2 = prm.eta2
    for i in prange(nf):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = rhof[i]
        pi = pf[i]
        a0 = a1 = a2 = 0.0
        dr = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xw, b, dim, periodic, period)  # r_i - r_b
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    f = gradient_factor(prm.kernel, gradient_scale, np.sqrt(r2) * inv_h)  # grad_i W = f r_ib
                    mb = mw[b]
                    n0, n1, n2 = point_of(nw, b, dim)
                    ndotgrad = (n0 * d0 + n1 * d1 + n2 * d2) * f
                    w0, w1, w2 = point_of(vb, b, dim)
                    u0 = vi0 - w0
                    u1 = vi1 - w1
                    u2 = vi2 - w2
                    if continuity_mode == 0:
                        vn = vi0 * n0 + vi1 * n1 + vi2 * n2 - vbn[b]
                        # eq. 21: only the normal relative motion, m_b (v_ib . n_b)(n_b . grad W)
                        dr += continuity(mb, vn, ndotgrad)
                    elif continuity_mode == 1:
                        vn = u0 * n0 + u1 * n1 + u2 * n2
                        uu = u0 * u0 + u1 * u1 + u2 * u2
                        if vn * vn > 1e-18 * uu:
                            dr += continuity(mb, u0 * d0 + u1 * d1 + u2 * d2, f)
                    psum = pi + pw[b]
                    if psum > 0.0:
                        # eq. 22: normal, repulsive only
                        s = -mb * psum / (rhoi * rho_b) * ndotgrad
                        a0 += s * n0
                        a1 += s * n1
                        a2 += s * n2
                    if wall_nu > 0.0:
                        # eq. 9 laminar term with mu_b = mu_i = rho nu and rho_b = rho0
                        lam = laminar_viscosity(mb, wall_nu, rhoi, rho_b, f, r2, eta2)
                        a0 += lam * u0
                        a1 += lam * u1
                        a2 += lam * u2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr


class Liu2015Wall(WallModel):
    """Dummy-particle wall of Liu et al. (2015), [Liu2015] sec. 3 (eq. 21-29).

    Parameters
    ----------
    slip : {"free", "noslip"}
        Free slip (dummy velocity = the wall's velocity, no viscous wall
        term) or no slip (dummy velocity 2 v_wall - <v> of eq. 28-29, used in
        eq. 21 and in the eq. 9 laminar viscous term).
    nu : float, optional
        Kinematic viscosity of the no-slip wall term [m^2/s]; default the
        fluid's laminar nu (else alpha h c0 / (2 d + 4) from its artificial
        viscosity).
    continuity : {"normal", "conditional", "off"}
        How eq. 21 is read: "normal" (default) keeps only the normal relative
        motion, m_b ((v_ib . n_b) n_b) . grad W; "conditional" is the extracted
        text literally (the full m_b v_ib . grad W whenever v_ib . n_b != 0);
        "off" drops the wall from the continuity equation.
    sound_speed_term : bool
        Include the rho c_s v . n term of eq. 26 (default True).
    normal_velocity : {"mirror", "wall"}
        With no slip, the dummy's normal velocity in eq. 21 (``continuity="normal"``):
        "mirror" (default) the normal part of eq. 29's v_b = 2 v_w - <v>, as the
        paper writes it; "wall" the wall's own normal velocity, so that eq. 29
        acts through the viscous term only. The mirror over-presses the first
        fluid column at a no-slip wall (docs/liu2015.md, choice 13). Free slip
        always uses the wall's.

    Each wall particle needs a normal (walls built by :mod:`seawall.shapes`
    carry them). The wall density is rho0 (constant) and its mass rho0 dx^d.
    """

    #: pairwise_momentum (see WallModel): one term per dummy particle ([Liu2015] eq. 22), but
    #: along the dummy's normal n_b, not r_ib: linear momentum is conserved pair by pair,
    #: angular momentum is not.
    pairwise_momentum = True

    name = "liu2015"

    #: the dummies' masses count in a summation-density fluid
    joins_summation_density = True

    @property
    def fluid_terms(self):
        """Continuity (eq. 21, its own normal form) unless off, pressure (eq. 22, its own normal,
        repulsive form) and, with no slip, the laminar term of eq. 9 with the wall's nu."""
        terms = {"pressure", "shifting", "transport_velocity"}
        if self.continuity != "off":
            terms.add("continuity")
        if self.slip == "noslip":
            terms.add("laminar_viscosity")
        return frozenset(terms)

    def __init__(self, *, slip="free", nu=None, continuity="normal", sound_speed_term=True, normal_velocity="mirror"):
        if slip not in SLIP_MODES:
            raise ParameterError(f"slip must be one of {', '.join(SLIP_MODES)}; got {slip!r}")
        if continuity not in CONTINUITY_MODES:
            raise ParameterError(f"continuity must be one of {', '.join(CONTINUITY_MODES)}; got {continuity!r}")
        if normal_velocity not in NORMAL_VELOCITIES:
            raise ParameterError(f"normal_velocity must be one of {', '.join(NORMAL_VELOCITIES)}; "
                                 f"got {normal_velocity!r}")
        if normal_velocity != "mirror" and continuity != "normal":
            raise ParameterError(f"normal_velocity={normal_velocity!r} acts on the normal form of eq. 21 only; "
                                 f"it needs continuity='normal', got continuity={continuity!r}")
        self.slip = slip
        self.nu = None if nu is None else require_nonnegative("nu", nu)
        self.continuity = continuity
        self.sound_speed_term = bool(sound_speed_term)
        self.normal_velocity = normal_velocity
        self.name = "liu2015" if slip == "free" else "liu2015-noslip"
        self._wall_nu = 0.0
        self._rho_b = 1000.0

    def check(self, fluid, physics):
        """No slip needs a viscosity (given, or the fluid's)."""
        if self.slip == "noslip":
            noslip_viscosity(self.nu, physics)

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        if "normal" not in pa:
            raise ParameterError(f"liu2015 wall {wall.name!r} needs wall normals (build it with seawall.shapes)")
        nrm = np.linalg.norm(pa["normal"], axis=1)
        if not np.all(np.abs(nrm - 1.0) < 1e-6):
            raise ParameterError(f"liu2015 wall {wall.name!r}: every wall normal must be a unit vector")
        n = wall.n
        self._rho_b = physics.rho0
        pa["p"] = np.full(n, physics.p_background)
        pa["rho"] = np.full(n, physics.rho0)
        pa["m"] = np.full(n, physics.rho0 * wall.spacing ** wall.dim)
        pa["v_dummy"] = pa["v"].copy()
        pa["vn_dummy"] = np.zeros(n)
        self._wall_nu = 0.0
        if self.slip == "noslip":
            self._wall_nu = noslip_viscosity(self.nu, physics)

    def _prm(self, physics):
        return physics if self.sound_speed_term else physics._replace(c0=0.0)

    def update(self, wall, fluid, ctx):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        cells = ctx.fluid_cells
        liu2015_wall_state(g.layout, pa["x"], pa["v"], pa["a"], pa["normal"], fp["x"], fp["v"], fp["p"], fp["rho"],
                           fp["m"], cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period,
                           self._prm(ctx.physics), self.slip == "noslip", self.normal_velocity == "mirror",
                           wall.movement is not None, pa["p"],
                           pa["v_dummy"], pa["vn_dummy"])

    def interact(self, fluid, wall, ctx, dv, drho):
        pa = wall.particles
        liu2015_wall_forces(fluid_view(fluid.particles), wall_view(pa, v="v_dummy"), pa["vn_dummy"], self._rho_b,
                            cell_view(ctx.grid, wall.cells, reach=True), ctx.physics,
                            CONTINUITY_MODES.index(self.continuity), self._wall_nu, dv, drho)

    def describe(self):
        return self.name
