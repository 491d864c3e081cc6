"""Modified dynamic boundary condition, mDBC ([English2022], English et al. 2022).

The wall is DBC's: fixed (or prescribed-motion) particles in layers behind
the surface that enter the fluid's equations as ordinary neighbours. What
mDBC changes is how a wall particle's density is found. Instead of
integrating the continuity equation on the wall particle (DBC, [Li2022]
eq. 8), each wall particle b has a *ghost node* x_g, its reflection across
the wall surface along the wall normal into the fluid ([English2022] sec. 2):

    x_g = x_b + 2 (s_b - x_b) = 2 s_b - x_b,    s_b = closest point of the wall surface,

the mirror point of the ghost walls (:func:`seawall.boundary.ghost.mirror_points`,
the same geometry from :mod:`seawall.shapes`; at a corner s_b is the corner
point). At x_g the fluid density and its gradient are interpolated with the
first-order corrected kernel of [LiuLiu2006]
(:func:`seawall.boundary.interpolation.corrected_point`), and the density
is extrapolated linearly back to the wall particle:

    rho_b = rho_g + (x_b - x_g) . grad rho_g                       ([English2022] sec. 2)

which is exact for a linear density field (hydrostatic water). When the
correction matrix is ill-conditioned, |det A| < ``det_min`` (1e-3 by
default, the value of DualSPHysics' implementation of [English2022]), the
ghost node takes the Shepard density sum m_j W / sum V_j W and no gradient;
with no fluid neighbour at all the wall particle gets rho0. ``order=0``
uses the Shepard density everywhere (zeroth order). The wall pressure is the
fluid's equation of state of rho_b.

Velocity ([English2022] sec. 2, no slip): with ``slip="vel0"`` (the
original mDBC) the wall particles keep the wall's own velocity v_w; with
``slip="noslip"`` the velocity interpolated at the ghost node (same
corrected interpolation and fallback) is mirrored through the wall,

    v_b = 2 v_w - v_g,

so that the velocity interpolated halfway, on the surface, is v_w. The
first-order v_g is limited to its neighbours' range, component by component
(docs/boundaries.md, "mDBC", choice 2).

The wall particles act on the fluid through the fluid's own pair terms
(continuity with the wall's own velocity v_w, pressure, the fluid's
artificial and laminar viscosity with v_b), as DBC particles do in
[English2022]; the loop is the ghost
walls' :func:`seawall.boundary.ghost.ghost_forces` (the same terms, not a
copy). Choices where the paper leaves room are listed in docs/boundaries.md
("mDBC").
"""

import numpy as np
from numba import prange

from ..eos import eos_pressure
from ..errors import ParameterError
from ..jit import particle_loop
from ..neighbors import point_of, tag_dim
from ..views import cell_view, fluid_view, wall_view
from .base import WallModel, rates_bundle
from .ghost import ghost_forces, mirror_points
from .interpolation import CORRECTED_LINEAR, CORRECTED_NONE, corrected_point

SLIP_MODES = ("vel0", "noslip")
ORDERS = (0, 1)
#: |det A| below which the ghost node falls back to the Shepard density (DualSPHysics' value)
DET_MIN = 1e-3


