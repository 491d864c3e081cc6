"""Compiled fluid-fluid loops: equation of state, density and momentum rates.

Each fluid particle gathers over its neighbours (no atomics, no races), so
the loops run in parallel with ``prange``. Formulas and their sources:

* continuity: drho_i/dt = sum_j m_j v_ij . grad_i W_ij            ([Li2022], eq. 8)
* summation:  rho_i = sum_j m_j W_ij                               ([Li2022], eq. 7)
* momentum:   dv_i/dt = -sum_j m_j (p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij) grad_i W_ij + g
                                                                   ([Li2022], eq. 5)
* artificial viscosity Pi_ij = (-alpha c_ij mu_ij + beta mu_ij^2)/rho_ij, for
  v_ij . r_ij < 0, mu_ij = h v_ij . r_ij / (r_ij^2 + eta^2)         ([Li2022], eq. 6)
  or for every pair when ``prm.alpha_all_pairs``                    ([Huang2019], eq. 5)
* laminar viscosity: + sum_j m_j (mu_i + mu_j)/(rho_i rho_j) v_ij (r_ij . grad_i W_ij)/(r_ij^2 + eta^2),
  with dynamic viscosity mu = rho nu                               ([Liu2015], eq. 9)
* density diffusion: + delta h c0 sum_j (m_j/rho_j) psi_ij . grad_i W_ij  ([Liu2015], eq. 12)
  psi_ij = 2 (rho_j - rho_i) r_ji / |r_ji|^2                       (Molteni & Colagrossi 2009)
  psi_ij -= (<grad rho>_i^L + <grad rho>_j^L)                       ([Liu2015], eq. 13; [Huang2019] sec. 2.1)
  The extracted eq. 13 of [Liu2015] reads 2(rho_i - rho_j) r_ij, which is the
  same vector (both factors change sign); see docs/formulas.md.
* renormalised gradient <grad rho>_i^L = L_i sum_j V_j (rho_j - rho_i) grad_i W_ij,
  L_i = [sum_j V_j grad_i W_ij (x) (x_j - x_i)]^-1                  ([Liu2015], eq. 14-15)
* tensile correction: f_ten = (R_i + R_j) (W_ij / W(dx))^4, R_k = eps p_k / rho_k^2,
  eps = 0.01 for p_k > 0 and -0.2 otherwise                         ([Li2022], eq. 20;
  the extracted text lost the square of rho_k, restored from Monaghan 2000)
* Riemann formulation (``prm.riemann``, [Zhang2017] sec. 3): the continuity and pressure terms
  above are replaced by drho_i/dt = 2 rho_i sum_j V_j (v_i - v*) . grad_i W_ij and
  dv_i/dt = -sum_j 2 m_j P*/(rho_i rho_j) grad_i W_ij, v* and P* of the linearised pair
  Riemann problem with the low-dissipation limiter (seawall.pairs.riemann_*)
* XSPH: dx_i/dt = v_i + eps sum_j (m_j / rho_ij) (v_j - v_i) W_ij   ([Li2022], eq. 10;
  the extracted text lost the sign of v_ij, restored from Monaghan 1989)
* EDAC pressure (``prm.edac``, [Ramachandran2019] sec. 3): dp_i/dt = c0^2 rho_i sum_j V_j v_ij . grad_i W_ij
  + (1/m_i) sum_j (V_i^2 + V_j^2) eta_ij (p_i - p_j) (r_ij . grad_i W_ij)/(r_ij^2 + eta^2),
  eta_ij = 2 eta_i eta_j / (eta_i + eta_j), eta = rho nu_edac (seawall.fluid.edac)
"""

import functools

import numpy as np
from numba import njit, prange

from ..eos import eos_state
from ..jit import fold_switches, particle_loop, type_constant
from ..kernels import kernel_gradient_factor, kernel_shape
from ..pairs import (continuity, density_diffusion, edac_diffusion, edac_divergence, gradient_factor, kernel_value,
                     laminar_viscosity,
                     monaghan_viscosity, pressure_acceleration, riemann_continuity, riemann_fluid_jump,
                     riemann_momentum_coefficient, riemann_pressure, tensile_coefficient, tensile_term, viscosity_acts, xsph_weight)
