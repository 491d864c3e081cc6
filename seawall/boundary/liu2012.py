"""Boundary force of Liu, Shao & Chang (2012), a baseline of [Liu2015].

Liu M.B., Shao J.R., Chang J.Z. (2012), "On the treatment of solid boundary
in smoothed particle hydrodynamics", Sci. China Technol. Sci. 55, 244-254
([Liu2015] ref. [9]). [Liu2015] describes it (sec. 1 and 4.4) but does not
print it: a single row of boundary particles, spaced finer than the fluid
(1.5 mm against 2.92 mm in its dam break), each pushing a fluid particle
along the line joining them with a strength that depends only on their
distance. The force used here is the one of Liu et al. (2012):

    (dv_i/dt)_b = 0.01 c^2 chi(r) f(eta) r_ib / r^2,      r = |r_ib|, eta = r / (0.75 h),

    chi(r) = 1 - r / dd for r < dd, else 0      (dd: the fluid's initial spacing),

    f(eta) = 2/3                  for 0 < eta <= 2/3,
             2 eta - 1.5 eta^2    for 2/3 < eta <= 1,
             0.5 (2 - eta)^2      for 1 < eta < 2,
             0                    otherwise.

It was written down from the publication, which is not among the seeds, so
docs/liu2015.md records it as such. The boundary particles carry no density
or pressure and do not enter the continuity equation; there is no viscous
wall term (free slip), as in [Liu2015]'s dam break.
"""

import numpy as np
from numba import prange

from ..errors import require_positive
from ..jit import loop_helper, particle_loop
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..views import cell_view
from .base import WallModel


@loop_helper
def liu2012_shape(eta):
    """f(eta) of Liu et al. (2012): 2/3, 2 eta - 1.5 eta^2, 0.5 (2 - eta)^2 on (0, 2/3], (2/3, 1], (1, 2)."""
    if eta <= 2.0 / 3.0:
        return 2.0 / 3.0
    if eta <= 1.0:
        return 2.0 * eta - 1.5 * eta * eta
    if eta < 2.0:
        return 0.5 * (2.0 - eta) * (2.0 - eta)
    return 0.0


@loop_helper
def liu2012_factor(r, h, dd, c):
    """The scalar s with (dv_i/dt)_b = s r_ib: 0.01 c^2 chi f(eta) / r^2."""
    if r >= dd or r <= 0.0:
        return 0.0
    chi = 1.0 - r / dd
    return 0.01 * c * c * chi * liu2012_shape(r / (0.75 * h)) / (r * r)


@particle_loop()
def liu2012_wall_forces(xf, xw, cells, prm, dd, c, dv):
    """Add the Liu et al. (2012) boundary force of every boundary particle within dd to the fluid's dv."""
    layout = cells.layout
    start = cells.start
    order = cells.order
    reach = cells.reach
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    dd2 = dd * dd
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
                    if r2 >= dd2 or r2 == 0.0:
                        continue
                    s = liu2012_factor(np.sqrt(r2), prm.h, dd, c)
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
        dv[i, 0] += a0
        dv[i, 1] += a1
        if dim == 3:
            dv[i, 2] += a2


class Liu2012Force(WallModel):
    """One row of boundary particles with the Liu, Shao & Chang (2012) repulsive force.

    Parameters
    ----------
    beta : float
        Fluid spacing / boundary-particle spacing, default 2 ([Liu2015]'s dam
        break: 2.92 mm fluid, 1.5 mm boundary particles).
    c : float, optional
        The speed c of the force scale 0.01 c^2 [m/s]; default the fluid's c0.

    The cases build the row on the wall surface at spacing dx / beta
    (``layout = "surface"``, as for Monaghan-Kajtar).
    """

    #: pairwise_momentum (see WallModel): one central force per boundary particle, a function
    #: of the distance only (Liu et al. 2012; module docstring).
    pairwise_momentum = True

    name = "liu2012"
    layout = "surface"
    #: the row's masses count in a summation-density fluid (as they always did)
    joins_summation_density = True

    def __init__(self, *, beta=2.0, c=None):
        self.beta = require_positive("beta", beta)
        self.c = None if c is None else require_positive("c", c)
        self._dd = 0.0
        self._c = 0.0

    def prepare(self, wall, fluid, physics):
        wall.particles["m"] = np.full(wall.n, physics.rho0 * wall.spacing ** wall.dim)
        self._dd = fluid.spacing
        self._c = self.c if self.c is not None else physics.c0

    def update(self, wall, fluid, ctx):
        """Boundary-force particles carry no state to update."""

    def interact(self, fluid, wall, ctx, dv, drho):
        liu2012_wall_forces(fluid.particles["x"], wall.x, cell_view(ctx.grid, wall.cells, reach=True), ctx.physics,
                            self._dd, self._c, dv)

    def describe(self):
        return self.name