@particle_loop()
def mdbc_wall_state(layout, xw, ghost, vwall, xf, fields, vol, start, order, lo, inv_cell, ncell, period, prm,
                    first_order, det_min, noslip, clip_negative, value, grad, rho_out, p_out, v_out, outcome):
    """mDBC wall state from the ghost nodes ([English2022] sec. 2; formulas in the module doc).

    ``fields[:, 0]`` is the fluid density, ``fields[:, 1:]`` the velocity (no slip only).
    rho_b = rho_g + (x_b - x_g) . grad rho_g (first order) or rho_g (Shepard); rho0 without neighbours.
    p_b = EOS(rho_b); v_b = v_w (vel0) or 2 v_w - v_g (no slip). ``outcome[b]`` is the
    interpolation's outcome (interpolation.CORRECTED_*). With ``clip_negative`` rho_b is not
    taken below rho0, so p_b >= p_background (docs/boundaries.md, "mDBC", choice 3).
    """
    for b in prange(xw.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        g0, g1, g2 = point_of(ghost, b, dim)
        # the velocity (columns 1..) is limited to the neighbours' range; the density is extrapolated
        cnt, how = corrected_point(layout, first_order, det_min, 1, g0, g1, g2, xf, fields, vol, start, order, lo,
                                   inv_cell, ncell, period, prm, value, grad, b)
        outcome[b] = how
        vw0, vw1, vw2 = point_of(vwall, b, dim)
        if how == CORRECTED_NONE:
            rho = prm.rho0
        else:
            x0, x1, x2 = point_of(xw, b, dim)
            rho = value[b, 0]
            if how == CORRECTED_LINEAR:
                rho += (x0 - g0) * grad[b, 0, 0] + (x1 - g1) * grad[b, 0, 1]
                if dim == 3:
                    rho += (x2 - g2) * grad[b, 0, 2]
        if clip_negative and rho < prm.rho0:
            rho = prm.rho0
        rho_out[b] = rho
        p_out[b] = eos_pressure(prm.eos, rho, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        if noslip and how != CORRECTED_NONE:
            v_out[b, 0] = 2.0 * vw0 - value[b, 1]
            v_out[b, 1] = 2.0 * vw1 - value[b, 2]
            if dim == 3:
                v_out[b, 2] = 2.0 * vw2 - value[b, 3]
        else:
            v_out[b, 0] = vw0
            v_out[b, 1] = vw1
            if dim == 3:
                v_out[b, 2] = vw2


def _order(order):
    if isinstance(order, bool):
        raise ParameterError(f"order must be 0 (Shepard) or 1 (first-order corrected), got {order!r}")
    try:
        value = float(str(order).strip()) if not isinstance(order, (int, float, np.integer)) else float(order)
    except (TypeError, ValueError):
        raise ParameterError(f"order must be 0 (Shepard) or 1 (first-order corrected), got {order!r}") from None
    if value not in ORDERS:
        raise ParameterError(f"order must be 0 (Shepard) or 1 (first-order corrected), got {order!r}")
    return int(value)


def _det_min(det_min):
    try:
        value = float(det_min)
    except (TypeError, ValueError):
        raise ParameterError(f"det_min must be a positive number, got {det_min!r}") from None
    if not (value > 0.0 and np.isfinite(value)):
        raise ParameterError(f"det_min must be a positive number, got {det_min!r}")
    return value


class ModifiedDynamicBoundary(WallModel):
    """Modified dynamic boundary condition (mDBC) of [English2022].

    Parameters
    ----------
    slip : {"vel0", "noslip"}
        ``vel0``: wall particles move with the wall (original mDBC); ``noslip``:
        v_b = 2 v_w - v_g from the velocity interpolated at the ghost node.
    order : {1, 0}
        1: first-order corrected interpolation at the ghost node and linear
        extrapolation to the wall particle ([LiuLiu2006], [English2022]); 0: the
        Shepard density of the ghost node (no gradient).
    det_min : float
        |det A| of the correction matrix below which the ghost node falls back
        to the Shepard value (default 1e-3).
    clip_negative : bool
        Keep the wall density at or above rho0, so that the wall never pulls on
        the fluid (p_b >= p_background). Off by default: [English2022] does not
        clip; docs/boundaries.md ("mDBC", choice 3) gives what it changes.
    """

    #: pairwise_momentum (see WallModel): the wall particles' state is set in update; the push is
    #: then one symmetric pressure and viscous pair term per wall particle (ghost_forces); central.
    pairwise_momentum = True
    #: DBC particles are ordinary neighbours ([English2022]): continuity, pressure and the fluid's
    #: viscosities act across the wall; no density diffusion (the wall densities carry the
    #: hydrostatic jump across the surface)
    fluid_terms = frozenset({"continuity", "pressure", "artificial_viscosity", "laminar_viscosity",
                             "shifting", "transport_velocity"})
    joins_summation_density = True
    edac_refusal = ("its wall pressure is the equation of state of the fluid density it extrapolates, and with "
                    "EDAC the fluid's density does not set its pressure")

    def __init__(self, *, slip="vel0", order=1, det_min=DET_MIN, clip_negative=False):
        slip = str(slip).strip()
        if slip not in SLIP_MODES:
            raise ParameterError(f"slip must be one of {', '.join(SLIP_MODES)} for mdbc; got {slip!r}")
        self.slip = slip
        self.order = _order(order)
        self.det_min = _det_min(det_min)
        self.clip_negative = bool(clip_negative)
        self.name = "mdbc" if slip == "vel0" else "mdbc-noslip"

    def prepare(self, wall, fluid, physics):
        pa = wall.particles
        if "surface" not in pa or "normal" not in pa:
            raise ParameterError(f"mdbc wall {wall.name!r} needs surface points and normals "
                                 "(build it with seawall.shapes.tank or polyline_wall)")
        n = wall.n
        # x_g - x_b = 2 (s_b - x_b), kept with the particle so a translating wall carries its ghost nodes
        pa["ghost_offset"] = np.ascontiguousarray(mirror_points(pa["surface"], pa["x"]) - pa["x"])
        pa["ghost"] = pa["x"] + pa["ghost_offset"]
        pa["rho"] = np.full(n, physics.rho0)
        pa["p"] = np.full(n, physics.p_background)
        pa["m"] = np.full(n, physics.rho0 * fluid.spacing ** wall.dim)
        pa["v_mdbc"] = pa["v"].copy()
        pa["mdbc_outcome"] = np.zeros(n, dtype=np.int64)

    def update(self, wall, fluid, ctx):
        g = ctx.grid
        pa = wall.particles
        fp = fluid.particles
        noslip = self.slip == "noslip"
        if wall.movement is not None:
            np.add(pa["x"], pa["ghost_offset"], out=pa["ghost"])
        nf = 1 + (wall.dim if noslip else 0)
        fields = np.empty((fp.n, nf))
        fields[:, 0] = fp["rho"]
        if noslip:
            fields[:, 1:] = fp["v"]
        vol = fp["m"] / fp["rho"]
        value = np.empty((wall.n, nf))
        grad = np.empty((wall.n, nf, wall.dim))
        mdbc_wall_state(g.layout, pa["x"], pa["ghost"], pa["v"], fp["x"], fields, vol, ctx.fluid_cells.start,
                        ctx.fluid_cells.order, g.lo, g.inv_cell, g.ncell, g.period, ctx.physics,
                        self.order == 1, self.det_min, noslip, self.clip_negative, value, grad, pa["rho"], pa["p"],
                        pa["v_mdbc"], pa["mdbc_outcome"])

    def interact(self, fluid, wall, ctx, dv, drho):
        # continuity with the wall's own velocity, viscosity with the mirrored one (as the Adami
        # no-slip wall, docs/boundaries.md "mDBC", choice 7); identical for slip="vel0"
        ghost_forces(fluid_view(fluid.particles), wall_view(wall.particles, v="v", v_visc="v_mdbc"),
                     cell_view(ctx.grid, wall.cells, reach=True), ctx.physics, self.cross_terms(ctx.physics),
                     rates_bundle(fluid, ctx, dv, drho))

    def describe(self):
        parts = [f"order {self.order}"]
        if self.det_min != DET_MIN:
            parts.append(f"det_min {self.det_min:g}")
        if self.clip_negative:
            parts.append("wall density clipped at rho0")
        return f"{self.name} ({', '.join(parts)})"


__all__ = ["ModifiedDynamicBoundary", "mdbc_wall_state", "SLIP_MODES", "DET_MIN"]
