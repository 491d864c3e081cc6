"""Fluid-wall adhesion of Akinci, Akinci & Teschner (2013), as [TrixiBoundary] offers it.

[TrixiBoundary] gives wall systems an ``adhesion_coefficient`` beta; the force is
the adhesion term of Akinci et al. (2013), "Versatile surface tension and
adhesion for SPH fluids", ACM TOG 32(6), eq. 6-7:

    F_i<-k = -beta m_i Psi_k C(|x_i - x_k|) (x_i - x_k) / |x_i - x_k|

so the acceleration of fluid particle i from wall particle k is

    a_i = -beta Psi_k C(r) (x_i - x_k) / r,

pointing from i towards the wall particle (attraction). Psi_k is the wall
particle's fluid-equivalent mass, which we take as the hydrodynamic mass
rho0 dx_wall^d of [TrixiBoundary] (the same mass the dummy particles carry).
The adhesion kernel, with s the support radius of the SPH kernel (Akinci's
"h" is the support radius, not the smoothing length), is

    C(r) = 0.007 / s^3.25 * (-4 r^2 / s + 6 r - 2 s)^(1/4)   for s/2 < r <= s,
    C(r) = 0                                              otherwise.

The bracket is -(4/s)(r - s/2)(r - s): zero at r = s/2 and r = s and
positive between, so the force vanishes continuously at both ends and
peaks at r = 3s/4. The constant 0.007 s^-3.25 is the paper's (derived for
3D); [TrixiBoundary] uses the same expression in 2D, and so do we. beta is in
the paper's units, so only relative values of it carry meaning across
resolutions; [TrixiBoundary]'s default is 0 (no adhesion).
"""

import numpy as np
from numba import prange

from ..jit import loop_helper, particle_loop
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..views import cell_view


@loop_helper
def adhesion_kernel(r, s):
    """C(r) of Akinci et al. (2013), eq. 7, with s the kernel support radius."""
    if r <= 0.5 * s or r > s:
        return 0.0
    bracket = -4.0 * r * r / s + 6.0 * r - 2.0 * s
    if bracket <= 0.0:
        return 0.0
    return 0.007 / s ** 3.25 * bracket ** 0.25


@particle_loop()
def adhesion_accelerations(xf, xw, psi, cells, support, beta, dv):
    """Add a_i = -beta sum_k Psi_k C(r_ik) (x_i - x_k)/r_ik to every fluid particle near the wall."""
    layout = cells.layout
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    support2 = support * support
    for i in prange(xf.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(xf, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        if reach[cx + ncell[0] * (cy + ncell[1] * cz)] == 0:
            continue
        a0 = a1 = a2 = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    b = order[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xw, b, dim, periodic, period)
                    if r2 > support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    s = -beta * psi[b] * adhesion_kernel(r, support) / r
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2


def add_adhesion(wall, fluid, ctx, support, dv):
    """Add the adhesion of ``wall`` (its ``adhesion_coefficient``) to the fluid's accelerations ``dv``."""
    g = ctx.grid
    pa = wall.particles
    if "adhesion_mass" not in pa:
        pa["adhesion_mass"] = np.full(wall.n, ctx.physics.rho0 * wall.spacing ** wall.dim)
    adhesion_accelerations(fluid.particles["x"], pa["x"], pa["adhesion_mass"], cell_view(g, wall.cells, reach=True),
                           support, wall.adhesion_coefficient, dv)
