"""Entropically damped artificial compressibility (EDAC): pressure as a particle variable.

[Ramachandran2019] (Ramachandran & Puri 2019, sec. 3) replace the equation of
state p(rho) of weakly compressible SPH by an evolution equation for the pressure,

    dp/dt = -rho c^2 div(v) + nu_edac lap(p),     nu_edac = alpha h c / 8,  alpha = 0.5,

the damping term coming from the entropy argument of their paper. The density
no longer sets the pressure: it is kept (by the fluid's own density mode,
continuity or summation) only for the volumes m / rho and the 1 / rho of the
momentum equation. The pair terms are :func:`seawall.pairs.edac_divergence` and
:func:`seawall.pairs.edac_diffusion`; the fluid loop sums them over fluid pairs
(``fluid.rates.fluid_rates``), and the simulation adds the walls' share:

* divergence: c0^2 times what the wall model added to the continuity rate (the
  model's own velocity rule, free or no slip, is kept; the wall's density
  stands in for the fluid particle's, a difference of order Ma^2);
* damping: :func:`edac_wall_diffusion` over the walls whose particles carry a
  pressure (layered models declaring the pressure term), with the wall pressure
  the model set in ``update`` and the volume m_b / rho_b.

With the transport velocity ([Adami2013]) the particles move with v~, and the
pressure is followed along v~: dp_i/dt gains (v~_i - v_i) . grad p_i
([Ramachandran2019] sec. 3, the EDAC-TVF pressure equation), summed by
:func:`edac_pressure_advection` over the fluid and over the same walls as the
damping term (wall pressure from ``update``, volume m_b / rho_b).

Choices and their tests are in docs/formulas.md ("EDAC").
"""

import numpy as np
from numba import prange

from ..errors import ParameterError, require_positive
from ..jit import particle_loop
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..pairs import edac_diffusion, edac_pressure_advection, gradient_factor

#: the values of the ``pressure`` option: the equation of state of the density, or EDAC
PRESSURE_MODELS = ("eos", "edac")


class EDAC:
    """The EDAC pressure equation of [Ramachandran2019] (sec. 3) as the fluid's pressure model.

    Parameters
    ----------
    alpha : float
        Damping coefficient of nu_edac = alpha h c0 / 8; 0.5 in [Ramachandran2019].
    """

    kind = "edac"

    def __init__(self, *, alpha=0.5):
        self.alpha = require_positive("edac_alpha", alpha)

    def viscosity(self, h, c0):
        """nu_edac = alpha h c0 / 8 [m^2/s] ([Ramachandran2019] sec. 3)."""
        return self.alpha * h * c0 / 8.0

    def __repr__(self):
        return f"EDAC(alpha={self.alpha})"


def as_pressure_model(value):
    """None (the equation of state) or an :class:`EDAC` from None, "eos", "edac" or an EDAC."""
    if value is None or isinstance(value, EDAC):
        return value
    if isinstance(value, str):
        name = value.strip().lower()
        if name == "eos":
            return None
        if name == "edac":
            return EDAC()
    raise ParameterError(f"pressure_model must be one of {', '.join(PRESSURE_MODELS)} (or seawall.fluid.EDAC); "
                         f"got {value!r}")


@particle_loop()
def edac_state(rho, m, p, c0, c, p_over_rho2, volume):
    """What :func:`seawall.fluid.rates.equation_of_state` stores, for a fluid whose pressure ``p`` is
    its own variable: c = c0 (the artificial sound speed of [Ramachandran2019]), p / rho^2 and m / rho.
    ``p`` is read, never written."""
    for i in prange(rho.shape[0]):
        r = rho[i]
        c[i] = c0
        p_over_rho2[i] = p[i] / (r * r)
        volume[i] = m[i] / r


@particle_loop()
def edac_wall_diffusion(layout, x, m, volume, rho, p, xw, volw, rhow, pw, start_w, order_w, lo, inv_cell, ncell,
                        period, prm, dp):
    """Adds the damping term nu_edac lap(p) over one wall's particles to the fluid's dp/dt
    ([Ramachandran2019] sec. 3, :func:`seawall.pairs.edac_diffusion` with the wall particle's pressure
    ``pw``, density ``rhow`` and volume ``volw``)."""
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    nu = prm.edac_nu
    eta2 = prm.eta2
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body: a constant there (docs/architecture.md)
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vol_i = volume[i]
        inv_m = 1.0 / m[i]
        rho_i = rho[i]
        p_i = p[i]
        acc = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_w)
                for k in range(ka, kb):
                    b = order_w[k]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xw, b, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    f = gradient_factor(prm.kernel, gradient_scale, np.sqrt(r2) * inv_h)
                    acc += edac_diffusion(vol_i, volw[b], inv_m, rho_i, rhow[b], nu, p_i, pw[b], f, r2, eta2)
        dp[i] += acc


@particle_loop()
def edac_pressure_advection_rates(layout, x, p, dvt, xb, volb, pb, start_b, order_b, lo, inv_cell, ncell, period,
                                  prm, same, dp):
    """Adds (v~_i - v_i) . grad p_i to the fluid's dp/dt, the pressure followed along the transport
    velocity ([Ramachandran2019] sec. 3, EDAC-TVF; :func:`seawall.pairs.edac_pressure_advection`):

        dp_i/dt += (v~_i - v_i) . sum_b V_b (p_b - p_i) grad_i W_ib.

    b is the fluid itself when ``same`` (V_b = m_b / rho_b), else one wall's particles with the pressure
    ``pb`` its model set in ``update`` and the volume ``volb`` = m_b / rho_b (the damping term's, see
    :func:`edac_wall_diffusion`). ``dvt`` is v~ - v of the fluid particles."""
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body: a constant there (docs/architecture.md)
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        t0, t1, t2 = point_of(dvt, i, dim)
        if t0 == 0.0 and t1 == 0.0 and t2 == 0.0:
            continue            # v~ = v (the first evaluation, dt = 0): nothing to add
        p_i = p[i]
        acc = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_b)
                for k in range(ka, kb):
                    b = order_b[k]
                    if same and b == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, xb, b, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    f = gradient_factor(prm.kernel, gradient_scale, np.sqrt(r2) * inv_h)
                    acc += edac_pressure_advection(volb[b], p_i, pb[b], f, t0 * d0 + t1 * d1 + t2 * d2)
        dp[i] += acc
