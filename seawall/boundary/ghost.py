"""Fixed ghost particles with mirror-point interpolation ([Huang2019], Huang et al. 2019).

The wall is a set of fixed particles in layers outside the fluid ([Huang2019]
sec. 2.2, Fig. 1). Each ghost particle G at x_G has a mirror (interpolation)
point x_M, its reflection across the wall surface along the wall normal:

    x_M = 2 s_G - x_G,   s_G = closest point of the wall surface,   n = (s_G - x_G)/|s_G - x_G|.

Both come from the wall geometry (``seawall.shapes``: ``surface_points``
and ``normals``); at a corner s_G is the corner point itself, so x_M is the
reflection through the corner and lies inside the fluid, not in the other
wall (see :func:`mirror_diagnostics`).

Before each evaluation of the fluid's rates (``update``) the fluid state is
interpolated at x_M by one of the methods of
:mod:`seawall.boundary.interpolation` and copied to G with the laws of
mirror ([Huang2019] sec. 2.2):

* pressure, Neumann condition dp/dn = rho (g - a_w) . n (sec. 2.2) integrated
  along the segment from x_M to x_G:

      p_G = p_M + rho_M (g - a_w) . (x_G - x_M)

  with rho_M the inverse EOS of p_M and a_w the wall's acceleration. Since
  x_G - x_M = -2 d_w n, with d_w = |s_G - x_G| the ghost's distance to the
  wall, this is p_M - 2 d_w rho (g - a_w) . n: the "2 d rho g . n" of the
  seed's eq. 13, 16 and 21 (d = distance from the ghost to the wall) and the
  "d rho g . n" of eq. 8 (d = distance from the ghost to its mirror point)
  are the same term; the seed's two d's differ by the factor 2
  (docs/ghost.md, with the measurement).
* density: rho_G = EOS^-1(p_G); mass: the hydrodynamic mass rho0 dx^d.
* velocity, relative to the wall's own velocity v_w (u = v_M - v_w):
  free slip reverses the normal component, u_G = u - 2 (u . n) n; no slip
  reverses both, u_G = -u; then v_G = v_w + u_G. A ghost beyond a corner
  (its closest surface point is a vertex or an edge, :func:`corner_tangents`)
  is the image of its mirror point under the reflections in *every* face it
  lies beyond, not in the plane normal to its diagonal ``n``: free slip
  reverses every component across those faces, u_G = -u in a 2D corner or
  at a 3D vertex, u_G = -u + 2 (u . t) t along a 3D edge of direction t.
  (For a 90-degree corner this is exact: the image of the corner flow
  u = -k x, v = k y, or of any flow symmetric about both faces, under the
  two reflections. The reflection in the plane normal to the diagonal
  swaps the components instead, u_G = (v, u) for a 45-degree diagonal.
  Its effect on the dam break's corner pressure: docs/validation-notes.md,
  plateau profiles; it did not remove the ghost walls' corner over-pressure.)

``interact`` adds the ghosts' terms to the fluid's rates; ghost particles
enter the fluid's equations as ordinary neighbours (Marrone et al. 2011,
[Huang2019] sec. 2.1) with their mirrored state:

    drho_i/dt += m_G (v_i - v_G) . grad_i W_iG
    dv_i/dt   -= m_G (p_i/rho_i^2 + p_G/rho_G^2 + Pi_iG) grad_i W_iG   (+ laminar term)

with the fluid's artificial viscosity Pi ([Li2022] eq. 6; on every pair, as
between fluid particles, when the fluid's ``ArtificialViscosity(all_pairs=True)``,
[Huang2019] eq. 5) and laminar viscosity ([Liu2015] eq. 9). The density-diffusion term is not applied
across the wall (ghost densities include the hydrostatic jump, and the
renormalised gradient is not available at ghosts).
"""

import os

import numpy as np
from numba import prange

from ..diagnostics import nearest_wall_particle
from ..eos import eos_density, eos_sound_speed
from ..errors import ParameterError
from ..jit import particle_loop
from ..neighbors import cell_index, neighbour_range, point_of, tag_dim, tag_periodic, separation
from ..pairs import (continuity, gradient_factor, laminar_viscosity, monaghan_viscosity, pressure_acceleration,
                     viscosity_acts)
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel, rates_bundle
from .interpolation import (INTERPOLATIONS, Interpolation, interpolate_points)

