"""Particle regularisation: particle shifting and the transport-velocity formulation.

Two options of :class:`~seawall.fluid.FluidSystem` that keep the particles of
a weakly compressible fluid evenly spread (docs/formulas.md, "Particle
regularisation", has the formulas, the derivations and the choices):

* :class:`ParticleShifting` -- after each step every particle moves by
  delta r_i against the gradient of the particle concentration
  C_i = sum_j V_j W_ij, with the free-surface correction (only the tangential
  part of the shift acts at and near a free surface):

  - ``"sun2017"``: delta r_i = -CFL Ma (2h)^2 grad C_i ([Sun2017]), with
    CFL = c0 dt / h of the step and Ma = max_i |v_i| / c0, so
    delta r_i = -4 h U dt grad C_i;
  - ``"lind2012"``: delta r_i = -D grad C_i, D = 0.5 h^2 ([Lind2012]);

  both with grad C_i = sum_j V_j (1 + R (W_ij / W(dx))^n) grad_i W_ij,
  R = 0.2, n = 4 ([Lind2012]; [Sun2017]).
* :class:`TransportVelocity` -- the transport-velocity formulation of
  [Adami2013]: the particles move with v~ = v + dt/2 a_b,
  a_b,i = -(p_b / m_i) sum_j (V_i^2 + V_j^2) grad_i W_ij ([Adami2013]),
  and the momentum equation gains the divergence of A = rho v (x) (v~ - v)
  ([Adami2013]).

The source papers are not among the project's documents; the formulas are
their published forms, cited without equation numbers (docs/formulas.md).

Free surface: lambda_i, the smallest eigenvalue of
B_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij (about the identity in the bulk,
[Marrone2010]), marks the particles at or near a free surface
(lambda_i < ``lambda_surface``); there the shift (or a_b) keeps only its part
orthogonal to n_i = -grad C_i / |grad C_i| ([Sun2017]; [Lind2012]).

Walls: every wall model whose ``fluid_terms`` contain ``"shifting"``
(``"transport_velocity"``) adds its particles, with the volumes m_b / rho0,
to the sums of grad C and B (of a_b and the extra stress).
"""

import math

import numpy as np
from numba import njit, prange

from ..errors import ParameterError, require_nonnegative, require_positive
from ..jit import particle_loop
from ..kernels import kernel_shape
from ..neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from ..pairs import gradient_factor

SHIFTING_KINDS = ("none", "sun2017", "lind2012")


class ParticleShifting:
    """Particle shifting along the concentration gradient, with the free-surface correction.

    Parameters
    ----------
    kind : {"sun2017", "lind2012"}
        ``"sun2017"``: delta r = -CFL Ma (2h)^2 grad C ([Sun2017]);
        ``"lind2012"``: delta r = -D grad C, D = ``coefficient`` h^2 ([Lind2012]).
    coefficient : float, optional
        Lind's D / h^2 (default 0.5, [Lind2012]); Sun's factor in front of CFL Ma h^2
        (default 4, the (2h)^2 of [Sun2017]).
    R, n : float
        The anti-clumping term (1 + R (W / W(dx))^n) of grad C ([Lind2012]), 0.2 and 4.
    free_surface : bool
        Apply the free-surface correction (default True): particles with
        lambda < ``lambda_surface`` shift only tangentially.
    lambda_surface : float
        Threshold on lambda (default 0.75, the upper bound of the free-surface
        region of [Marrone2010]; [Sun2017]).
    """

    def __init__(self, kind="sun2017", *, coefficient=None, R=0.2, n=4.0, free_surface=True,
                 lambda_surface=0.75):
        if kind not in SHIFTING_KINDS[1:]:
            raise ParameterError(f"shifting must be one of {', '.join(SHIFTING_KINDS)}; got {kind!r}")
        self.kind = kind
        default = 4.0 if kind == "sun2017" else 0.5
        self.coefficient = require_positive("shifting_coefficient", default if coefficient is None else coefficient)
        self.R = require_nonnegative("shifting R", R)
        self.n = require_positive("shifting n", n)
        self.free_surface = bool(free_surface)
        self.lambda_surface = require_positive("lambda_surface", lambda_surface)

    def describe(self):
        return {"kind": self.kind, "coefficient": self.coefficient, "R": self.R, "n": self.n,
                "free_surface": self.free_surface, "lambda_surface": self.lambda_surface}

    def __repr__(self):
        return f"ParticleShifting({self.kind!r}, coefficient={self.coefficient}, free_surface={self.free_surface})"


