"""Equations of state p(rho) for weakly compressible SPH, with their inverses.

* :class:`Tait` -- Tait/Cole: p = B [(rho/rho0)^gamma - 1] + p_b with
  B = c0^2 rho0 / gamma ([Li2022], eq. 9; Monaghan 1994). The optional
  background pressure p_b is added to every particle (Marrone et al. 2011).
* :class:`Linear` -- p = c0^2 (rho - rho0) + p_b ([Huang2019], sec. 2.1; it is
  also the first-order Taylor expansion of Tait, [Li2022] eq. 12).

Compiled code calls :func:`eos_pressure`, :func:`eos_density` and
:func:`eos_sound_speed` with an integer EOS id and scalars.
"""

import math

import numpy as np

from .errors import ParameterError, require_positive
from .jit import loop_helper

TAIT = 0
LINEAR = 1


@loop_helper
def eos_pressure(kind, rho, rho0, c0, gamma, p_background):
    """Pressure from density ([Li2022] eq. 9 for Tait, [Huang2019] for linear)."""
    if kind == TAIT:
        b = c0 * c0 * rho0 / gamma
        return b * ((rho / rho0) ** gamma - 1.0) + p_background
    return c0 * c0 * (rho - rho0) + p_background


@loop_helper
def eos_density(kind, p, rho0, c0, gamma, p_background):
    """Inverse of :func:`eos_pressure`.

    For Tait the pressure is floored at -B (zero density would follow) so
    that an extrapolated wall pressure far below the fluid's never produces
    NaN; the floor maps to 1e-3 rho0.
    """
    if kind == TAIT:
        b = c0 * c0 * rho0 / gamma
        ratio = (p - p_background) / b + 1.0
        if ratio < 1e-3 ** gamma:
            ratio = 1e-3 ** gamma
        return rho0 * ratio ** (1.0 / gamma)
    return rho0 + (p - p_background) / (c0 * c0)


@loop_helper
def eos_sound_speed(kind, rho, rho0, c0, gamma):
    """Local sound speed c = sqrt(dp/drho): c0 (rho/rho0)^((gamma-1)/2) for Tait, c0 for linear."""
    if kind == TAIT:
        return c0 * (rho / rho0) ** (0.5 * (gamma - 1.0))
    return c0


@loop_helper
def eos_state(kind, rho, rho0, c0, gamma, p_background):
    """(pressure, sound speed) of :func:`eos_pressure` and :func:`eos_sound_speed` with one power.

    Tait: with s = (rho/rho0)^((gamma-1)/2), (rho/rho0)^gamma = s^2 (rho/rho0) and c = c0 s
    ([Li2022] eq. 9 and its derivative). The power is most of an equation-of-state pass
    (1.0 of 1.6 ms per step at 80k particles, one thread, with two); the product agrees with the
    direct power to a few units in the last place.
    """
    if kind == TAIT:
        ratio = rho / rho0
        s = ratio ** (0.5 * (gamma - 1.0))
        b = c0 * c0 * rho0 / gamma
        return b * (s * s * ratio - 1.0) + p_background, c0 * s
    return c0 * c0 * (rho - rho0) + p_background, c0


class EquationOfState:
    """Description of an equation of state; compiled code uses ``kind`` and the scalars."""

    kind = -1

    def __init__(self, *, c0, gamma=1.0, background_pressure=0.0):
        self.c0 = require_positive("c0", c0)
        self.gamma = require_positive("gamma", gamma)
        self.background_pressure = float(background_pressure)
        if not math.isfinite(self.background_pressure):
            raise ParameterError("background_pressure must be finite")

    def pressure(self, rho, rho0):
        """Pressure for density array ``rho`` (numpy)."""
        rho = np.asarray(rho, dtype=np.float64)
        return np.vectorize(lambda r: eos_pressure(self.kind, r, rho0, self.c0, self.gamma,
                                                   self.background_pressure))(rho)

    def density(self, p, rho0):
        """Density for pressure array ``p`` (numpy)."""
        p = np.asarray(p, dtype=np.float64)
        return np.vectorize(lambda q: eos_density(self.kind, q, rho0, self.c0, self.gamma,
                                                  self.background_pressure))(p)

    def sound_speed(self, rho, rho0):
        rho = np.asarray(rho, dtype=np.float64)
        return np.vectorize(lambda r: eos_sound_speed(self.kind, r, rho0, self.c0, self.gamma))(rho)


class Tait(EquationOfState):
    """Tait/Cole EOS, p = B[(rho/rho0)^gamma - 1] + p_b, B = c0^2 rho0/gamma ([Li2022] eq. 9).

    Parameters
    ----------
    c0 : float
        Reference speed of sound [m/s]; usually 10 x the largest expected flow speed.
    gamma : float
        Exponent, 7 for water (Monaghan 1994; [Li2022]).
    background_pressure : float
        Constant added to every pressure [Pa], default 0.
    """

    kind = TAIT

    def __init__(self, *, c0, gamma=7.0, background_pressure=0.0):
        super().__init__(c0=c0, gamma=gamma, background_pressure=background_pressure)

    def __repr__(self):
        return f"Tait(c0={self.c0}, gamma={self.gamma}, background_pressure={self.background_pressure})"


class Linear(EquationOfState):
    """Linear EOS, p = c0^2 (rho - rho0) + p_b ([Huang2019], sec. 2.1)."""

    kind = LINEAR

    def __init__(self, *, c0, background_pressure=0.0):
        super().__init__(c0=c0, gamma=1.0, background_pressure=background_pressure)

    def __repr__(self):
        return f"Linear(c0={self.c0}, background_pressure={self.background_pressure})"