SLIP_MODES = ("free", "noslip")


def corner_tangents(positions, surface_points, spacing):
    """Which ghosts lie beyond a corner, and the corner's edge direction.

    The ghosts whose closest surface point is the same point s are grouped; their
    offsets x - s span a line for a face point (the normal), a plane at a 3D edge
    (normal to the edge) and the whole space at a 2D corner or a 3D vertex. Returns
    ``corner`` (int8, 1 where the span has more than one dimension) and ``tangent``
    (unit edge direction at a 3D edge, zero otherwise), the data of the free-slip
    image at corners (module doc).
    """
    x = np.asarray(positions, dtype=np.float64)
    s = np.asarray(surface_points, dtype=np.float64)
    n, dim = x.shape
    corner = np.zeros(n, dtype=np.int8)
    tangent = np.zeros((n, dim))
    if n == 0:
        return corner, tangent
    keys = np.round(s / (1e-6 * spacing)).astype(np.int64)
    _, group = np.unique(keys, axis=0, return_inverse=True)
    group = group.ravel()
    order = np.argsort(group, kind="stable")
    bounds = np.r_[0, np.nonzero(np.diff(group[order]))[0] + 1, n]
    for a, b in zip(bounds[:-1], bounds[1:]):
        idx = order[a:b]
        off = x[idx] - s[idx]
        norms = np.linalg.norm(off, axis=1)
        off = off[norms > 1e-9 * spacing] / norms[norms > 1e-9 * spacing][:, None]
        if off.shape[0] < 2:
            continue
        sv, vt = np.linalg.svd(off, full_matrices=True)[1:]
        rank = int(np.sum(sv > 1e-6 * sv[0]))
        if rank < 2:
            continue
        corner[idx] = 1
        if dim == 3 and rank == 2:
            tangent[idx] = vt[2]
    return corner, tangent