class TransportVelocity:
    """Transport-velocity formulation of [Adami2013].

    Parameters
    ----------
    background_pressure : float
        p_b [Pa] of the advection velocity ([Adami2013]); give it, or
        ``background_factor``.
    background_factor : float
        p_b = factor * rho0 c0^2 (default 1: [Adami2013] takes p_b = p0 = rho0 c0^2 / gamma with gamma = 1
        for the linear EOS).
    free_surface : bool
        Free-surface correction (default False): at and near a free surface
        (lambda < ``lambda_surface``) a_b keeps only its tangential part. A
        case with a free surface refuses the formulation without it.
    lambda_surface : float
        As for :class:`ParticleShifting`.
    """

    def __init__(self, *, background_pressure=None, background_factor=1.0, free_surface=False,
                 lambda_surface=0.75):
        self.background_pressure = None if background_pressure is None else require_nonnegative(
            "tvf_background_pressure", background_pressure)
        self.background_factor = require_nonnegative("tvf_background", background_factor)
        self.free_surface = bool(free_surface)
        self.lambda_surface = require_positive("lambda_surface", lambda_surface)

    def pressure(self, rho0, c0):
        """p_b [Pa] for a fluid of reference density rho0 and sound speed c0."""
        if self.background_pressure is not None:
            return self.background_pressure
        return self.background_factor * rho0 * c0 * c0

    def describe(self, rho0=None, c0=None):
        out = {"background_factor": self.background_factor, "free_surface": self.free_surface,
               "lambda_surface": self.lambda_surface}
        if self.background_pressure is not None:
            out["background_pressure"] = self.background_pressure
        elif rho0 is not None:
            out["background_pressure"] = self.pressure(rho0, c0)
        return out

    def __repr__(self):
        return f"TransportVelocity(p_b={self.background_pressure or str(self.background_factor) + ' rho0 c0^2'})"


def as_shifting(value):
    """A :class:`ParticleShifting` or None from a FluidSystem / CLI value (None, "none", a kind, an object)."""
    if value is None or isinstance(value, ParticleShifting):
        return value
    if isinstance(value, str):
        if value == "none":
            return None
        return ParticleShifting(value)
    raise ParameterError(f"shifting must be one of {', '.join(SHIFTING_KINDS)} or a ParticleShifting; got {value!r}")


def as_transport_velocity(value):
    """A :class:`TransportVelocity` or None from a FluidSystem value (None, False/True, an object)."""
    if value is None or value is False:
        return None
    if value is True:
        return TransportVelocity()
    if isinstance(value, TransportVelocity):
        return value
    raise ParameterError(f"transport_velocity must be True, False or a TransportVelocity; got {value!r}")


