"""Time integration: symplectic position-Verlet and kick-drift-kick leap-frog.

Both need one evaluation of the rates per step; the rates of the previous
evaluation are kept in the fluid's arrays (``dv``, ``drho``, ``xsph``), so a
checkpoint holds everything needed to continue a run bit for bit.

Time-step rules (adaptive unless ``dt`` is given):

* ``"monaghan-kos"`` ([Li2022], eq. 11; Monaghan & Kos 1999):
  dt = CFL * min(dt_f, dt_cv), dt_f = min_a sqrt(h / |a_a|),
  dt_cv = min_a h / (c_a + max_b |mu_ab|); with laminar viscosity also
  dt <= 0.125 h^2 / nu (Morris et al. 1997). The extracted eq. 11 reads
  h / sqrt(|f_a|), which is not a time; sqrt(h / |f_a|) is, and is the
  criterion of Monaghan & Kos.
* ``"liu2015"`` ([Liu2015], eq. 18-20): dt = min(0.4 dt_cv, 0.25 dt_f) with
  dt_cv = min_i h / (c + 0.6 alpha c) and dt_f = min_i sqrt(h / |a_i|)
  (again the square root restores the dimension of time).
"""

import math

import numpy as np
from numba import njit, prange

from .errors import ParameterError, require_positive
from .jit import particle_loop


@njit(cache=True)
def step_limits(dv, c, mu_max, h):
    """max_a |a_a| and min_a h / (c_a + max_b |mu_ab|) in one pass."""
    amax2 = 0.0
    cv = np.inf
    for i in range(dv.shape[0]):
        a2 = 0.0
        for k in range(dv.shape[1]):
            a2 += dv[i, k] * dv[i, k]
        if a2 > amax2:
            amax2 = a2
        t = h / (c[i] + mu_max[i])
        if t < cv:
            cv = t
    return math.sqrt(amax2), cv


@particle_loop()
def symplectic_predict(x, v, rho, dv, drho, xsph, dt, v_old, rho_old):
    """Predictor half step of :class:`Symplectic` (keeps v_n, rho_n for the corrector)."""
    half = 0.5 * dt
    for i in prange(x.shape[0]):
        rho_old[i] = rho[i]
        rho[i] += half * drho[i]
        for k in range(x.shape[1]):
            v_old[i, k] = v[i, k]
            x[i, k] += half * (v[i, k] + xsph[i, k])
            v[i, k] += half * dv[i, k]


@particle_loop()
def symplectic_correct(x, v, rho, dv, drho, xsph, dt, v_old, rho_old):
    """Corrector of :class:`Symplectic` with the rates at the half step."""
    half = 0.5 * dt
    for i in prange(x.shape[0]):
        eps = -(drho[i] / rho[i]) * dt
        rho[i] = rho_old[i] * (2.0 - eps) / (2.0 + eps)
        for k in range(x.shape[1]):
            v[i, k] = v_old[i, k] + dt * dv[i, k]
            x[i, k] += half * (v[i, k] + xsph[i, k])


@particle_loop()
def kick(v, rho, dv, drho, dt_half):
    """Half kick of velocity and density (:class:`LeapFrog`)."""
    for i in prange(v.shape[0]):
        rho[i] += dt_half * drho[i]
        for k in range(v.shape[1]):
            v[i, k] += dt_half * dv[i, k]


@particle_loop()
def drift(x, v, xsph, dt):
    """Full drift of the positions with the XSPH-corrected velocity (:class:`LeapFrog`)."""
    for i in prange(x.shape[0]):
        for k in range(x.shape[1]):
            x[i, k] += dt * (v[i, k] + xsph[i, k])

DT_RULES = ("monaghan-kos", "liu2015")


def pressure_variable(pa):
    """(p, dp/dt) of a fluid whose pressure is its own variable (EDAC, seawall.fluid.edac), else None.

    The integrators advance it as they advance the velocity (it enters the rates linearly, like v):
    predictor p* = p + dt/2 dp_n, corrector p' = p + dt dp*, leap-frog kicks of dt/2.
    """
    if "dp" not in pa:
        return None
    return pa["p"], pa["dp"]


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
        amax, dt_cv = step_limits(pa["dv"], pa["c"], pa["mu_max"], h)
        dt_f = math.sqrt(h / amax) if amax > 0 else math.inf
        if self.rule == "monaghan-kos":
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

    def _scratch(self, pa):
        """v_n and rho_n kept for the corrector; reused across steps (fresh pages cost ~1 ms a step)."""
        buf = getattr(self, "_buffers", None)
        if buf is None or buf[0].shape != pa["v"].shape:
            buf = (np.empty_like(pa["v"]), np.empty_like(pa["rho"]))
            self._buffers = buf
        return buf

    def step(self, sim, dt):
        pa = sim.fluid.particles
        v_old, rho_old = self._scratch(pa)
        pressure = pressure_variable(pa)
        if pressure is not None:
            p_old = pressure[0].copy()
            pressure[0][:] += 0.5 * dt * pressure[1]
        symplectic_predict(pa["x"], pa["v"], pa["rho"], pa["dv"], pa["drho"], pa["xsph"], dt, v_old, rho_old)
        sim.evaluate(sim.time + 0.5 * dt)
        # the arrays are the same objects: evaluate never reallocates inside a step
        symplectic_correct(pa["x"], pa["v"], pa["rho"], pa["dv"], pa["drho"], pa["xsph"], dt, v_old, rho_old)
        if pressure is not None:
            np.add(p_old, dt * pressure[1], out=pressure[0])