from ..neighbors import cell_index, neighbour_range, point_of, reach_plan, reach_range, tag_dim, tag_periodic, separation
from .params import DIFFUSION_NONE, DIFFUSION_RENORMALISED


@particle_loop()
def equation_of_state(rho, m, prm, p, c, p_over_rho2, volume):
    """Pressure and sound speed of every particle from its density.

    Also stores p / rho^2 and the volume m / rho, which the pair loops would
    otherwise divide out once per pair (two divisions per pair saved).
    """
    for i in prange(rho.shape[0]):
        r = rho[i]
        pi, ci = eos_state(prm.eos, r, prm.rho0, prm.c0, prm.gamma, prm.p_background)
        p[i] = pi
        c[i] = ci
        p_over_rho2[i] = pi / (r * r)
        volume[i] = m[i] / r


@particle_loop()
def summation_density(layout, x, m, xb, mb, start_b, order_b, lo, inv_cell, ncell, period, prm, same, rho):
    """Density by summation, rho_i = sum_j m_j W_ij ([Li2022], eq. 7).

    With ``same`` the set b is the fluid itself: rho is overwritten and the
    self term m_i W(0) included. Otherwise b is a wall whose (hydrodynamic)
    masses are added to rho.
    """
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    w0 = prm.sigma * kernel_shape(prm.kernel, 0.0)
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body: a constant there (see fluid_rates)
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        acc = m[i] * w0 if same else rho[i]
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_b)
                for k in range(ka, kb):
                    j = order_b[k]
                    if same and j == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, xb, j, dim, periodic, period)
                    if r2 < prm.support2:
                        acc += mb[j] * prm.sigma * kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
        rho[i] = acc


@njit(cache=True, inline="always")
def store_renormalised_gradient(grad, i, dim, a00, a01, a02, a11, a12, a22, g0, g1, g2):
    """grad[i] = A^-1 g for the symmetric renormalisation matrix A ([Liu2015] eq. 15).

    Where det A < 1e-2 (A is ~identity in the bulk; a droplet or a particle with
    few neighbours) the plain kernel gradient g is stored instead.
    """
    if dim == 2:
        det = a00 * a11 - a01 * a01
        if det > 1e-2:
            grad[i, 0] = (a11 * g0 - a01 * g1) / det
            grad[i, 1] = (-a01 * g0 + a00 * g1) / det
        else:
            grad[i, 0] = g0
            grad[i, 1] = g1
    else:
        c00 = a11 * a22 - a12 * a12
        c01 = a02 * a12 - a01 * a22
        c02 = a01 * a12 - a02 * a11
        det = a00 * c00 + a01 * c01 + a02 * c02
        if det > 1e-2:
            c11 = a00 * a22 - a02 * a02
            c12 = a01 * a02 - a00 * a12
            c22 = a00 * a11 - a01 * a01
            grad[i, 0] = (c00 * g0 + c01 * g1 + c02 * g2) / det
            grad[i, 1] = (c01 * g0 + c11 * g1 + c12 * g2) / det
            grad[i, 2] = (c02 * g0 + c12 * g1 + c22 * g2) / det
        else:
            grad[i, 0] = g0
            grad[i, 1] = g1
            grad[i, 2] = g2


