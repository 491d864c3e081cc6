"""A rigid wall on a spring that gives way under a wave's impact ([Huang2019] sec. 4.4, after Liang et al. 2017).

The wall (mass m per metre, spring stiffness k, relaxed at its initial
position x0) stays put until the force of the fluid on it exceeds the
threshold F_threshold = r F_static (r = 1.10 in [Huang2019]; F_static the
hydrostatic force). [Huang2019] sec. 4.4 integrates, once per time step n:

    a_n     = ((F_n - F_threshold) - k (x_n - x0)) / m    if F_n > F_threshold
    a_n     = -k (x_n - x0) / m                           otherwise
    v_{n+1} = v_n + a_n dt
    x_{n+1} = x_n + v_{n+1} dt   if that exceeds x0,   else x0

with F_n the impact force of [Huang2019] eq. 29, the pairwise force of the
fluid on the wall particles, F = sum_i m_i sum_j m_j/rho_j (p_j/rho_j +
p_i/rho_i) grad_i W_ij for the pressure part (read from
``sim.wall_forces``, which every wall model fills with minus what the wall
adds to sum_i m_i dv_i/dt, the same pairwise sum for a momentum-conserving
model).

Choices where the seed is silent (docs/waves.md):

* when the wall is stopped at x0 (the last case) its velocity is set to zero:
  a wall resting against its stop does not keep a backward velocity;
* F_n is the force of the last evaluation of the rates (the mid-step
  evaluation of the symplectic scheme); the wall's new position and velocity
  are then prescribed to its particles for the next step (explicit coupling,
  as the seed's update). The acceleration a_n is given to the wall particles
  for the pressure extrapolation of dummy/ghost walls.
"""

import numpy as np

from .coupling import Coupling
from .errors import ParameterError, require_nonnegative, require_positive
from .waves import RigidMotion


class SpringWall(Coupling):
    """Spring-mounted rigid wall driven by the fluid's force ([Huang2019] sec. 4.4).

    Parameters
    ----------
    wall : str
        Name of the wall system that moves (all its particles).
    mass : float
        Mass of the wall per metre [kg/m] (2D) or [kg] (3D).
    stiffness : float
        Spring stiffness k [N/m per metre] (k >= 0).
    static_force : float
        Hydrostatic force on the wall F_static [N/m] (> 0).
    threshold_ratio : float
        F_threshold / F_static ([Huang2019]: 1.10).
    axis : int
        Axis along which the wall moves; the force along +axis pushes it.
    name : str
        Coupling name (summary.json, checkpoints).
    """

    def __init__(self, wall, *, mass, stiffness, static_force, threshold_ratio=1.10, axis=0,
                 name="spring_wall"):
        self.wall_name = str(wall)
        self.mass = require_positive("mass", mass)
        self.stiffness = require_nonnegative("stiffness", stiffness)
        self.static_force = require_positive("static_force", static_force)
        self.threshold_ratio = require_positive("threshold_ratio", threshold_ratio)
        self.threshold = self.threshold_ratio * self.static_force
        self.axis = int(axis)
        self.name = str(name)
        self.displacement = 0.0   # x_n - x0 [m]
        self.velocity = 0.0       # v_n [m/s]
        self.acceleration = 0.0   # a_{n-1} [m/s^2]
        self.force = 0.0          # F of the last step [N/m]
        self.started = False
        self.onset_time = None
        self.max_displacement = 0.0
        self.max_force = 0.0

    # --------------------------------------------------------------- hooks
    def prepare(self, sim):
        walls = {w.name: w for w in sim.walls}
        if self.wall_name not in walls:
            raise ParameterError(f"coupling {self.name!r}: no wall named {self.wall_name!r}")
        if not 0 <= self.axis < sim.dim:
            raise ParameterError(f"coupling {self.name!r}: axis must be in 0..{sim.dim - 1}, got {self.axis}")
        wall = walls[self.wall_name]
        if wall.movement is not None:
            raise ParameterError(f"coupling {self.name!r}: wall {self.wall_name!r} already has a prescribed movement")
        dim = sim.dim

        def vec(value):
            out = np.zeros(dim)
            out[self.axis] = value
            return out

        wall.movement = RigidMotion(lambda t: vec(self.displacement), is_moving=lambda t: self.started,
                                    velocity=lambda t: vec(self.velocity),
                                    acceleration=lambda t: vec(self.acceleration))
        wall.movement.attach(wall)
        sim.wall_forces.setdefault(self.wall_name, np.zeros(dim))
        self._sim = sim

    def step_motion(self, force, dt):
        """Advance the wall by one step under the force ``force`` ([Huang2019] sec. 4.4); returns (x - x0, v, a)."""
        self.force = float(force)
        spring = self.stiffness * self.displacement
        if self.force > self.threshold:
            a = ((self.force - self.threshold) - spring) / self.mass
        else:
            a = -spring / self.mass
        v = self.velocity + a * dt
        x = self.displacement + v * dt
        if x <= 0.0:
            x, v = 0.0, 0.0   # against its stop: never behind x0, no backward velocity kept
        self.acceleration, self.velocity, self.displacement = a, v, x
        self.max_displacement = max(self.max_displacement, x)
        self.max_force = max(self.max_force, self.force)
        return x, v, a

    def after_step(self, sim, dt):
        force = float(sim.wall_forces[self.wall_name][self.axis])
        x, v, _ = self.step_motion(force, dt)
        if not self.started and (x > 0.0 or v != 0.0):
            self.started = True
            self.onset_time = float(sim.time)

    # --------------------------------------------------------------- state
    def state(self):
        return {"displacement": self.displacement, "velocity": self.velocity, "acceleration": self.acceleration,
                "force": self.force, "started": self.started, "onset_time": self.onset_time,
                "max_displacement": self.max_displacement, "max_force": self.max_force}

    def set_state(self, state):
        if not state:
            return
        self.displacement = float(state["displacement"])
        self.velocity = float(state["velocity"])
        self.acceleration = float(state["acceleration"])
        self.force = float(state["force"])
        self.started = bool(state["started"])
        self.onset_time = state["onset_time"]
        self.max_displacement = float(state["max_displacement"])
        self.max_force = float(state["max_force"])

    def summary(self):
        return {"mass": self.mass, "stiffness": self.stiffness, "static_force": self.static_force,
                "threshold": self.threshold, "onset_time": self.onset_time,
                "final_displacement": self.displacement, "max_displacement": self.max_displacement,
                "max_force_over_static": self.max_force / self.static_force}

    def describe(self):
        return (f"spring-mounted wall {self.wall_name!r} (m = {self.mass:g}, k = {self.stiffness:g}, "
                f"threshold {self.threshold_ratio:g} F_static)")