class LeapFrog(Integrator):
    """Kick-drift-kick leap-frog ([Liu2015], eq. 16-17).

    v_{n+1/2} = v_n + dt/2 a_n,  rho_{n+1/2} = rho_n + dt/2 D_n,
    x_{n+1} = x_n + dt (v_{n+1/2} + v_xsph),
    rates at t + dt from (x_{n+1}, v_{n+1/2}, rho_{n+1/2}),
    v_{n+1} = v_{n+1/2} + dt/2 a_{n+1},  rho_{n+1} = rho_{n+1/2} + dt/2 D_{n+1}.
    """

    name = "leapfrog"

    def step(self, sim, dt):
        pa = sim.fluid.particles
        pressure = pressure_variable(pa)
        kick(pa["v"], pa["rho"], pa["dv"], pa["drho"], 0.5 * dt)
        if pressure is not None:
            pressure[0][:] += 0.5 * dt * pressure[1]
        drift(pa["x"], pa["v"], pa["xsph"], dt)
        sim.evaluate(sim.time + dt)
        kick(pa["v"], pa["rho"], pa["dv"], pa["drho"], 0.5 * dt)
        if pressure is not None:
            pressure[0][:] += 0.5 * dt * pressure[1]


class PredictedLeapFrog(Integrator):
    """Leap-frog with the rates evaluated at the predicted full-step state ([Liu2015] eq. 16-17).

    [Liu2015] (after Liu & Liu 2003) staggers velocity and density half a step
    from the positions: phi_{n+1/2} = phi_{n-1/2} + dt dphi/dt(t_n), x_{n+1} = x_n
    + dt v_{n+1/2}, with the rates at t_n taken from the state predicted to t_n,
    phi_n = phi_{n-1/2} + dt/2 dphi/dt(t_{n-1}). Written from full steps:

        v_{n+1/2} = v_n + dt/2 a_n,   rho_{n+1/2} = rho_n + dt/2 D_n,   x_{n+1} = x_n + dt v_{n+1/2};
        rates a_{n+1}, D_{n+1} at (x_{n+1}, v_{n+1/2} + dt/2 a_n, rho_{n+1/2} + dt/2 D_n);
        v_{n+1} = v_{n+1/2} + dt/2 a_{n+1},   rho_{n+1} = rho_{n+1/2} + dt/2 D_{n+1}.

    :class:`LeapFrog` evaluates the rates at (x_{n+1}, v_{n+1/2}, rho_{n+1/2})
    instead: density and velocity half a step behind the positions, which
    lets the acoustic (density-pressure) oscillation grow; the [Liu2015] dam
    break at dx = 6 mm blows up within 0.03 s with it (docs/liu2015.md).
    """

    name = "leapfrog-predicted"

    def step(self, sim, dt):
        pa = sim.fluid.particles
        buf = getattr(self, "_buffers", None)
        if buf is None or buf[0].shape != pa["v"].shape:
            buf = (np.empty_like(pa["v"]), np.empty_like(pa["rho"]))
            self._buffers = buf
        v_half, rho_half = buf
        pressure = pressure_variable(pa)
        kick(pa["v"], pa["rho"], pa["dv"], pa["drho"], 0.5 * dt)
        if pressure is not None:
            pressure[0][:] += 0.5 * dt * pressure[1]
            p_half = pressure[0].copy()
            pressure[0][:] += 0.5 * dt * pressure[1]
        drift(pa["x"], pa["v"], pa["xsph"], dt)
        np.copyto(v_half, pa["v"])
        np.copyto(rho_half, pa["rho"])
        kick(pa["v"], pa["rho"], pa["dv"], pa["drho"], 0.5 * dt)   # predicted to t + dt with the old rates
        sim.evaluate(sim.time + dt)
        np.copyto(pa["v"], v_half)
        np.copyto(pa["rho"], rho_half)
        kick(pa["v"], pa["rho"], pa["dv"], pa["drho"], 0.5 * dt)
        if pressure is not None:
            np.add(p_half, 0.5 * dt * pressure[1], out=pressure[0])


INTEGRATORS = {"symplectic": Symplectic, "leapfrog": LeapFrog, "leapfrog-predicted": PredictedLeapFrog}