@particle_loop()
def renormalised_density_gradient(layout, x, rho, volume, start, order, lo, inv_cell, ncell, period, prm, grad):
    """<grad rho>_i^L of [Liu2015] eq. 14-15 (Randles & Libersky renormalisation).

    Where the renormalisation matrix is nearly singular (a particle with few
    neighbours, e.g. a droplet) its determinant falls below 1e-2 (it is ~1 in
    the bulk); there the plain kernel gradient is used instead.
    """
    n = x.shape[0]
    inv_h = 1.0 / prm.h
    gradient_scale = prm.sigma * inv_h * inv_h
    for i in prange(n):
        dim = tag_dim(layout)   # inside the parallel body: a constant there (see fluid_rates)
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        a00 = a01 = a02 = a11 = a12 = a22 = 0.0
        g0 = g1 = g2 = 0.0
        rhoi = rho[i]
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for k in range(ka, kb):
                    j = order[k]
                    if j == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, x, j, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    # grad_i W = F r_ij, and x_j - x_i = -r_ij
                    f = gradient_scale * kernel_gradient_factor(prm.kernel, r * inv_h)
                    vol = volume[j]
                    s = -f * vol
                    a00 += s * d0 * d0
                    a01 += s * d0 * d1
                    a02 += s * d0 * d2
                    a11 += s * d1 * d1
                    a12 += s * d1 * d2
                    a22 += s * d2 * d2
                    t = vol * (rho[j] - rhoi) * f
                    g0 += t * d0
                    g1 += t * d1
                    g2 += t * d2
        store_renormalised_gradient(grad, i, dim, a00, a01, a02, a11, a12, a22, g0, g1, g2)


@functools.lru_cache(maxsize=64)
def scheme_tag(prm):
    """The fluid loop's switches (kernel, Riemann, tensile, laminar viscosity, diffusion, lagged gradient,
    XSPH, artificial viscosity and its pair rule, EDAC pressure) as compile-time constants.

    A tuple of zero-size arrays whose numbers of axes are the switches' values + 1, the same device as
    :func:`seawall.neighbors.layout_tag`: Numba compiles one :func:`fluid_rates` per combination and
    folds away every branch a run does not take. Measured (dam break, 80k particles, the loop alone,
    1 thread, CPU time): 25.5 -> 19.5 ms, of which the kernel's id 8 %; read inside the parallel body
    together with dim and periodicity, 15.9 ms (docs/architecture.md). Their values still come from
    ``prm`` (this only says which branches exist). Remembered per ``prm`` (a tuple of scalars), as the
    wall loops ask for it every evaluation.
    """
    switches = (prm.kernel, prm.riemann != 0, prm.tensile != 0, prm.nu > 0.0, prm.diffusion,
                prm.diffusion == DIFFUSION_RENORMALISED and prm.lagged_gradient != 0, prm.xsph > 0.0,
                prm.alpha > 0.0, prm.alpha_all_pairs != 0, prm.edac != 0)
    return tuple(np.empty((0,) * (int(v) + 1)) for v in switches)


_switch_value = type_constant(lambda tag: tag.ndim - 1)


@njit(cache=True, inline="always")
def tag_value(tag):
    """The switch value a :func:`scheme_tag` entry encodes (a literal: its branches are pruned)."""
    fold_switches()
    return _switch_value(tag)