# ---------------------------------------------------------------- compiled passes
@particle_loop()
def concentration_sums(layout, x, vol, xb, volb, start_b, order_b, lo, inv_cell, ncell, period, prm, same,
                       R, nexp, inv_w_dx, grad_c, bmat, bg):
    """Sums over the particles b (the fluid itself when ``same``, else a wall) for every fluid particle i:

    * grad_c[i] += sum_b V_b (1 + R (W_ib / W(dx))^n) grad_i W_ib   ([Lind2012]; [Sun2017])
    * bmat[i]   += sum_b V_b (x_b - x_i) (x) grad_i W_ib, as (xx, xy, xz, yy, yz, zz)  ([Marrone2010])
    * bg[i]     += sum_b (V_i^2 + V_b^2) grad_i W_ib                 ([Adami2013])

    With ``same`` the arrays are overwritten (the fluid pass comes first).
    """
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vi2 = vol[i] * vol[i]
        if same:
            c0 = c1 = c2 = 0.0
            b00 = b01 = b02 = b11 = b12 = b22 = 0.0
            s0 = s1 = s2 = 0.0
        else:
            c0, c1, c2 = point_of(grad_c, i, dim)
            s0, s1, s2 = point_of(bg, i, dim)
            b00 = bmat[i, 0]
            b01 = bmat[i, 1]
            b02 = bmat[i, 2]
            b11 = bmat[i, 3]
            b12 = bmat[i, 4]
            b22 = bmat[i, 5]
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_b)
                for k in range(ka, kb):
                    j = order_b[k]
                    if same and j == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, xb, j, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    qq = np.sqrt(r2) * inv_h
                    f = gradient_factor(prm.kernel, gradient_scale, qq)   # grad_i W = f r_ib
                    vj = volb[j]
                    wr = prm.sigma * kernel_shape(prm.kernel, qq) * inv_w_dx
                    t = vj * (1.0 + R * wr ** nexp) * f
                    c0 += t * d0
                    c1 += t * d1
                    c2 += t * d2
                    s = -f * vj          # (x_b - x_i) = -r_ib
                    b00 += s * d0 * d0
                    b01 += s * d0 * d1
                    b02 += s * d0 * d2
                    b11 += s * d1 * d1
                    b12 += s * d1 * d2
                    b22 += s * d2 * d2
                    u = (vi2 + vj * vj) * f
                    s0 += u * d0
                    s1 += u * d1
                    s2 += u * d2
        grad_c[i, 0] = c0
        grad_c[i, 1] = c1
        bg[i, 0] = s0
        bg[i, 1] = s1
        if dim == 3:
            grad_c[i, 2] = c2
            bg[i, 2] = s2
        bmat[i, 0] = b00
        bmat[i, 1] = b01
        bmat[i, 2] = b02
        bmat[i, 3] = b11
        bmat[i, 4] = b12
        bmat[i, 5] = b22


@njit(cache=True, inline="always")
def smallest_eigenvalue(dim, b00, b01, b02, b11, b12, b22):
    """Smallest eigenvalue of the symmetric matrix B (2 x 2 or 3 x 3, closed form)."""
    if dim == 2:
        m = 0.5 * (b00 + b11)
        d = 0.5 * (b00 - b11)
        return m - math.sqrt(d * d + b01 * b01)
    # trigonometric solution of the characteristic cubic of a symmetric 3 x 3 matrix
    p1 = b01 * b01 + b02 * b02 + b12 * b12
    q = (b00 + b11 + b22) / 3.0
    if p1 == 0.0:
        return min(b00, min(b11, b22))
    p2 = (b00 - q) ** 2 + (b11 - q) ** 2 + (b22 - q) ** 2 + 2.0 * p1
    p = math.sqrt(p2 / 6.0)
    c00 = (b00 - q) / p
    c11 = (b11 - q) / p
    c22 = (b22 - q) / p
    c01 = b01 / p
    c02 = b02 / p
    c12 = b12 / p
    r = 0.5 * (c00 * (c11 * c22 - c12 * c12) - c01 * (c01 * c22 - c12 * c02) + c02 * (c01 * c12 - c11 * c02))
    r = min(1.0, max(-1.0, r))
    phi = math.acos(r) / 3.0
    return q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)


@particle_loop()
def surface_lambda(bmat, dim, lam):
    """lambda_i, the smallest eigenvalue of B_i ([Marrone2010]), for every particle."""
    for i in prange(bmat.shape[0]):
        lam[i] = smallest_eigenvalue(dim, bmat[i, 0], bmat[i, 1], bmat[i, 2], bmat[i, 3], bmat[i, 4], bmat[i, 5])


