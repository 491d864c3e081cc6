"""Interpolation of fluid fields at arbitrary points (the mirror points of ghost walls).

[Huang2019] (Huang et al. 2019, sec. 3) compares five ways to evaluate the fluid
state at the interpolation ("mirror") point of a fixed ghost particle. All
five are implemented here as compiled per-point functions that gather over
the fluid's cell list (no neighbour lists, no ghost x fluid matrices), behind
interchangeable description objects:

============================  =====================  ===========================
object                        [Huang2019]               reproduces exactly
============================  =====================  ===========================
``MLS(order=1)``              sec. 3.1, eq. 8-9      linear fields
``MLS(order=2)``              sec. 3.1               quadratic fields
``SFDI()``                    sec. 3.2, eq. 10-13    linear fields
``Normalised()``              sec. 3.3, eq. 14-16    constant fields
``ImprovedShepard()``         sec. 3.4, eq. 17-21    constant fields
============================  =====================  ===========================

Notation: x0 the interpolation point, j the fluid particles with
|x_j - x0| < R (R = the kernel's support radius), W_j = W(|x_j - x0|, h),
V_j = m_j / rho_j. Every method fills ``out[k, :]`` with the interpolated
value of each column of ``fields`` and returns the number of neighbours.
With no neighbour the output is zero and the count 0 (the caller decides).

Choices where the extracted seed text is ambiguous (docs/ghost.md):

* MLS: the basis offsets are scaled by 1/h (x_j - x0)/h, which leaves the
  interpolant unchanged but keeps the moment matrix O(1). Fallback (the seed
  names the failure modes but no remedy): a quadratic fit with fewer than 6
  (2D) / 10 (3D) neighbours or a pivot below ``1e-6 M_00`` drops to the
  linear fit (the leading block of the same moment matrix), a failed linear
  fit drops to the normalised (Shepard) average, i.e. M_00^-1 c_0.
* SFDI: the gradient at the nearest particle i is found from the moments
  A_km = sum_j w_ij e_k e_m / |e|^2, b_m = sum_j w_ij (f_j - f_i) e_m / |e|^2
  (e = x_j - x_i). Ma (2008) as written in sec. 3.2 keeps only the diagonal
  of A (n_{i,xk} = 1 / A_kk); that is exact for linear fields only on
  symmetric neighbour sets. By default the d x d system is solved in closed
  form (no general matrix inverse, exact for linear fields on any
  neighbour set); ``SFDI(diagonal=True)`` is the literal seed form.
* Limiter (MLS and SFDI, on by default, ``limit=False`` to switch off): the
  fitted value is clipped to [min_j f_j, max_j f_j] of the neighbours. A
  mirror point near the free surface sees a one-sided, truncated
  neighbourhood, where a quadratic fit extrapolates wildly: without the
  limiter the hydrostatic tank with MLS-quadratic blew up at t = 0.06 s
  (dx = 0.02 m, Gaussian kernel). Inside the neighbours' hull a linear
  field never leaves that range, so linear reproduction is untouched.
* Improved Shepard: the extracted eq. 20 lost its minus signs and the
  scaling of r. We use the dimensionless q = r / R,
  beta(q) = exp(-q^2 / (1 - q^lambda)) for q < 1 and 0 otherwise, which is
  1 at q = 0 and vanishes with all derivatives at q = 1 (r = R), and
  phi = beta(q) / q, weights phi^mu / sum phi^mu with mu = 4. The weights
  already sum to one, so the V_j of the extracted eq. 21 is not applied (it
  would scale the pressure by V_j). A weight below ``SHEPARD_WEIGHT_FLOOR``
  (1e-290; q > 0.99702 for the defaults) counts as outside the support: near
  q = 1 the weight underflows to a subnormal number, and a mirror point whose
  only neighbour sat there got 1 / sum w = inf, i.e. an infinite ghost
  pressure (the non-finite particles of the ghost-shepard dam break). Beside
  any neighbour of normal weight such a weight changes no digit of the result.
"""

import math

import numpy as np
from numba import njit, prange

from ..errors import ParameterError, require_positive
from ..jit import loop_helper, particle_loop
from ..kernels import kernel_gradient_factor, kernel_shape
from ..neighbors import cell_index, minimum_image, neighbour_range, point_of, tag_dim, tag_periodic, separation

