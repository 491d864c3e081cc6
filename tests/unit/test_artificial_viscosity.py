"""Artificial viscosity as a shear viscosity: Monaghan's switch ([Li2022] eq. 6) against every pair ([Huang2019] eq. 5).

A periodic sine shear u = U sin(k y), v = 0, at uniform density has no pressure
force, so the fluid's acceleration is the viscous term alone. On every pair
the artificial viscosity is the shear viscosity nu = alpha h c0 / (2 (d + 2)),
alpha h c0 / 8 in 2D (derivation in docs/formulas.md), giving
du/dt = nu d2u/dy2 = -nu k^2 U sin(k y). Measured at 40 particles per
wavelength, h = 1.3 dx (amplitude of the fitted sine over the exact one):
Gaussian cut at 3h (marrone2011) 0.923 with every pair (largest pointwise
deviation 7.7 % of the exact amplitude), 0.462 with Monaghan's switch (the
ratio of the two is 0.50); tolerance 10 % as asked of the scheme. (The cubic
spline gives 0.861 with every pair at this h/dx: not asserted here.)
"""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.cases.flows import channel_walls
from seawall.boundary.base import WallSystem
from seawall.boundary.ghost import GhostParticles
from seawall.fluid.presets import marrone2011

U, C0, RHO0 = 0.1, 10.0, 1000.0
N = 40  # particles per wavelength
L = 1.0
DX = L / N
H = 1.3 * DX


def fitted_amplitude(y, a, k, phase):
    """Least-squares amplitude A of a = A f(k y), f = sin or cos."""
    f = np.sin(k * y) if phase == "sin" else np.cos(k * y)
    return float(np.sum(a * f) / np.sum(f * f)), f


def shear_acceleration(fluid_factory, kernel):
    """du/dt of every particle of the periodic sine shear, and the exact nu d2u/dy2 (nu from alpha)."""
    block = sw.shapes.rectangle((0.0, 0.0), (L, L), DX)
    y = block.positions[:, 1]
    k = 2.0 * math.pi / L
    velocity = np.stack([U * np.sin(k * y), np.zeros_like(y)], axis=1)
    fluid = fluid_factory(block, velocity)
    sim = sw.Simulation([fluid], kernel=kernel, h=H, gravity=(0.0, 0.0), threads=1,
                        domain=((0.0, 0.0), (L, L)), periodic=(True, True))
    sim.evaluate(0.0)
    fp = fluid.particles
    nu = fluid.artificial_viscosity.alpha * H * C0 / 8.0
    return fp["x"][:, 1], fp["dv"][:, 0], -nu * k * k * U, k


def marrone_fluid(block, velocity):
    return marrone2011(C0).fluid(block, rho0=RHO0, velocity=velocity)


def gaussian_fluid(all_pairs):
    """The marrone2011 fluid with the artificial viscosity's switch chosen here."""
    def make(block, velocity):
        return sw.FluidSystem(block, rho0=RHO0, eos=sw.Linear(c0=C0), density_diffusion=sw.DeltaSPH(delta=0.1),
                              viscosity=sw.ArtificialViscosity(alpha=0.02, all_pairs=all_pairs), velocity=velocity)
    return make


def test_marrone2011_viscosity_is_the_shear_viscosity_alpha_h_c0_over_8():
    y, a, exact, k = shear_acceleration(marrone_fluid, sw.Gaussian())
    amp, f = fitted_amplitude(y, a, k, "sin")
    assert amp == pytest.approx(exact, rel=0.10)
    assert np.max(np.abs(a - exact * f)) < 0.10 * abs(exact)


def test_monaghan_switch_gives_about_half_the_shear_stress():
    amps = {}
    for all_pairs in (True, False):
        y, a, exact, k = shear_acceleration(gaussian_fluid(all_pairs), sw.Gaussian())
        amps[all_pairs] = fitted_amplitude(y, a, k, "sin")[0]
    assert 0.4 < amps[False] / amps[True] < 0.6


def test_all_pairs_needs_beta_zero():
    with pytest.raises(sw.ParameterError, match="beta"):
        sw.ArtificialViscosity(alpha=0.02, beta=0.1, all_pairs=True)
    with pytest.raises(sw.ParameterError, match="all_pairs"):
        sw.ArtificialViscosity(all_pairs="yes")
    assert sw.ArtificialViscosity().all_pairs is False


def test_ghost_wall_applies_the_viscosity_on_every_pair_too():
    # u = U cos(k y) between free-slip ghost walls at y = 0 and y = L/2 is even about both walls, so the
    # mirrored ghost velocities continue it; the rows next to the walls get nu d2u/dy2 only if the
    # fluid-ghost pairs follow the fluid's all-pairs switch as the fluid-fluid pairs do.
    width = 0.5 * L
    block = sw.shapes.rectangle((0.0, 0.0), (L, width), DX)
    y = block.positions[:, 1]
    k = 2.0 * math.pi / width
    velocity = np.stack([U * np.cos(k * y), np.zeros_like(y)], axis=1)
    fluid = marrone2011(C0).fluid(block, rho0=RHO0, velocity=velocity)
    kernel = sw.Gaussian()
    layers = int(math.ceil(kernel.support(H) / DX))
    bottom, top = channel_walls(L, width, DX, layers)
    walls = [WallSystem(s, model=GhostParticles("mls2", slip="free"), name=n) for s, n in ((bottom, "b"), (top, "t"))]
    margin = (layers + 2) * DX
    sim = sw.Simulation([fluid, *walls], kernel=kernel, h=H, gravity=(0.0, 0.0), threads=1,
                        domain=((0.0, -margin), (L, width + margin)), periodic=(True, False))
    sim.evaluate(0.0)
    a = fluid.particles["dv"][:, 0]
    y = fluid.particles["x"][:, 1]
    nu = 0.02 * H * C0 / 8.0
    amplitude = nu * k * k * U
    deviation = np.abs(a + amplitude * np.cos(k * y)) / amplitude
    first_row = (y < DX) | (y > width - DX)
    interior = (y > 4 * H) & (y < width - 4 * H)  # out of the walls' reach (Gaussian support 3h)
    # measured: largest deviation 8.5 % in the first rows, 8.6 % inside (the lattice error of the
    # periodic case); with the ghost pairs on Monaghan's switch the first rows deviate by 11.4 %
    assert np.max(deviation) < 0.10
    assert abs(np.max(deviation[first_row]) - np.max(deviation[interior])) < 0.01