@particle_loop()
def fluid_rates(fluid, cells, pairs, grad_rho, prm, rates, grad_rho_next, scheme, dp):
    """Fluid-fluid contributions to dv/dt, drho/dt and the XSPH velocity correction.

    ``fluid`` is a :class:`~seawall.views.FluidView`, ``cells`` the fluid's
    :class:`~seawall.views.CellView`, ``rates`` a :class:`~seawall.views.Rates`.
    ``pairs`` a :class:`~seawall.views.PairView`: with a list (:mod:`seawall.pair_list`) each
    particle's candidates are its listed pairs, else those of the cell walk; either way the pairs
    beyond the support are skipped.
    Overwrites ``rates.dv``, ``rates.drho``, ``rates.xsph``; ``rates.mu_max[i]``
    receives max_j |mu_ij| for the Monaghan-Kos time-step criterion ([Li2022],
    eq. 11). Gravity is added here too, so wall models only add their own terms
    afterwards. The pair terms are those of :mod:`seawall.pairs`;
    ``prm.alpha_all_pairs`` applies the artificial viscosity to receding pairs too. ``scheme`` is
    :func:`scheme_tag` of ``prm``: which terms exist is fixed at compile time. With EDAC
    (``prm.edac``) ``dp`` receives the fluid pairs' dp/dt of [Ramachandran2019] (else it is not touched).
    """
    layout = cells.layout
    x = fluid.x
    v = fluid.v
    rho = fluid.rho
    p = fluid.p
    c = fluid.c
    m = fluid.m
    p_over_rho2 = fluid.p_over_rho2
    volume = fluid.volume
    start = cells.start
    order = cells.order
    lo = cells.lo
    inv_cell = cells.inv_cell
    ncell = cells.ncell
    period = cells.period
    dv = rates.dv
    drho = rates.drho
    xsph = rates.xsph
    mu_max = rates.mu_max
    n = x.shape[0]
    h = prm.h
    inv_h = 1.0 / h
    gradient_scale = prm.sigma * inv_h * inv_h
    alpha = prm.alpha
    beta = prm.beta
    nu = prm.nu
    eta2 = prm.eta2
    diff_coef = prm.delta * h * prm.c0
    rho0c0 = prm.rho0 * prm.c0
    c2 = prm.c0 * prm.c0
    nu_edac = prm.edac_nu
    for i in prange(n):
        # read inside the parallel body: values computed outside it reach the outlined loop as
        # run-time arguments, and their branches would not fold
        kernel = tag_value(scheme[0])
        riemann = tag_value(scheme[1]) != 0
        tensile = tag_value(scheme[2]) != 0
        laminar = tag_value(scheme[3]) != 0
        diffusion = tag_value(scheme[4])
        lagged = tag_value(scheme[5]) != 0
        use_xsph = tag_value(scheme[6]) != 0
        artificial = tag_value(scheme[7]) != 0
        all_pairs = tag_value(scheme[8])
        edac = tag_value(scheme[9]) != 0
        renorm = diffusion == DIFFUSION_RENORMALISED
        dim = tag_dim(layout)   # likewise: computed outside, dim and periodicity would not fold
        periodic = tag_periodic(layout)
        listed = tag_value(pairs.listed) != 0
        nrows = 1 if listed else (25 if dim == 3 else 5)
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        plan = reach_plan(p0, p1, p2, cx, cy, cz, lo, inv_cell)
        vi0, vi1, vi2 = point_of(v, i, dim)
        rhoi = rho[i]
        pi = p[i]
        ci = c[i]
        pr_i = p_over_rho2[i]
        if tensile:
            ri = tensile_coefficient(pi, rhoi)
        else:
            ri = 0.0
        if renorm:
            gi0, gi1, gi2 = point_of(grad_rho, i, dim)
        else:
            gi0 = gi1 = gi2 = 0.0
        a0 = a1 = a2 = 0.0
        dr = 0.0
        x0 = x1 = x2 = 0.0
        mu_num = 0.0
        mu_den = 1.0
        a00 = a01 = a02 = a11 = a12 = a22 = 0.0
        g0 = g1 = g2 = 0.0
        dpi = 0.0
        if edac:
            vol_i = volume[i]
            inv_m_i = 1.0 / m[i]
        else:
            vol_i = inv_m_i = 0.0
        for row in range(nrows):
            for part in range(2 if periodic and not listed else 1):
                if listed:
                    ka = i * pairs.stride
                    kb = ka + pairs.counts[i]
                elif periodic:
                    ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                else:  # only the cells the support reaches: the same pairs, fewer candidates
                    ka, kb = reach_range(row, cx, cy, cz, plan, ncell, start, prm.support2)
                for k in range(ka, kb):
                    j = pairs.index[k] if listed else order[k]
                    if j == i:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, x, j, dim, periodic, period)
                    if r2 >= prm.support2 or r2 == 0.0:
                        continue
                    r = np.sqrt(r2)
                    qq = r * inv_h
                    f = gradient_factor(kernel, gradient_scale, qq)  # grad_i W = f r_ij
                    mj = m[j]
                    rhoj = rho[j]
                    vj0, vj1, vj2 = point_of(v, j, dim)
                    u0 = vi0 - vj0
                    u1 = vi1 - vj1
                    u2 = vi2 - vj2
                    vr = u0 * d0 + u1 * d1 + u2 * d2
                    if riemann:
                        dr += riemann_continuity(rhoi, volume[j], vr, pi, p[j], r, rho0c0, f)
                        coef = riemann_momentum_coefficient(
                            riemann_pressure(pi, p[j], riemann_fluid_jump(vr, r), rho0c0, prm.c0, prm.riemann_eta), rhoi, rhoj)
                    else:
                        dr += continuity(mj, vr, f)
                        coef = pr_i + p_over_rho2[j]
                    if edac:
                        dpi += edac_divergence(c2, rhoi, volume[j], vr, f)
                        dpi += edac_diffusion(vol_i, volume[j], inv_m_i, rhoi, rhoj, nu_edac, pi, p[j], f, r2, eta2)
                    if tensile:
                        rj = tensile_coefficient(p[j], rhoj)
                        coef += tensile_term(ri, rj, kernel_value(kernel, prm.sigma, qq) * prm.inv_w_dx)
                    # max_j |vr|/(r^2 + eta^2) for the time step, compared as fractions
                    # (a/b > c/d <=> a d > c b) so that no pair pays a division for it
                    den = r2 + eta2
                    avr = abs(vr)
                    if avr * mu_den > mu_num * den:
                        mu_num = avr
                        mu_den = den
                    if artificial and viscosity_acts(vr, all_pairs):
                        coef += monaghan_viscosity(alpha, beta, h * vr / den, 0.5 * (ci + c[j]), 0.5 * (rhoi + rhoj))
                    s = pressure_acceleration(mj, coef, f)
                    a0 += s * d0
                    a1 += s * d1
                    a2 += s * d2
                    if laminar:
                        lam = laminar_viscosity(mj, nu, rhoi, rhoj, f, r2, eta2)
                        a0 += lam * u0
                        a1 += lam * u1
                        a2 += lam * u2
                    if diffusion != DIFFUSION_NONE:
                        if renorm:
                            gj0, gj1, gj2 = point_of(grad_rho, j, dim)
                            g_dot_r = (gi0 + gj0) * d0 + (gi1 + gj1) * d1 + (gi2 + gj2) * d2
                        else:
                            g_dot_r = 0.0
                        if lagged:
                            # this state's <grad rho>^L, used by the next evaluation ([Liu2015] eq. 14-15)
                            vol = volume[j]
                            sv = -f * vol
                            a00 += sv * d0 * d0
                            a01 += sv * d0 * d1
                            a02 += sv * d0 * d2
                            a11 += sv * d1 * d1
                            a12 += sv * d1 * d2
                            a22 += sv * d2 * d2
                            t = vol * (rhoj - rhoi) * f
                            g0 += t * d0
                            g1 += t * d1
                            g2 += t * d2
                        dr += density_diffusion(diff_coef, volume[j], rhoi, rhoj, f, renorm, g_dot_r)
                    if use_xsph:
                        wx = xsph_weight(kernel_value(kernel, prm.sigma, qq), mj, rhoi, rhoj)
                        x0 -= wx * u0
                        x1 -= wx * u1
                        x2 -= wx * u2
        dv[i, 0] = a0 + prm.gx
        dv[i, 1] = a1 + prm.gy
        if dim == 3:
            dv[i, 2] = a2 + prm.gz
        drho[i] = dr
        if edac:
            dp[i] = dpi
        eps = prm.xsph
        xsph[i, 0] = eps * x0
        xsph[i, 1] = eps * x1
        if dim == 3:
            xsph[i, 2] = eps * x2
        mu_max[i] = h * mu_num / mu_den
        if lagged:
            store_renormalised_gradient(grad_rho_next, i, dim, a00, a01, a02, a11, a12, a22, g0, g1, g2)