MLS_LINEAR = 0
MLS_QUADRATIC = 1
SFDI_KIND = 2
NORMALISED = 3
IMPROVED_SHEPARD = 4

#: relative pivot below which a moment matrix counts as singular
PIVOT_TOL = 1e-6
#: improved Shepard weights below this count as zero (their reciprocal would overflow; module doc)
SHEPARD_WEIGHT_FLOOR = 1e-290


# ---------------------------------------------------------------- helpers
@loop_helper
def shepard_beta(q, lam):
    """beta(q) = exp(-q^2 / (1 - q^lambda)) for 0 <= q < 1, else 0 ([Huang2019] eq. 20, q = r/R)."""
    if q >= 1.0:
        return 0.0
    return math.exp(-q * q / (1.0 - q ** lam))


@loop_helper
def shepard_weight_q2(q2, mu, lam):
    """phi^mu from q^2: (beta/q)^mu = exp(-mu q^2 / (1 - q^lambda)) q^-mu, one exp and
    (for the defaults lambda = 2, mu = 4) no pow."""
    if q2 >= 1.0:
        return 0.0
    ql = q2 if lam == 2.0 else q2 ** (0.5 * lam)
    qm = q2 * q2 if mu == 4.0 else q2 ** (0.5 * mu)
    return math.exp(-mu * q2 / (1.0 - ql)) / qm


@loop_helper
def shepard_weight(q, mu, lam):
    """Unnormalised improved Shepard weight phi(q)^mu, phi = beta(q)/q ([Huang2019] eq. 19-20)."""
    return shepard_weight_q2(q * q, mu, lam)


@njit(cache=True)
def solve_first_column(M, m, a):
    """Solve M[:m, :m] a = e_1 by Gaussian elimination with partial pivoting.

    Returns False (a untouched) when a pivot falls below PIVOT_TOL * M[0, 0].
    """
    A = np.empty((m, m + 1))
    for r in range(m):
        for c in range(m):
            A[r, c] = M[r, c]
        A[r, m] = 1.0 if r == 0 else 0.0
    scale = M[0, 0]
    if not scale > 0.0:
        return False
    tol = PIVOT_TOL * scale
    for col in range(m):
        piv = col
        best = abs(A[col, col])
        for r in range(col + 1, m):
            v = abs(A[r, col])
            if v > best:
                best = v
                piv = r
        if not best > tol:
            return False
        if piv != col:
            for c in range(col, m + 1):
                t = A[col, c]
                A[col, c] = A[piv, c]
                A[piv, c] = t
        inv = 1.0 / A[col, col]
        for r in range(col + 1, m):
            fct = A[r, col] * inv
            if fct != 0.0:
                for c in range(col, m + 1):
                    A[r, c] -= fct * A[col, c]
    for r in range(m - 1, -1, -1):
        s = A[r, m]
        for c in range(r + 1, m):
            s -= A[r, c] * a[c]
        a[r] = s / A[r, r]
    return True


# ---------------------------------------------------------------- per-point methods
@njit(cache=True)
def normalised_point(layout, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell, period, prm, out, k):
    """Normalised (corrected-kernel) interpolation, [Huang2019] sec. 3.3 eq. 14-16:

        f(x0) = sum_j f_j W_j V_j / sum_j W_j V_j
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = fields.shape[1]
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    for q in range(nf):
        out[k, q] = 0.0
    sw = 0.0
    cnt = 0
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                if r2 >= prm.support2:
                    continue
                w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h) * vol[j]
                if w <= 0.0:
                    continue
                sw += w
                cnt += 1
                for q in range(nf):
                    out[k, q] += w * fields[j, q]
    if sw > 0.0:
        inv = 1.0 / sw
        for q in range(nf):
            out[k, q] *= inv
    return cnt


@njit(cache=True)
def improved_shepard_point(layout, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell, period, prm,
                           mu, lam, out, k):
    """Improved Shepard interpolation, [Huang2019] sec. 3.4 eq. 17-21:

        f(x0) = sum_j phi_j^mu f_j / sum_j phi_j^mu,  phi_j = beta(r_j / R) / (r_j / R),
        beta(q) = exp(-q^2 / (1 - q^lambda)) (q < 1), 0 otherwise;
        f(x0) = f_j when x0 coincides with a particle j (eq. 17, r_j = 0).
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = fields.shape[1]
    inv_r2 = 1.0 / prm.support2
    nrows = 25 if dim == 3 else 5
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    for q in range(nf):
        out[k, q] = 0.0
    sw = 0.0
    cnt = 0
    hit = -1
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                if r2 >= prm.support2:
                    continue
                q2 = r2 * inv_r2
                if q2 < 1e-18:
                    hit = j
                    continue
                w = shepard_weight_q2(q2, mu, lam)
                if w < SHEPARD_WEIGHT_FLOOR:
                    continue   # underflowing weight: as outside the support (module doc)
                sw += w
                cnt += 1
                for q in range(nf):
                    out[k, q] += w * fields[j, q]
    if hit >= 0:
        for q in range(nf):
            out[k, q] = fields[hit, q]
        return cnt + 1
    if sw > 0.0:
        inv = 1.0 / sw
        for q in range(nf):
            out[k, q] *= inv
    return cnt