@particle_loop()
def corrected_vectors(vec, grad_c, lam, scale, lambda_surface, surface, out):
    """out_i = scale * vec_i, with its component along n_i = -grad C_i / |grad C_i| removed where
    ``surface`` and lambda_i < ``lambda_surface`` ([Sun2017]; [Lind2012])."""
    dim = vec.shape[1]
    for i in prange(vec.shape[0]):
        a0 = scale * vec[i, 0]
        a1 = scale * vec[i, 1]
        a2 = scale * vec[i, 2] if dim == 3 else 0.0
        if surface and lam[i] < lambda_surface:
            g0 = grad_c[i, 0]
            g1 = grad_c[i, 1]
            g2 = grad_c[i, 2] if dim == 3 else 0.0
            gg = g0 * g0 + g1 * g1 + g2 * g2
            if gg > 0.0:
                proj = (a0 * g0 + a1 * g1 + a2 * g2) / gg
                a0 -= proj * g0
                a1 -= proj * g1
                a2 -= proj * g2
        out[i, 0] = a0
        out[i, 1] = a1
        if dim == 3:
            out[i, 2] = a2


@particle_loop()
def transport_stress(layout, x, v, rho, vol, m, dvt, xb, vb, rhob, volb, dvtb, start_b, order_b, lo, inv_cell,
                     ncell, period, prm, same, dv, drho):
    """The terms the transport velocity adds to the rates of every fluid particle i (b: the fluid itself
    when ``same``, else a wall whose transport correction dvtb is zero):

    * dv_i   += (1/m_i) sum_b (V_i^2 + V_b^2) 1/2 (A_i + A_b) . grad_i W_ib,
      A = rho v (x) (v~ - v), (A . grad W)_a = rho v_a (v~ - v) . grad W      ([Adami2013])
    * drho_i += (v~_i - v_i) . sum_b V_b (rho_b - rho_i) grad_i W_ib  (fluid pairs only): the density
      followed along v~ instead of v (docs/formulas.md).
    """
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vi0, vi1, vi2 = point_of(v, i, dim)
        ti0, ti1, ti2 = point_of(dvt, i, dim)
        rhoi = rho[i]
        voli2 = vol[i] * vol[i]
        a0 = a1 = a2 = 0.0
        g0 = g1 = g2 = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_b)
                for k in range(ka, kb):
                    j = order_b[k]
                    if same and j == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, xb, j, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    f = gradient_factor(prm.kernel, gradient_scale, np.sqrt(r2) * inv_h)
                    vj = volb[j]
                    w = 0.5 * (voli2 + vj * vj) * f     # times r_ib: 1/2 (V_i^2 + V_b^2) grad_i W_ib
                    ai = rhoi * (ti0 * d0 + ti1 * d1 + ti2 * d2) * w
                    a0 += ai * vi0
                    a1 += ai * vi1
                    a2 += ai * vi2
                    if same:
                        vj0, vj1, vj2 = point_of(vb, j, dim)
                        tj0, tj1, tj2 = point_of(dvtb, j, dim)
                        aj = rhob[j] * (tj0 * d0 + tj1 * d1 + tj2 * d2) * w
                        a0 += aj * vj0
                        a1 += aj * vj1
                        a2 += aj * vj2
                        t = vj * (rhob[j] - rhoi) * f
                        g0 += t * d0
                        g1 += t * d1
                        g2 += t * d2
        inv_m = 1.0 / m[i]
        dv[i, 0] += a0 * inv_m
        dv[i, 1] += a1 * inv_m
        if dim == 3:
            dv[i, 2] += a2 * inv_m
        if same:
            drho[i] += ti0 * g0 + ti1 * g1 + ti2 * g2


@njit(cache=True)
def max_speed(v):
    """max_i |v_i|."""
    best = 0.0
    for i in range(v.shape[0]):
        s = 0.0
        for k in range(v.shape[1]):
            s += v[i, k] * v[i, k]
        if s > best:
            best = s
    return math.sqrt(best)
