"""What single precision could give the fluid pair loop, measured before building it (issue 19, item 5).

One copy of the fluid-fluid loop of the 2D dam break's scheme (cubic spline; continuity,
pressure, Monaghan viscosity on approaching pairs, the time-step mu, delta-SPH with the
lagged renormalised gradient, as :func:`seawall.fluid.rates.fluid_rates` runs them), written
once and compiled per dtype, on a state like the dam break's at 80k particles (a 2H x H block
at dx = 0.0015 m, H = 0.3 m, jittered lattice, hydrostatic density, small random velocities,
stored in cell order as the simulation keeps it; ``--dim 3``: a 2H x H/2 x H block at dx = 0.0065 m,
97k particles). Five variants on the same data:

* ``abs64``: absolute float64 positions, the separation as seawall computes it (today's loop);
* ``rel64``: float64 offsets from each particle's cell origin plus its integer cell
  coordinates, x_i - x_j = (o_i - o_j) + (c_i - c_j) * cell (the representation single
  precision needs, measured in double to see its own cost);
* ``rel32``: the same in float32, every array and every constant float32: keeps x_i - x_j to
  ~1e-7 of the cell size, not of the domain;
* ``abs32``: absolute float32 positions (loses dx to ~1e-7 of the domain size; an upper bound
  of the speed, not a candidate);
* ``seawall``: :func:`seawall.fluid.rates.fluid_rates` itself on the same state and scheme, to
  show that the copy costs what the real loop costs.

Timing: the variants interleaved, ``--repeats`` calls each, median of the CPU time of the
process per call (``time.process_time``: all threads; passive waiting costs none) and of the
wall time; 1 and 2 threads in one process (``numba.set_num_threads``). Accuracy: the relative
difference of dv and drho of each variant from ``abs64`` (max over particles, scaled by the
largest |dv| and |drho|).

    NUMBA_NUM_THREADS=2 python benchmarks/precision_probe.py --repeats 25
    NUMBA_NUM_THREADS=2 python benchmarks/precision_probe.py --dim 3 --repeats 15

The figures and what they mean are in docs/performance.md ("Single precision").
"""

import argparse
import json
import math
import os
import statistics
import time

import numba
import numpy as np
from numba import njit, prange

from seawall.fluid.params import DIFFUSION_RENORMALISED, Physics
from seawall.fluid.rates import fluid_rates, scheme_tag
from seawall.kernels import CUBIC_SPLINE
from seawall.neighbors import CellGrid, neighbour_range
from seawall.views import CellView, FluidView, Rates

GRAVITY = 9.81