@particle_loop()
def ghost_transfer(layout, xg, mirror, normal, vwall, awall, interp, count, prm, noslip, pg, rhog, vg,
                   corner, tangent):
    """Laws of mirror ([Huang2019] sec. 2.2): ghost p, rho, v from the values interpolated at the mirror points.

    ``interp[:, 0]`` is the pressure, ``interp[:, 1:]`` the velocity at x_M. ``corner`` and
    ``tangent`` (:func:`corner_tangents`) give the free-slip image of the ghosts beyond a corner.
    A ghost whose mirror point has no fluid neighbour gets the background
    pressure, rho0 and the wall velocity.
    """
    for b in prange(xg.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        vw0, vw1, vw2 = point_of(vwall, b, dim)
        if count[b] == 0:
            pg[b] = prm.p_background
            rhog[b] = prm.rho0
            vg[b, 0] = vw0
            vg[b, 1] = vw1
            if dim == 3:
                vg[b, 2] = vw2
            continue
        pm = interp[b, 0]
        rhom = eos_density(prm.eos, pm, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        x0, x1, x2 = point_of(xg, b, dim)
        m0, m1, m2 = point_of(mirror, b, dim)
        a0, a1, a2 = point_of(awall, b, dim)
        gterm = (prm.gx - a0) * (x0 - m0) + (prm.gy - a1) * (x1 - m1) + (prm.gz - a2) * (x2 - m2)
        p = pm + rhom * gterm
        pg[b] = p
        rhog[b] = eos_density(prm.eos, p, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        u0 = interp[b, 1] - vw0
        u1 = interp[b, 2] - vw1
        u2 = (interp[b, 3] - vw2) if dim == 3 else 0.0
        if noslip:
            vg[b, 0] = vw0 - u0
            vg[b, 1] = vw1 - u1
            if dim == 3:
                vg[b, 2] = vw2 - u2
        elif corner[b] != 0:
            # the reflections in every face the ghost lies beyond: all components across them reversed
            t0, t1, t2 = point_of(tangent, b, dim)
            ut = 2.0 * (u0 * t0 + u1 * t1 + u2 * t2)
            vg[b, 0] = vw0 - u0 + ut * t0
            vg[b, 1] = vw1 - u1 + ut * t1
            if dim == 3:
                vg[b, 2] = vw2 - u2 + ut * t2
        else:
            n0, n1, n2 = point_of(normal, b, dim)
            un = 2.0 * (u0 * n0 + u1 * n1 + u2 * n2)
            vg[b, 0] = vw0 + u0 - un * n0
            vg[b, 1] = vw1 + u1 - un * n1
            if dim == 3:
                vg[b, 2] = vw2 + u2 - un * n2


@particle_loop()
def ghost_forces(fluid, wall, cells, prm, terms, rates):
    """Add the ghost particles' terms to the fluid's rates (gather over ghost cells; formulas in the module doc).

    ``wall.v`` is the velocity in the continuity term and ``wall.v_visc`` the one in the viscous terms
    (both the mirrored ghost velocities for ghost walls; mDBC may split them); ``terms`` (:class:`~seawall.boundary.base.CrossTerms`)
    says which of the fluid's viscous terms act across the wall.
    """
    layout = cells.layout
    xf = fluid.x
    vf = fluid.v
    rhof = fluid.rho
    pf = fluid.p
    cf = fluid.c
    xg = wall.x
    vc = wall.v         # velocity in the continuity term
    vg = wall.v_visc    # velocity in the viscous terms (the same array for ghost walls)
    rhog = wall.rho
    pg = wall.p
    mg = wall.m
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
    h = prm.h
    inv_h = 1.0 / h
    gradient_scale = prm.sigma * inv_h * inv_h
    eta2 = prm.eta2
    alpha = prm.alpha if terms.artificial_viscosity else 0.0
    beta = prm.beta
    nu = prm.nu if terms.laminar_viscosity else 0.0
    for i in prange(nf):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue   # no wall particle in the cells this particle searches (CellList.reach_mask)
        vi0, vi1, vi2 = point_of(vf, i, dim)
        rhoi = rhof[i]
        pr_i = pf[i] / (rhoi * rhoi)
        ci = cf[i]
        a0 = a1 = a2 = 0.0
        dr = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xg, b, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    f = gradient_factor(prm.kernel, gradient_scale, r * inv_h)
                    mb = mg[b]
                    rhob = rhog[b]
                    c0_, c1_, c2_ = point_of(vc, b, dim)
                    dr += continuity(mb, (vi0 - c0_) * d0 + (vi1 - c1_) * d1 + (vi2 - c2_) * d2, f)
                    w0, w1, w2 = point_of(vg, b, dim)
                    u0 = vi0 - w0
                    u1 = vi1 - w1
                    u2 = vi2 - w2
                    vr = u0 * d0 + u1 * d1 + u2 * d2
                    coef = pr_i + pg[b] / (rhob * rhob)
                    if alpha > 0.0 and viscosity_acts(vr, terms.all_pairs):
                        cb = eos_sound_speed(prm.eos, rhob, prm.rho0, prm.c0, prm.gamma)
                        coef += monaghan_viscosity(alpha, beta, h * vr / (r2 + eta2), 0.5 * (ci + cb),
                                                   0.5 * (rhoi + rhob))
                    s = pressure_acceleration(mb, coef, f)
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
                    if nu > 0.0:
                        lam = laminar_viscosity(mb, nu, rhoi, rhob, f, r2, eta2)
                        a0 += lam * u0
                        a1 += lam * u1
                        a2 += lam * u2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2
        drho[i] += dr


@particle_loop(fastmath=False)
def reflect_crossed(xf, vf, xw, nw, sw, vw, start, order, reach, lo, inv_cell, ncell, radius2, hit):
    """Return the fluid particles that crossed the wall surface to the fluid side (opt-in safeguard).

    For each fluid particle the nearest wall particle b within the radius gives
    the surface point s_b and normal n_b (as :func:`seawall.diagnostics.signed_wall_distance`);
    with d = (x - s_b) . n_b < 0 the particle is reflected specularly across the
    surface, x <- x - 2 d n_b, and an inward normal velocity relative to the
    wall, u_n = (v - v_b) . n_b < 0, is reversed, v <- v - 2 u_n n_b (an
    elastic bounce: position and kinetic energy relative to the wall kept).
    ``hit[i]`` is set to 1 for a reflected particle.
    """
    dim = xf.shape[1]
    for i in prange(xf.shape[0]):
        hit[i] = 0
        p2 = xf[i, 2] if dim == 3 else 0.0
        b_best = nearest_wall_particle(xf[i, 0], xf[i, 1], p2, dim, xw, start, order, reach, lo, inv_cell, ncell,
                                       radius2)
        if b_best < 0:
            continue
        s = 0.0
        un = 0.0
        for k in range(dim):
            s += (xf[i, k] - sw[b_best, k]) * nw[b_best, k]
            un += (vf[i, k] - vw[b_best, k]) * nw[b_best, k]
        if s >= 0.0:
            continue
        hit[i] = 1
        for k in range(dim):
            xf[i, k] -= 2.0 * s * nw[b_best, k]
            if un < 0.0:
                vf[i, k] -= 2.0 * un * nw[b_best, k]


def mirror_points(surface_points, positions):
    """Mirror (interpolation) points 2 s - x of wall particles ([Huang2019] sec. 2.2, Fig. 1)."""
    return 2.0 * np.asarray(surface_points, dtype=np.float64) - np.asarray(positions, dtype=np.float64)


def mirror_diagnostics(positions, surface_points, spacing):
    """Check the mirror points of a wall: for each particle, the distance from its
    mirror point to the nearest wall particle, in units of the spacing.

    A mirror point inside the fluid lies at least ~0.5 dx from every wall
    particle (1 dx for a first-layer particle on a lattice); a value below
    0.5 flags a mirror point that fell into the wall itself or into another
    wall (e.g. a wrongly chosen surface point at a corner).

    Returns (mirror points, distance / dx).
    """
    from ..shapes import _nearest_distances

    x = np.asarray(positions, dtype=np.float64)
    m = mirror_points(surface_points, x)
    dist = _nearest_distances(m, x, 2.0 * spacing)  # exact below 2 dx, larger values are bounds
    return m, dist / spacing


def export_ghost_vtu(wall, directory):
    """Write the ghost particles and their mirror points as two VTU files for inspection.

    ``DIR/ghost_<name>.vtu``: ghost positions with ``normal``, ``to_mirror``
    (x_M - x_G, glyph it in ParaView), ``distance_to_wall`` and, once the
    model has run, pressure/density/velocity. ``DIR/mirror_<name>.vtu``:
    the mirror points with the ghost ``id`` and ``nearest_wall_over_dx``
    (:func:`mirror_diagnostics`). Returns both paths.
    """
    from ..io.vtk import write_vtu

    pa = wall.particles
    if "surface" not in pa or "normal" not in pa:
        raise ParameterError(f"wall {wall.name!r} has no surface points/normals (use seawall.shapes walls)")
    os.makedirs(directory, exist_ok=True)
    x = pa["x"]
    mirror, near = mirror_diagnostics(x, pa["surface"], wall.spacing)
    data = {"id": pa["id"], "normal": pa["normal"], "to_mirror": mirror - x,
            "distance_to_wall": np.linalg.norm(pa["surface"] - x, axis=1)}
    for key, name in (("p", "pressure"), ("rho", "density"), ("v_ghost", "ghost_velocity")):
        if key in pa:
            data[name] = pa[key]
    g = write_vtu(os.path.join(directory, f"ghost_{wall.name}.vtu"), x, data)
    m = write_vtu(os.path.join(directory, f"mirror_{wall.name}.vtu"), mirror,
                  {"id": pa["id"], "nearest_wall_over_dx": near})
    return g, m


class GhostParticles(WallModel):
    """Fixed ghost particles whose state is mirrored from interpolation points ([Huang2019]).

    Parameters
    ----------
    interpolation : Interpolation or str
        ``MLS(1)``, ``MLS(2)``, ``SFDI()``, ``Normalised()`` or
        ``ImprovedShepard()`` (or their names ``mls1``, ``mls2``, ``sfdi``,
        ``normalized``, ``shepard``); default the improved Shepard method.
    slip : {"free", "noslip"}
        Free slip reverses the normal velocity at the ghost, no slip both
        components (relative to the wall's own velocity).
    """

    #: pairwise_momentum (see WallModel): the ghosts' state is interpolated in update; the
    #: push is then one symmetric pressure ([Li2022] eq. 5 form) and viscous pair term per
    #: ghost; central. The wall force of [Huang2019] eq. 29 is the sum of their reactions.
    pairwise_momentum = True
    #: ghosts are ordinary neighbours with their mirrored state ([Huang2019] sec. 2.1), with the fluid's
    #: viscosities; no density diffusion across the wall (see the module doc)
    fluid_terms = frozenset({"continuity", "pressure", "artificial_viscosity", "laminar_viscosity", "shifting",
                             "transport_velocity"})
    #: the ghosts' hydrodynamic masses count in a summation-density fluid
    joins_summation_density = True

    def __init__(self, interpolation="shepard", *, slip="free", reflect=False):
        if isinstance(interpolation, str):
            try:
                interpolation = INTERPOLATIONS[interpolation]()
            except KeyError:
                raise ParameterError(f"unknown interpolation {interpolation!r}; available: "
                                     f"{', '.join(INTERPOLATIONS)}") from None
        if not isinstance(interpolation, Interpolation):
            raise ParameterError(f"interpolation must be a seawall interpolation, got {interpolation!r}")
        if slip not in SLIP_MODES:
            raise ParameterError(f"slip must be one of {', '.join(SLIP_MODES)}; got {slip!r}")
        self.interpolation = interpolation
        self.slip = slip
        self.reflect = bool(reflect)
        #: fluid particles reflected by the ``reflect`` safeguard so far (not part of the state)
        self.reflections = 0
        self.name = f"ghost-{interpolation.name}" + ("" if slip == "free" else "-noslip")
        self._buf = None

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        if "surface" not in pa or "normal" not in pa:
            raise ParameterError(f"ghost wall {wall.name!r} needs surface points and normals "
                                 "(build it with seawall.shapes.tank or polyline_wall)")
        n = wall.n
        pa["mirror"] = np.ascontiguousarray(mirror_points(pa["surface"], pa["x"]))
        pa["p"] = np.full(n, physics.p_background)
        pa["rho"] = np.full(n, physics.rho0)
        pa["m"] = np.full(n, physics.rho0 * fluid.spacing ** wall.dim)
        pa["v_ghost"] = pa["v"].copy()
        pa["n_interp"] = np.zeros(n, dtype=np.int64)
        corner, tangent = corner_tangents(pa["x"], pa["surface"], wall.spacing)
        pa["corner"] = corner
        pa["corner_tangent"] = np.ascontiguousarray(tangent)
        self._buf = np.zeros((n, 1 + wall.dim))

    def update(self, wall, fluid, ctx):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        fields = np.empty((fp.n, 1 + wall.dim))
        fields[:, 0] = fp["p"]
        fields[:, 1:] = fp["v"]
        vol = fp["m"] / fp["rho"]
        kind, mu, lam, flag = self.interpolation.compiled()
        if self._buf is None or self._buf.shape[0] != wall.n:
            self._buf = np.zeros((wall.n, 1 + wall.dim))
        interpolate_points(g.layout, kind, mu, lam, flag, pa["mirror"], fp["x"], fields, vol,
                           ctx.fluid_cells.start, ctx.fluid_cells.order, g.lo, g.inv_cell, g.ncell, g.period,
                           ctx.physics, self._buf, pa["n_interp"])
        ghost_transfer(g.layout, pa["x"], pa["mirror"], pa["normal"], pa["v"], pa["a"], self._buf,
                       pa["n_interp"], ctx.physics, self.slip == "noslip", pa["p"], pa["rho"], pa["v_ghost"],
                       pa["corner"], pa["corner_tangent"])

    def interact(self, fluid, wall, ctx, dv, drho):
        ghost_forces(fluid_view(fluid.particles), wall_view(wall.particles, v="v_ghost"),
                     cell_view(ctx.grid, wall.cells, reach=True), ctx.physics, self.cross_terms(ctx.physics),
                     rates_bundle(fluid, ctx, dv, drho))

    def after_step(self, wall, fluid, sim):
        """With ``reflect``: send fluid particles that ended the step behind the wall surface back
        across it (:func:`reflect_crossed`)."""
        if not self.reflect or fluid.particles.n == 0:
            return
        fp = fluid.particles
        pa = wall.particles
        g = sim.grid
        hit = np.zeros(fp.n, dtype=np.uint8)
        reflect_crossed(fp["x"], fp["v"], pa["x"], pa["normal"], pa["surface"], pa["v"], wall.cells.start,
                        wall.cells.order, wall.cells.reach_mask(g), g.lo, g.inv_cell, g.ncell,
                        sim.physics.support2, hit)
        self.reflections += int(hit.sum())

    def describe(self):
        return self.name