@njit(cache=True)
def mls_point(layout, quadratic, limit, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell, period,
              prm, out, k):
    """Moving least squares, [Huang2019] sec. 3.1 eq. 8-9 (Colagrossi & Landrini 2003):

        f(x0) = sum_j f_j W^MLS_j V_j,  W^MLS_j = (M^-1 e_1) . b_j W_j,
        M = sum_j b_j b_j^T W_j V_j,  b_j = [1, (x_j - x0)/h, ...] (+ quadratic terms).

    Written as f(x0) = a . c with M a = e_1 and c = sum_j b_j W_j V_j f_j,
    so one pass over the neighbours suffices. Fallback quadratic -> linear
    -> normalised when the fit is under-determined or singular.
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = fields.shape[1]
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    m1 = dim + 1
    if quadratic:
        m = 6 if dim == 2 else 10
    else:
        m = m1
    M = np.zeros((m, m))
    c = np.zeros((nf, m))
    b = np.empty(m)
    a = np.zeros(m)
    fmin = np.full(nf, np.inf)
    fmax = np.full(nf, -np.inf)
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    cnt = 0
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                if r2 >= prm.support2:
                    continue
                w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h) * vol[j]
                if w <= 0.0:
                    continue
                cnt += 1
                e0 = -d0 * inv_h
                e1 = -d1 * inv_h
                e2 = -d2 * inv_h
                b[0] = 1.0
                b[1] = e0
                b[2] = e1
                if dim == 3:
                    b[3] = e2
                if quadratic:
                    if dim == 2:
                        b[3] = e0 * e0
                        b[4] = e0 * e1
                        b[5] = e1 * e1
                    else:
                        b[4] = e0 * e0
                        b[5] = e0 * e1
                        b[6] = e0 * e2
                        b[7] = e1 * e1
                        b[8] = e1 * e2
                        b[9] = e2 * e2
                for r in range(m):
                    wr = w * b[r]
                    for s in range(r, m):
                        M[r, s] += wr * b[s]
                    for q in range(nf):
                        c[q, r] += wr * fields[j, q]
                if limit:
                    for q in range(nf):
                        fq = fields[j, q]
                        if fq < fmin[q]:
                            fmin[q] = fq
                        if fq > fmax[q]:
                            fmax[q] = fq
    for q in range(nf):
        out[k, q] = 0.0
    if cnt == 0:
        return 0
    for r in range(m):
        for s in range(r):
            M[r, s] = M[s, r]
    used = 0
    if quadratic and cnt >= m and solve_first_column(M, m, a):
        used = m
    elif cnt >= m1 and solve_first_column(M, m1, a):
        used = m1
    if used > 0:
        for q in range(nf):
            s = 0.0
            for r in range(used):
                s += a[r] * c[q, r]
            if limit:
                s = min(max(s, fmin[q]), fmax[q])
            out[k, q] = s
    else:
        inv = 1.0 / M[0, 0]
        for q in range(nf):
            out[k, q] = c[q, 0] * inv
    return cnt


@njit(cache=True)
def sfdi_point(layout, diagonal, limit, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell, period, prm,
               out, k):
    """Simplified finite difference interpolation, [Huang2019] sec. 3.2 eq. 10-13 (Ma 2008):

        f(x0) = sum_j w_j f_j / sum_j w_j - grad f(x_i) . R_0,
        R_0 = sum_j (x_j - x0) w_j / sum_j w_j,   w_j = W(|x_j - x0|),

    i the fluid particle nearest to x0; this is sum_j Phi_j f_j with the
    shape functions Phi_j of eq. 11. grad f(x_i) from the simplified finite
    difference A g = b, A_km = sum_{j != i} w_ij e_k e_m / |e|^2,
    b_m = sum_{j != i} w_ij (f_j - f_i) e_m / |e|^2, e = x_j - x_i, over the
    neighbours of x_i. ``diagonal`` keeps only A_kk (n_{i,xk} = 1/A_kk of the
    seed); otherwise the d x d system is solved by Cramer's rule. Where A is
    singular (too few neighbours) the gradient is dropped (Shepard average).
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = fields.shape[1]
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    for q in range(nf):
        out[k, q] = 0.0
    sw = 0.0
    r00 = r01 = r02 = 0.0
    cnt = 0
    near = -1
    near_r2 = 1e300
    fmin = np.full(nf, np.inf)
    fmax = np.full(nf, -np.inf)
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                if r2 >= prm.support2:
                    continue
                w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                if w <= 0.0:
                    continue
                if r2 < near_r2:
                    near_r2 = r2
                    near = j
                sw += w
                cnt += 1
                r00 -= w * d0
                r01 -= w * d1
                r02 -= w * d2
                for q in range(nf):
                    fq = fields[j, q]
                    out[k, q] += w * fq
                    if fq < fmin[q]:
                        fmin[q] = fq
                    if fq > fmax[q]:
                        fmax[q] = fq
    if cnt == 0:
        return 0
    inv = 1.0 / sw
    r00 *= inv
    r01 *= inv
    r02 *= inv
    for q in range(nf):
        out[k, q] *= inv
    if cnt < dim + 1:
        return cnt
    # second pass: simplified finite-difference gradient at the nearest particle
    s0, s1, s2 = point_of(xf, near, dim)
    cx, cy, cz = cell_index(s0, s1, s2, lo, inv_cell, ncell)
    a00 = a01 = a02 = a11 = a12 = a22 = 0.0
    g = np.zeros((nf, 3))
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                if j == near:
                    continue
                q0, q1, q2 = point_of(xf, j, dim)
                e0 = -(minimum_image(s0 - q0, period[0]) if periodic else s0 - q0)
                e1 = -(minimum_image(s1 - q1, period[1]) if periodic else s1 - q1)
                e2 = -(minimum_image(s2 - q2, period[2]) if periodic else s2 - q2)
                r2 = e0 * e0 + e1 * e1 + e2 * e2
                if r2 >= prm.support2 or r2 == 0.0:
                    continue
                w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h) / r2
                if w <= 0.0:
                    continue
                a00 += w * e0 * e0
                a01 += w * e0 * e1
                a02 += w * e0 * e2
                a11 += w * e1 * e1
                a12 += w * e1 * e2
                a22 += w * e2 * e2
                for q in range(nf):
                    df = w * (fields[j, q] - fields[near, q])
                    g[q, 0] += df * e0
                    g[q, 1] += df * e1
                    g[q, 2] += df * e2
    trace = a00 + a11 + a22
    if not trace > 0.0:
        return cnt
    if diagonal:
        if a00 <= PIVOT_TOL * trace or a11 <= PIVOT_TOL * trace or (dim == 3 and a22 <= PIVOT_TOL * trace):
            return cnt
        for q in range(nf):
            corr = g[q, 0] / a00 * r00 + g[q, 1] / a11 * r01
            if dim == 3:
                corr += g[q, 2] / a22 * r02
            out[k, q] -= corr
            if limit:
                out[k, q] = min(max(out[k, q], fmin[q]), fmax[q])
        return cnt
    if dim == 2:
        det = a00 * a11 - a01 * a01
        if not det > PIVOT_TOL * trace * trace:
            return cnt
        for q in range(nf):
            gx = (a11 * g[q, 0] - a01 * g[q, 1]) / det
            gy = (-a01 * g[q, 0] + a00 * g[q, 1]) / det
            out[k, q] -= gx * r00 + gy * r01
            if limit:
                out[k, q] = min(max(out[k, q], fmin[q]), fmax[q])
    else:
        c00 = a11 * a22 - a12 * a12
        c01 = a02 * a12 - a01 * a22
        c02 = a01 * a12 - a02 * a11
        det = a00 * c00 + a01 * c01 + a02 * c02
        if not det > PIVOT_TOL * trace * trace * trace:
            return cnt
        c11 = a00 * a22 - a02 * a02
        c12 = a01 * a02 - a00 * a12
        c22 = a00 * a11 - a01 * a01
        for q in range(nf):
            gx = (c00 * g[q, 0] + c01 * g[q, 1] + c02 * g[q, 2]) / det
            gy = (c01 * g[q, 0] + c11 * g[q, 1] + c12 * g[q, 2]) / det
            gz = (c02 * g[q, 0] + c12 * g[q, 1] + c22 * g[q, 2]) / det
            out[k, q] -= gx * r00 + gy * r01 + gz * r02
            if limit:
                out[k, q] = min(max(out[k, q], fmin[q]), fmax[q])
    return cnt


