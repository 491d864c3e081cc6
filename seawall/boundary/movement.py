"""Prescribed motion of wall particles ([TrixiBoundary], "BoundaryMovement"; PrescribedMotion today).

``PrescribedMotion(movement_function, is_moving)`` moves the chosen wall
particles to x(t) = x0 + f(t), where ``movement_function`` f returns a
d-vector ([TrixiBoundary]). Their velocity f'(t) and acceleration f''(t) -- which
the Adami extrapolation needs (the term rho_f (g - a_b) . r_bf) -- come from
the ``velocity`` and ``acceleration`` functions when given, otherwise from
central differences of f with step 1e-5 (relative error ~1e-10 for smooth f
on the time scales of a wave maker; tested against analytic derivatives).
While ``is_moving(t)`` is false the particles stay put, with zero velocity and
acceleration, and the neighbour structures are not rebuilt.
"""

import numpy as np

from ..errors import ParameterError

DIFF_STEP = 1e-5  # s, central-difference step for f' and f''


class PrescribedMotion:
    """Rigid prescribed motion of (a subset of) a wall's particles.

    Parameters
    ----------
    movement_function : callable t -> sequence of d floats
        Displacement of the moving particles from their initial positions [m].
    is_moving : callable t -> bool, optional
        Whether the particles move at time t (default: always).
    moving_particles : array of int, optional
        Indices (in the wall's initial order) of the particles that move;
        default all.
    velocity, acceleration : callable t -> d floats, optional
        Exact derivatives of ``movement_function``; central differences otherwise.
    """

    def __init__(self, movement_function, is_moving=None, *, moving_particles=None, velocity=None,
                 acceleration=None):
        if not callable(movement_function):
            raise ParameterError("movement_function must be a function of time returning a d-vector")
        for name, f in (("is_moving", is_moving), ("velocity", velocity), ("acceleration", acceleration)):
            if f is not None and not callable(f):
                raise ParameterError(f"{name} must be a function of time")
        self.movement_function = movement_function
        self.is_moving = is_moving if is_moving is not None else (lambda t: True)
        self.moving_particles = None if moving_particles is None else np.asarray(moving_particles, dtype=np.int64)
        self._velocity = velocity
        self._acceleration = acceleration

    def displacement(self, t):
        return np.asarray(self.movement_function(t), dtype=np.float64)

    def velocity(self, t):
        if self._velocity is not None:
            return np.asarray(self._velocity(t), dtype=np.float64)
        e = DIFF_STEP
        return (self.displacement(t + e) - self.displacement(t - e)) / (2 * e)

    def acceleration(self, t):
        if self._acceleration is not None:
            return np.asarray(self._acceleration(t), dtype=np.float64)
        e = DIFF_STEP * 10  # a wider step: the second difference loses digits faster
        return (self.displacement(t + e) - 2 * self.displacement(t) + self.displacement(t - e)) / (e * e)

    def attach(self, wall):
        """Remember initial positions and the moving subset in the wall's arrays (they follow reordering)."""
        pa = wall.particles
        n = wall.n
        moving = np.zeros(n, dtype=bool)
        if self.moving_particles is None:
            moving[:] = True
        else:
            if self.moving_particles.size and (self.moving_particles.min() < 0 or self.moving_particles.max() >= n):
                raise ParameterError(f"moving_particles must be indices in 0..{n - 1}")
            moving[self.moving_particles] = True
        d = self.displacement(0.0)
        if d.shape != (wall.dim,):
            raise ParameterError(f"movement_function must return {wall.dim} components, got shape {d.shape}")
        pa["x0"] = pa["x"] - np.where(moving[:, None], d[None, :], 0.0)
        pa["moving"] = moving

    def apply(self, wall, t):
        """Set positions, velocities and accelerations of the moving particles at time t; True if they move."""
        pa = wall.particles
        moving = pa["moving"]
        if not self.is_moving(t):
            pa["v"][moving] = 0.0
            pa["a"][moving] = 0.0
            return False
        pa["x"][moving] = pa["x0"][moving] + self.displacement(t)
        pa["v"][moving] = self.velocity(t)
        pa["a"][moving] = self.acceleration(t)
        return True


def sinusoidal_piston(amplitude, period, axis=0, dim=2):
    """Displacement A (1 - cos(2 pi t / T)) / 2 along ``axis``: starts from rest, pushes in and back."""
    omega = 2 * np.pi / period

    def displacement(t):
        d = np.zeros(dim)
        d[axis] = 0.5 * amplitude * (1.0 - np.cos(omega * t))
        return d

    def velocity(t):
        d = np.zeros(dim)
        d[axis] = 0.5 * amplitude * omega * np.sin(omega * t)
        return d

    def acceleration(t):
        d = np.zeros(dim)
        d[axis] = 0.5 * amplitude * omega * omega * np.cos(omega * t)
        return d

    return displacement, velocity, acceleration