@njit(cache=True, inline="always")
def cubic_gradient_factor(q, one, two, three, c225, c075):
    """(dw/dq)/q of the cubic spline ([Li2022] eq. 3), as seawall.kernels writes it."""
    if q < one:
        return -three + c225 * q
    t = two - q
    return -c075 * t * t / q


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def pair_loop(xs, cells, cellf, relative, v, rho, p, c, m, volume, grad, start, order, ncell, period, cell_size, k,
              dv, drho, mu_max, grad_next):
    """The dam break's fluid loop: continuity ([Li2022] eq. 8), momentum with the artificial viscosity
    ([Li2022] eq. 5-6), the time-step mu ([Li2022] eq. 11), density diffusion with the renormalised
    gradient and its lagged accumulation ([Liu2015] eq. 12-15); ``k`` holds every constant in the arrays' dtype (no literal
    may promote a float32 expression to float64). With ``relative``, ``xs`` are offsets from the
    cell origins, ``cells`` the integer cell coordinates and ``cellf`` the same in the arrays' dtype
    (an integer times a float32 would be promoted to float64); else ``xs`` are absolute positions."""
    n = xs.shape[0]
    zero, one, two, three, c225, c075, half, h, inv_h, gscale, support2, eta2, alpha, diff_coef, gy = k
    for i in prange(n):
        p0 = xs[i, 0]
        p1 = xs[i, 1]
        ci0 = cells[i, 0]
        ci1 = cells[i, 1]
        fi0 = cellf[i, 0]
        fi1 = cellf[i, 1]
        vi0 = v[i, 0]
        vi1 = v[i, 1]
        rhoi = rho[i]
        pri = p[i] / (rhoi * rhoi)
        cci = c[i]
        gi0 = grad[i, 0]
        gi1 = grad[i, 1]
        a0 = zero
        a1 = zero
        dr = zero
        mu_num = zero
        mu_den = one
        a00 = zero
        a01 = zero
        a11 = zero
        g0 = zero
        g1 = zero
        for row in range(5):
            ka, kb = neighbour_range(row, 0, ci0, ci1, 0, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                if j == i:
                    continue
                if relative:
                    d0 = (p0 - xs[j, 0]) + (fi0 - cellf[j, 0]) * cell_size
                    d1 = (p1 - xs[j, 1]) + (fi1 - cellf[j, 1]) * cell_size
                else:
                    d0 = p0 - xs[j, 0]
                    d1 = p1 - xs[j, 1]
                r2 = d0 * d0 + d1 * d1
                if r2 >= support2 or r2 == zero:
                    continue
                r = np.sqrt(r2)
                f = gscale * cubic_gradient_factor(r * inv_h, one, two, three, c225, c075)
                mj = m[j]
                rhoj = rho[j]
                u0 = vi0 - v[j, 0]
                u1 = vi1 - v[j, 1]
                vr = u0 * d0 + u1 * d1
                dr += mj * vr * f
                coef = pri + p[j] / (rhoj * rhoj)
                den = r2 + eta2
                avr = abs(vr)
                if avr * mu_den > mu_num * den:
                    mu_num = avr
                    mu_den = den
                if vr < zero:
                    mu = h * vr / den
                    coef += (-alpha * (half * (cci + c[j])) * mu) / (half * (rhoi + rhoj))
                s = -mj * coef * f
                a0 += s * d0
                a1 += s * d1
                vol = volume[j]
                sv = -f * vol
                a00 += sv * d0 * d0
                a01 += sv * d0 * d1
                a11 += sv * d1 * d1
                t = vol * (rhoj - rhoi) * f
                g0 += t * d0
                g1 += t * d1
                g_dot_r = (gi0 + grad[j, 0]) * d0 + (gi1 + grad[j, 1]) * d1
                dr += diff_coef * vol * (-two * (rhoj - rhoi) * f - g_dot_r * f)
        dv[i, 0] = a0
        dv[i, 1] = a1 + gy
        drho[i] = dr
        mu_max[i] = h * mu_num / mu_den
        det = a00 * a11 - a01 * a01
        grad_next[i, 0] = (a11 * g0 - a01 * g1) / det
        grad_next[i, 1] = (-a01 * g0 + a00 * g1) / det


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def pair_loop_3d(xs, cells, cellf, relative, v, rho, p, c, m, volume, grad, start, order, ncell, period, cell_size,
                 k, dv, drho, mu_max, grad_next):
    """:func:`pair_loop` in 3D (25 rows of 5 cells; the 3 x 3 renormalisation matrix of [Liu2015] eq. 15)."""
    n = xs.shape[0]
    zero, one, two, three, c225, c075, half, h, inv_h, gscale, support2, eta2, alpha, diff_coef, gy = k
    for i in prange(n):
        p0 = xs[i, 0]
        p1 = xs[i, 1]
        p2 = xs[i, 2]
        ci0 = cells[i, 0]
        ci1 = cells[i, 1]
        ci2 = cells[i, 2]
        fi0 = cellf[i, 0]
        fi1 = cellf[i, 1]
        fi2 = cellf[i, 2]
        vi0 = v[i, 0]
        vi1 = v[i, 1]
        vi2 = v[i, 2]
        rhoi = rho[i]
        pri = p[i] / (rhoi * rhoi)
        cci = c[i]
        gi0 = grad[i, 0]
        gi1 = grad[i, 1]
        gi2 = grad[i, 2]
        a0 = zero
        a1 = zero
        a2 = zero
        dr = zero
        mu_num = zero
        mu_den = one
        a00 = zero
        a01 = zero
        a02 = zero
        a11 = zero
        a12 = zero
        a22 = zero
        g0 = zero
        g1 = zero
        g2 = zero
        for row in range(25):
            ka, kb = neighbour_range(row, 0, ci0, ci1, ci2, ncell, period, start)
            for kk in range(ka, kb):
                j = order[kk]
                if j == i:
                    continue
                if relative:
                    d0 = (p0 - xs[j, 0]) + (fi0 - cellf[j, 0]) * cell_size
                    d1 = (p1 - xs[j, 1]) + (fi1 - cellf[j, 1]) * cell_size
                    d2 = (p2 - xs[j, 2]) + (fi2 - cellf[j, 2]) * cell_size
                else:
                    d0 = p0 - xs[j, 0]
                    d1 = p1 - xs[j, 1]
                    d2 = p2 - xs[j, 2]
                r2 = d0 * d0 + d1 * d1 + d2 * d2
                if r2 >= support2 or r2 == zero:
                    continue
                r = np.sqrt(r2)
                f = gscale * cubic_gradient_factor(r * inv_h, one, two, three, c225, c075)
                mj = m[j]
                rhoj = rho[j]
                u0 = vi0 - v[j, 0]
                u1 = vi1 - v[j, 1]
                u2 = vi2 - v[j, 2]
                vr = u0 * d0 + u1 * d1 + u2 * d2
                dr += mj * vr * f
                coef = pri + p[j] / (rhoj * rhoj)
                den = r2 + eta2
                avr = abs(vr)
                if avr * mu_den > mu_num * den:
                    mu_num = avr
                    mu_den = den
                if vr < zero:
                    mu = h * vr / den
                    coef += (-alpha * (half * (cci + c[j])) * mu) / (half * (rhoi + rhoj))
                s = -mj * coef * f
                a0 += s * d0
                a1 += s * d1
                a2 += s * d2
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
                g_dot_r = (gi0 + grad[j, 0]) * d0 + (gi1 + grad[j, 1]) * d1 + (gi2 + grad[j, 2]) * d2
                dr += diff_coef * vol * (-two * (rhoj - rhoi) * f - g_dot_r * f)
        dv[i, 0] = a0
        dv[i, 1] = a1
        dv[i, 2] = a2 + gy
        drho[i] = dr
        mu_max[i] = h * mu_num / mu_den
        c00 = a11 * a22 - a12 * a12
        c01 = a02 * a12 - a01 * a22
        c02 = a01 * a12 - a02 * a11
        det = a00 * c00 + a01 * c01 + a02 * c02
        grad_next[i, 0] = (c00 * g0 + c01 * g1 + c02 * g2) / det
        grad_next[i, 1] = (c01 * g0 + (a00 * a22 - a02 * a02) * g1 + (a01 * a02 - a00 * a12) * g2) / det
        grad_next[i, 2] = (c02 * g0 + (a01 * a02 - a00 * a12) * g1 + (a00 * a11 - a01 * a01) * g2) / det


def dam_break_state(dx, dim=2, seed=1):
    """The dam break's water block (2H x H, in 3D 2H x H/2 x H) at spacing dx in cell order: positions,
    fields, cell list."""
    H = 0.3
    rng = np.random.default_rng(seed)
    extent = (2 * H, H) if dim == 2 else (2 * H, 0.5 * H, H)
    counts = [int(round(e / dx)) for e in extent]
    axes = np.meshgrid(*[(np.arange(c) + 0.5) * dx for c in counts], indexing="ij")
    n = int(np.prod(counts))
    x = np.column_stack([a.ravel() for a in axes]) + rng.uniform(-0.05, 0.05, (n, dim)) * dx
    h = 1.3 * dx
    hi = (5.366 * H + 3 * dx, 2 * H) if dim == 2 else (5.366 * H + 3 * dx, 0.5 * H + 3 * dx, 2 * H)
    grid = CellGrid((-3 * dx,) * dim, hi, 2 * h)
    cl = grid.build(x)
    x = x[cl.order]                      # the simulation keeps the fluid in cell order
    cl = grid.build(x)
    rho0 = 1000.0
    c0 = 10.0 * math.sqrt(2 * GRAVITY * H)
    b = rho0 * c0 * c0 / 7.0
    p_hydro = rho0 * GRAVITY * (H - x[:, dim - 1])
    rho = rho0 * (1.0 + p_hydro / b) ** (1.0 / 7.0) * (1.0 + rng.uniform(-1e-4, 1e-4, n))
    p = b * ((rho / rho0) ** 7 - 1.0)
    c = c0 * (rho / rho0) ** 3
    m = np.full(n, rho0 * dx ** dim)
    v = rng.normal(0.0, 0.05 * math.sqrt(GRAVITY * H), (n, dim))
    grad = rng.normal(0.0, rho0 * GRAVITY / (c0 * c0), (n, dim))
    cells = np.empty((n, dim), dtype=np.int32)
    for a in range(dim):
        cells[:, a] = np.clip(((x[:, a] - grid.lo[a]) * grid.inv_cell[a]).astype(np.int64), 0, grid.ncell[a] - 1)
    cell_size = grid.cell_size[0]
    assert np.all(np.abs(grid.cell_size[:dim] - cell_size) < 1e-12 * cell_size)
    offsets = x - grid.lo[:dim] - cells * cell_size
    return dict(grid=grid, dim=dim, x=x, offsets=offsets, cells=cells, v=v, rho=rho, p=p, c=c, m=m,
                volume=m / rho, grad=grad, start=cl.start, order=cl.order, ncell=grid.ncell, period=grid.period,
                cell_size=cell_size, h=h, c0=c0, rho0=rho0)


def variant_args(state, name):
    """The loop's arguments for one variant, every float array and constant in its dtype."""
    dt = np.float32 if name.endswith("32") else np.float64
    relative = name.startswith("rel")
    h = state["h"]
    sigma = 10.0 / (7.0 * math.pi * h * h) if state["dim"] == 2 else 1.0 / (math.pi * h ** 3)
    k = tuple(dt(value) for value in (0.0, 1.0, 2.0, 3.0, 2.25, 0.75, 0.5, h, 1.0 / h, sigma / (h * h),
                                      (2 * h) ** 2, (0.1 * h) ** 2, 0.02, 0.1 * h * state["c0"], -GRAVITY))
    xs = state["offsets"] if relative else state["x"]
    n = xs.shape[0]
    args = (np.ascontiguousarray(xs, dtype=dt), state["cells"], state["cells"].astype(dt), relative,
            *(np.ascontiguousarray(state[key], dtype=dt) for key in ("v", "rho", "p", "c", "m", "volume", "grad")),
            state["start"], state["order"], state["ncell"], state["period"], dt(state["cell_size"]), k,
            np.zeros((n, state["dim"]), dt), np.zeros(n, dt), np.zeros(n, dt), np.zeros((n, state["dim"]), dt))
    return args


def seawall_args(state):
    """fluid_rates' arguments for the same state and scheme (alpha = 0.02, delta = 0.1, lagged gradient)."""
    h = state["h"]
    grid = state["grid"]
    x = state["x"]
    n = x.shape[0]
    dim = state["dim"]
    sigma = 10.0 / (7.0 * math.pi * h * h) if dim == 2 else 1.0 / (math.pi * h ** 3)
    prm = Physics(dim=dim, kernel=CUBIC_SPLINE, h=h, sigma=sigma, support2=(2 * h) ** 2,
                  eta2=(0.1 * h) ** 2, rho0=state["rho0"], eos=0, c0=state["c0"], gamma=7.0, p_background=0.0,
                  alpha=0.02, beta=0.0, nu=0.0, diffusion=DIFFUSION_RENORMALISED, delta=0.1, lagged_gradient=1,
                  tensile=0, inv_w_dx=0.0, xsph=0.0, gx=0.0, gy=-GRAVITY if dim == 2 else 0.0,
                  gz=-GRAVITY if dim == 3 else 0.0)
    cells = CellView(grid.layout, grid.lo, grid.inv_cell, grid.ncell, grid.period, state["start"], state["order"],
                     np.zeros(0, dtype=np.uint8))
    rho = state["rho"]
    fluid = FluidView(x, state["v"], rho, state["p"], state["c"], state["m"], state["p"] / rho ** 2, state["volume"])
    rates = Rates(np.zeros((n, dim)), np.zeros(n), np.zeros((n, dim)), np.zeros(n))
    return (fluid, cells, state["grad"], prm, rates, np.zeros((n, dim)), scheme_tag(prm))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dim", type=int, choices=(2, 3), default=2)
    parser.add_argument("--dx", type=float, default=None, help="default 0.0015 m (2D, 80k), 0.0065 m (3D, 97k)")
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args(argv)
    dx = args.dx or (0.0015 if args.dim == 2 else 0.0065)
    state = dam_break_state(dx, args.dim)
    names = ("abs64", "rel64", "rel32", "abs32", "seawall")
    runs = {name: variant_args(state, name) for name in names[:-1]}
    runs["seawall"] = seawall_args(state)
    loops = {name: pair_loop if args.dim == 2 else pair_loop_3d for name in names[:-1]}
    loops["seawall"] = fluid_rates
    for name in names:   # compile (or load from the cache) and check
        loops[name](*runs[name])
    ref_dv, ref_drho = runs["abs64"][-4], runs["abs64"][-3]
    outputs = {name: (runs[name][-4], runs[name][-3]) for name in names[:-1]}
    outputs["seawall"] = (runs["seawall"][4].dv, runs["seawall"][4].drho)
    accuracy = {}
    for name in names:
        dv, drho = outputs[name]
        accuracy[name] = {"dv": float(np.abs(dv - ref_dv).max() / np.abs(ref_dv).max()),
                          "drho": float(np.abs(drho - ref_drho).max() / np.abs(ref_drho).max())}
    result = {"dim": args.dim, "n": state["x"].shape[0], "dx": dx, "repeats": args.repeats, "accuracy": accuracy,
              "load": os.getloadavg()[0], "threads": {}}
    for threads in args.threads:
        numba.set_num_threads(threads)
        cpu = {name: [] for name in names}
        wall = {name: [] for name in names}
        for _ in range(args.repeats):
            for name in names:
                w0, c0 = time.perf_counter(), time.process_time()
                loops[name](*runs[name])
                cpu[name].append(time.process_time() - c0)
                wall[name].append(time.perf_counter() - w0)
        med = statistics.median
        result["threads"][threads] = {
            name: {"cpu_ms": med(cpu[name]) * 1e3, "wall_ms": med(wall[name]) * 1e3,
                   "cpu_x_abs64": med(a / b for a, b in zip(cpu["abs64"], cpu[name])),
                   "wall_x_abs64": med(a / b for a, b in zip(wall["abs64"], wall[name]))}
            for name in names}
    result["load_after"] = os.getloadavg()[0]
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
