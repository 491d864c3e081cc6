"""What the SPH sums read on the exactly deformed lattice of the elliptical drop.

``python validation/elliptical-drop/lattice_moments.py [--h-factors 1.3,2.0]``

No simulation: the initial disc lattice (dx = 0.025, radius 1) is moved by the exact
Lagrangian map of [Monaghan1994] sec. 5, x -> (a x, y / a), a(t) from
``seawall.analytic.elliptical_drop``, and at each time the interior particles (initial
radius below 0.5, far from the surface) are asked what the standard SPH sums give there:

* the summation density rho_i / rho0 = sum_j V0 W_ij (V0 = dx^2: the exact map keeps every
  particle's area, so the exact value is 1);
* the continuity equation's divergence of the exact velocity u = -A x, v = A y,
  -sum_j V0 (v_i - v_j) . grad_i W_ij, divided by A (exact: 0);
* the kernel-gradient moments M_kk = sum_j V0 (x_j - x_i)_k d_k W_ij (grad_i W_ij; exact: 1), which
  weight the pressure gradient along x and y.

The lattice spacing becomes a dx along x and dx / a along y; when dx / a approaches the
kernel's reach (2 h) the sums sample too few rows along y and stop being consistent.
Prints one JSON line per (h / dx, t).
"""

import argparse
import json
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))   # this checkout's seawall

from seawall import shapes  # noqa: E402
from seawall.analytic import elliptical_drop  # noqa: E402
from seawall.kernels import CubicSpline  # noqa: E402

DX = 0.025
TIMES = (0.0, 0.002, 0.004, 0.005, 0.006, 0.007, 0.0076)


def lattice_sums(h_factor, t, dx=DX):
    """Means over the interior particles of (rho / rho0, div u / A, M_xx, M_yy) on the exact map at t."""
    x0 = shapes.circle((0.0, 0.0), 1.0, dx).positions
    a = 1.0 if t == 0 else float(elliptical_drop(t)[1])
    x = np.stack([a * x0[:, 0], x0[:, 1] / a], axis=1)
    kernel, h = CubicSpline(), h_factor * dx
    inner = np.flatnonzero(np.hypot(x0[:, 0], x0[:, 1]) < 0.5)
    tree = cKDTree(x)
    vol = dx * dx
    out = np.zeros((inner.size, 4))
    for k, i in enumerate(inner):
        j = np.array(tree.query_ball_point(x[i], kernel.support(h)))
        rvec = x[i] - x[j]                       # x_i - x_j
        r = np.linalg.norm(rvec, axis=1)
        rho = vol * np.sum(kernel.value(r, h, 2))
        grad = kernel.gradient(rvec, h)          # grad_i W_ij
        dv = np.stack([-(rvec[:, 0]), rvec[:, 1]], axis=1)   # (v_i - v_j) / A for u = -A x, v = A y
        div = -vol * np.sum(dv * grad)
        mxx = -vol * np.sum(rvec[:, 0] * grad[:, 0])
        myy = -vol * np.sum(rvec[:, 1] * grad[:, 1])
        out[k] = rho, div, mxx, myy
    return a, out.mean(axis=0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--h-factors", default="1.3,2.0", help="h / dx values, comma-separated")
    args = ap.parse_args(argv)
    for hf in (float(s) for s in args.h_factors.split(",")):
        for t in TIMES:
            a, (rho, div, mxx, myy) = lattice_sums(hf, t)
            print(json.dumps({"h_factor": hf, "t_ms": round(t * 1e3, 3), "a": round(a, 5),
                              "spacing_y_over_h": round(1.0 / (a * hf), 3), "rho_sum": round(rho, 5),
                              "div_u_over_A": round(div, 4), "M_xx": round(mxx, 4), "M_yy": round(myy, 4)}))


if __name__ == "__main__":
    main()
