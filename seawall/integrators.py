"""Time integration: symplectic position-Verlet and kick-drift-kick leap-frog.

Both need one evaluation of the rates per step; the rates of the previous
evaluation are kept in the fluid's arrays (``dv``, ``drho``, ``xsph``), so a
checkpoint holds everything needed to continue a run bit for bit.

Time-step rules (adaptive unless ``dt`` is given):

* ``"monaghan-kos"`` (seed 000, eq. 11; Monaghan & Kos 1999):
  dt = CFL * min(dt_f, dt_cv), dt_f = min_a sqrt(h / |a_a|),
  dt_cv = min_a h / (c_a + max_b |mu_ab|); with laminar viscosity also
  dt <= 0.125 h^2 / nu (Morris et al. 1997). The extracted eq. 11 reads
  h / sqrt(|f_a|), which is not a time; sqrt(h / |f_a|) is, and is the
  criterion of Monaghan & Kos.
* ``"liu2015"`` (seed 003, eq. 18-20): dt = min(0.4 dt_cv, 0.25 dt_f) with
  dt_cv = min_i h / (c + 0.6 alpha c) and dt_f = min_i sqrt(h / |a_i|)
  (again the square root restores the dimension of time).
"""

import math

import numpy as np

from .errors import ParameterError, require_positive

DT_RULES = ("monaghan-kos", "liu2015")


class Integrator:
    """Common parameters of the integrators.

    Parameters
    ----------
    cfl : float
        Courant number of the Monaghan-Kos rule, default 0.2.
    dt : float, optional
        Fixed time step [s]; overrides the adaptive rule.
    rule : {"monaghan-kos", "liu2015"}
        Adaptive time-step rule.
    dt_max : float, optional
        Upper bound on the adaptive step [s].
    """

    name = "integrator"

    def __init__(self, *, cfl=0.2, dt=None, rule="monaghan-kos", dt_max=None):
        self.cfl = require_positive("cfl", cfl)
        if self.cfl > 1.0:
            raise ParameterError(f"cfl must be in (0, 1], got {cfl}")
        self.dt = None if dt is None else require_positive("dt", dt)
        if rule not in DT_RULES:
            raise ParameterError(f"rule must be one of {', '.join(DT_RULES)}; got {rule!r}")
        self.rule = rule
        self.dt_max = None if dt_max is None else require_positive("dt_max", dt_max)

    def time_step(self, fluid, physics):
        """Next time step from the rates of the last evaluation."""
        if self.dt is not None:
            return self.dt
        pa = fluid.particles
        h = physics.h
        if pa.n == 0:
            return self.dt_max or 1e-4
        amax = float(np.sqrt(np.max(np.sum(pa["dv"] ** 2, axis=1))))
        dt_f = math.sqrt(h / amax) if amax > 0 else math.inf
        if self.rule == "monaghan-kos":
            dt_cv = float(np.min(h / (pa["c"] + pa["mu_max"])))
            dt = self.cfl * min(dt_f, dt_cv)
        else:
            c = physics.c0
            dt_cv = h / (c + 0.6 * physics.alpha * c)
            dt = min(0.4 * dt_cv, 0.25 * dt_f)
        if physics.nu > 0.0:
            dt = min(dt, 0.125 * h * h / physics.nu)
        if self.dt_max is not None:
            dt = min(dt, self.dt_max)
        return dt


class Symplectic(Integrator):
    """Symplectic position-Verlet scheme (Leimkuhler et al. 1996; as in Monaghan 2005 sec. 5.2).

    predictor:  x* = x + dt/2 (v + v_xsph),  v* = v + dt/2 a_n,  rho* = rho + dt/2 D_n
    rates at t + dt/2:  a*, D*
    corrector:  v' = v + dt a*,  x' = x* + dt/2 (v' + v_xsph*),
                rho' = rho (2 - e)/(2 + e), e = -(D*/rho*) dt
    The density update is the exact solution of drho/dt = -rho div v over
    the step with div v frozen, which keeps rho positive.
    """

    name = "symplectic"

    def step(self, sim, dt):
        pa = sim.fluid.particles
        x, v, rho = pa["x"], pa["v"], pa["rho"]
        v_old = v.copy()
        rho_old = rho.copy()
        x += 0.5 * dt * (v + pa["xsph"])
        v += 0.5 * dt * pa["dv"]
        rho += 0.5 * dt * pa["drho"]
        sim.evaluate(sim.time + 0.5 * dt)
        # the arrays are the same objects: evaluate never reallocates inside a step
        eps = -(pa["drho"] / rho) * dt
        v[:] = v_old + dt * pa["dv"]
        x += 0.5 * dt * (v + pa["xsph"])
        rho[:] = rho_old * (2.0 - eps) / (2.0 + eps)


class LeapFrog(Integrator):
    """Kick-drift-kick leap-frog (seed 003, eq. 16-17).

    v_{n+1/2} = v_n + dt/2 a_n,  rho_{n+1/2} = rho_n + dt/2 D_n,
    x_{n+1} = x_n + dt (v_{n+1/2} + v_xsph),
    rates at t + dt from (x_{n+1}, v_{n+1/2}, rho_{n+1/2}),
    v_{n+1} = v_{n+1/2} + dt/2 a_{n+1},  rho_{n+1} = rho_{n+1/2} + dt/2 D_{n+1}.
    """

    name = "leapfrog"

    def step(self, sim, dt):
        pa = sim.fluid.particles
        x, v, rho = pa["x"], pa["v"], pa["rho"]
        v += 0.5 * dt * pa["dv"]
        rho += 0.5 * dt * pa["drho"]
        x += dt * (v + pa["xsph"])
        sim.evaluate(sim.time + dt)
        v += 0.5 * dt * pa["dv"]
        rho += 0.5 * dt * pa["drho"]


INTEGRATORS = {"symplectic": Symplectic, "leapfrog": LeapFrog}