#: corrected_point outcomes
CORRECTED_NONE = 0       # no fluid neighbour
CORRECTED_SHEPARD = 1    # zeroth order (Shepard) value, gradient 0
CORRECTED_LINEAR = 2     # first-order corrected value and gradient


@njit(cache=True)
def solve_with_determinant(A, B, m, nrhs):
    """Solve A[:m, :m] X = B[:m, :nrhs] in place (X in B) by Gaussian elimination with partial pivoting.

    Returns det A (0 when a pivot is exactly zero; B is then unusable). A is overwritten.
    """
    det = 1.0
    for col in range(m):
        piv = col
        best = abs(A[col, col])
        for r in range(col + 1, m):
            v = abs(A[r, col])
            if v > best:
                best = v
                piv = r
        if best == 0.0:
            return 0.0
        if piv != col:
            det = -det
            for c in range(m):
                t = A[col, c]
                A[col, c] = A[piv, c]
                A[piv, c] = t
            for c in range(nrhs):
                t = B[col, c]
                B[col, c] = B[piv, c]
                B[piv, c] = t
        det *= A[col, col]
        inv = 1.0 / A[col, col]
        for r in range(col + 1, m):
            fct = A[r, col] * inv
            if fct != 0.0:
                for c in range(col, m):
                    A[r, c] -= fct * A[col, c]
                for c in range(nrhs):
                    B[r, c] -= fct * B[col, c]
    for r in range(m - 1, -1, -1):
        for c in range(nrhs):
            s = B[r, c]
            for q in range(r + 1, m):
                s -= A[r, q] * B[q, c]
            B[r, c] = s / A[r, r]
    return det


@njit(cache=True)
def corrected_point(layout, first_order, det_min, clip_from, p0, p1, p2, xf, fields, vol, start, order, lo,
                    inv_cell, ncell, period, prm, value, grad, k):
    """First-order kernel-corrected SPH interpolation of ``fields`` and their gradients at x0 ([LiuLiu2006]
    sec. 3, the corrective scheme that [English2022] sec. 2 uses at the mDBC ghost nodes).

    A Taylor expansion f_j = f_0 + (x_j - x0) . g, multiplied by V_j W_j and by V_j grad_0 W_j and summed
    over the fluid neighbours j, gives the (d+1) x (d+1) system

        [ sum V W          sum V W (x_j - x0)^T          ] [f_0]   [ sum V_j f_j W_j       ]
        [ sum V grad_0 W   sum V grad_0 W (x_j - x0)^T   ] [ g ] = [ sum V_j f_j grad_0 W_j ]

    (grad_0 W_j = dW/dx0, W the fluid's kernel). Its solution reproduces linear fields exactly. The
    matrix is dimensionless in its determinant (rows 2.. scale as 1/L, columns 2.. as L), ~1 in a full
    neighbourhood; when |det| < ``det_min`` (or ``first_order`` is False) the value falls back to the
    Shepard average sum V f W / sum V W with zero gradient ([English2022]: zeroth order where the matrix
    is ill-conditioned). Columns q >= ``clip_from`` are limited to the neighbours' range
    [min_j f_j, max_j f_j] after a first-order solve (the limiter of the MLS and SFDI fits above; a
    value at x0 inside the neighbours' hull of a linear field is never clipped). Writes ``value[k, q]`` and ``grad[k, q, :]``; returns (neighbour count,
    outcome: CORRECTED_NONE / CORRECTED_SHEPARD / CORRECTED_LINEAR).
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    nf = fields.shape[1]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    nrows = 25 if dim == 3 else 5
    m = dim + 1
    A = np.zeros((m, m))
    B = np.zeros((m, nf))
    e = np.zeros(3)
    gw = np.zeros(3)
    fmin = np.full(nf, np.inf)
    fmax = np.full(nf, -np.inf)
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    cnt = 0
    for row in range(nrows):
        for part in range(2):
            ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                if r2 >= prm.support2:
                    continue
                q = np.sqrt(r2) * inv_h
                vw = prm.sigma * kernel_shape(prm.kernel, q) * vol[j]
                if vw <= 0.0:
                    continue
                cnt += 1
                # d = x0 - x_j: e = x_j - x0 = -d, grad_0 W_j = F d
                fv = gradient_scale * kernel_gradient_factor(prm.kernel, q) * vol[j] if r2 > 0.0 else 0.0
                e[0] = -d0
                e[1] = -d1
                e[2] = -d2
                gw[0] = fv * d0
                gw[1] = fv * d1
                gw[2] = fv * d2
                A[0, 0] += vw
                for c in range(dim):
                    A[0, 1 + c] += vw * e[c]
                for a in range(dim):
                    A[1 + a, 0] += gw[a]
                    for c in range(dim):
                        A[1 + a, 1 + c] += gw[a] * e[c]
                for qf in range(nf):
                    fj = fields[j, qf]
                    B[0, qf] += vw * fj
                    for a in range(dim):
                        B[1 + a, qf] += gw[a] * fj
                    if qf >= clip_from:
                        if fj < fmin[qf]:
                            fmin[qf] = fj
                        if fj > fmax[qf]:
                            fmax[qf] = fj
    for qf in range(nf):
        value[k, qf] = 0.0
        for a in range(grad.shape[2]):
            grad[k, qf, a] = 0.0
    if cnt == 0:
        return 0, CORRECTED_NONE
    shep = A[0, 0]
    if first_order:
        S = B.copy()
        det = solve_with_determinant(A.copy(), S, m, nf)
        if abs(det) >= det_min:
            for qf in range(nf):
                fv0 = S[0, qf]
                if qf >= clip_from:
                    fv0 = min(max(fv0, fmin[qf]), fmax[qf])
                value[k, qf] = fv0
                for a in range(dim):
                    grad[k, qf, a] = S[1 + a, qf]
            return cnt, CORRECTED_LINEAR
    for qf in range(nf):
        value[k, qf] = B[0, qf] / shep
    return cnt, CORRECTED_SHEPARD


@particle_loop()
def interpolate_points(layout, kind, mu, lam, flag, points, xf, fields, vol, start, order, lo, inv_cell, ncell,
                       period, prm, out, count):
    """Interpolate every column of ``fields`` at every row of ``points`` (one thread per point)."""
    for k in prange(points.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        p0, p1, p2 = point_of(points, k, dim)
        limit = (flag & 2) != 0
        if kind == MLS_LINEAR:
            cnt = mls_point(layout, False, limit, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell,
                            period, prm, out, k)
        elif kind == MLS_QUADRATIC:
            cnt = mls_point(layout, True, limit, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell,
                            period, prm, out, k)
        elif kind == SFDI_KIND:
            cnt = sfdi_point(layout, (flag & 1) != 0, limit, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell,
                             period, prm, out, k)
        elif kind == NORMALISED:
            cnt = normalised_point(layout, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell, ncell,
                                   period, prm, out, k)
        else:
            cnt = improved_shepard_point(layout, p0, p1, p2, xf, fields, vol, start, order, lo, inv_cell,
                                         ncell, period, prm, mu, lam, out, k)
        count[k] = cnt


# ---------------------------------------------------------------- description objects
class Interpolation:
    """Base class: an interpolation of fluid fields at points, compiled down to (kind, mu, lam, flag)."""

    kind = -1
    name = "interpolation"
    #: highest polynomial degree reproduced exactly
    degree = 0

    #: clip fitted values to the neighbours' range (MLS and SFDI only)
    limit = False

    def compiled(self):
        """(kind, mu, lam, flags) passed to :func:`interpolate_points`; flags: 1 SFDI diagonal, 2 limiter."""
        return self.kind, 4.0, 2.0, 2 if self.limit else 0

    def interpolate(self, points, grid, cells, xf, fields, vol, physics, out=None, count=None):
        """Interpolate ``fields`` (N_f, n) known at ``xf`` (with volumes ``vol``) at ``points``.

        ``cells`` is the cell list of ``xf`` on ``grid``; returns (values, neighbour counts).
        """
        points = np.ascontiguousarray(points, dtype=np.float64)
        fields = np.ascontiguousarray(fields, dtype=np.float64)
        if fields.ndim == 1:
            fields = fields[:, None]
        npt = points.shape[0]
        if out is None:
            out = np.zeros((npt, fields.shape[1]))
        if count is None:
            count = np.zeros(npt, dtype=np.int64)
        kind, mu, lam, flag = self.compiled()
        interpolate_points(grid.layout, kind, mu, lam, flag, points, xf, fields, vol, cells.start, cells.order,
                           grid.lo, grid.inv_cell, grid.ncell, grid.period, physics, out, count)
        return out, count

    def __repr__(self):
        return f"{type(self).__name__}()"


class MLS(Interpolation):
    """Moving least squares with a linear (``order=1``) or quadratic (``order=2``) basis ([Huang2019] sec. 3.1)."""

    def __init__(self, order=1, limit=True):
        self.limit = bool(limit)
        if order not in (1, 2):
            raise ParameterError(f"MLS order must be 1 or 2, got {order!r}")
        self.order = int(order)
        self.kind = MLS_LINEAR if order == 1 else MLS_QUADRATIC
        self.degree = self.order
        self.name = f"mls{self.order}"

    def __repr__(self):
        return f"MLS(order={self.order}, limit={self.limit})"


class SFDI(Interpolation):
    """Simplified finite difference interpolation ([Huang2019] sec. 3.2, Ma 2008).

    ``diagonal=True`` is the literal form of the seed (diagonal normalisation
    n_{i,xk}); the default solves the d x d gradient system and is exact for
    linear fields on irregular neighbour sets.
    """

    kind = SFDI_KIND
    name = "sfdi"
    degree = 1

    def __init__(self, diagonal=False, limit=True):
        self.diagonal = bool(diagonal)
        self.limit = bool(limit)

    def compiled(self):
        return self.kind, 4.0, 2.0, (1 if self.diagonal else 0) | (2 if self.limit else 0)

    def __repr__(self):
        return f"SFDI(diagonal={self.diagonal}, limit={self.limit})"


class Normalised(Interpolation):
    """Normalised kernel (Shepard) interpolation sum f W V / sum W V ([Huang2019] sec. 3.3)."""

    kind = NORMALISED
    name = "normalized"
    degree = 0


class ImprovedShepard(Interpolation):
    """Improved Shepard interpolation ([Huang2019] sec. 3.4), compactly supported on the kernel support R.

    Parameters
    ----------
    mu : float
        Power parameter, 4 in [Huang2019] (continuity of the weights' derivatives).
    lam : float
        Adjustment index lambda of beta(q) = exp(-q^2 / (1 - q^lambda)); the
        seed gives no value, default 2 (larger lambda: flatter, sharper cut).
    """

    kind = IMPROVED_SHEPARD
    name = "shepard"
    degree = 0

    def __init__(self, mu=4.0, lam=2.0):
        self.mu = require_positive("mu", mu)
        self.lam = require_positive("lam", lam)

    def compiled(self):
        return self.kind, self.mu, self.lam, 0

    def weights(self, r, R):
        """Normalised weights of neighbours at distances ``r`` for support ``R`` (numpy, for inspection)."""
        q = np.asarray(r, dtype=np.float64) / R
        w = np.array([shepard_weight(float(x), self.mu, self.lam) if x > 0 else np.inf for x in q])
        w[w < SHEPARD_WEIGHT_FLOOR] = 0.0
        if np.isinf(w).any():
            return np.where(np.isinf(w), 1.0, 0.0) / np.isinf(w).sum()
        s = w.sum()
        return w / s if s > 0 else w

    def __repr__(self):
        return f"ImprovedShepard(mu={self.mu}, lam={self.lam})"


INTERPOLATIONS = {
    "mls1": lambda: MLS(1),
    "mls2": lambda: MLS(2),
    "sfdi": SFDI,
    "normalized": Normalised,
    "shepard": ImprovedShepard,
}
