"""Particle shifting and the transport-velocity formulation (seawall/fluid/regularisation.py)."""

import numpy as np
import pytest

from seawall import shapes
from seawall.boundary.base import WallSystem
from seawall.boundary.dummy import DummyParticles
from seawall.cases import build
from seawall.eos import Linear
from seawall.errors import ParameterError
from seawall.fluid import FluidSystem, LaminarViscosity, ParticleShifting, TransportVelocity
from seawall.fluid.regularisation import smallest_eigenvalue
from seawall.kernels import CubicSpline
from seawall.simulation import Simulation

DX = 0.05


def _periodic_lattice(shifting="lind2012", velocity=(0.3, -0.2)):
    fluid = FluidSystem(shapes.rectangle((0.0, 0.0), (1.0, 1.0), DX), rho0=1.0, eos=Linear(c0=10.0),
                        viscosity=LaminarViscosity(nu=0.01), velocity=velocity, shifting=shifting)
    return Simulation([fluid], kernel=CubicSpline(), h=1.3 * DX, gravity=(0.0, 0.0), threads=1,
                      domain=((0.0, 0.0), (1.0, 1.0)), periodic=(True, True))


def _free_block(shifting="lind2012", walls=None):
    fluid = FluidSystem(shapes.rectangle((0.0, 0.0), (0.6, 0.4), DX), rho0=1000.0, eos=Linear(c0=10.0),
                        viscosity=None, shifting=shifting)
    systems = [fluid]
    if walls is not None:
        tank = shapes.tank((0.0, 0.0), (0.6, 0.8), DX, layers=3)
        systems.append(WallSystem(tank, model=walls()))
    return Simulation(systems, kernel=CubicSpline(), h=1.3 * DX, gravity=(0.0, 0.0), threads=1,
                      domain=((-0.5, -0.5), (1.1, 1.3)), hull=None)


def test_shifting_vanishes_on_a_uniform_lattice():
    sim = _periodic_lattice()
    sim.evaluate(0.0)
    fp = sim.fluid.particles
    h = sim.h
    # |grad C| is a sum of O(1/h) terms that cancel exactly on the lattice
    assert np.abs(fp["grad_c"]).max() * h < 1e-12
    assert np.allclose(fp["lambda"], fp["lambda"][0]) and fp["lambda"].min() > 0.9
    x0 = fp["x"].copy()
    ids = fp["id"].copy()
    sim.run_steps(5)
    # a uniform translation keeps the lattice: shifting moved no particle relative to the others
    order = np.argsort(fp["id"])
    d = fp["x"][order] - x0[np.argsort(ids)]
    d -= np.round(d / 1.0)
    assert np.ptp(d[:, 0]) < 1e-12 and np.ptp(d[:, 1]) < 1e-12


def test_concentration_gradient_and_free_surface_detection():
    sim = _free_block()
    sim.evaluate(0.0)
    fp = sim.fluid.particles
    x = fp["x"]
    top = x[:, 1] > 0.4 - DX
    inner = (np.abs(x[:, 0] - 0.3) < 0.1) & (np.abs(x[:, 1] - 0.2) < 0.06)
    # the concentration falls outwards: grad C points into the fluid, so the outward normal
    # n = -grad C / |grad C| points up at the top row, and the unrestricted shift -grad C points out
    mid_top = top & (np.abs(x[:, 0] - 0.3) < 0.15)
    g = fp["grad_c"][mid_top]
    assert np.all(g[:, 1] < 0.0) and np.all(np.abs(g[:, 0]) < 0.05 * np.abs(g[:, 1]))
    assert fp["lambda"][top].max() < 0.75 < fp["lambda"][inner].min()
    # the corrected shift has no normal component at the surface
    before = x.copy()
    sim._apply_shifting(1e-3)
    shift = fp["x"] - before
    n = -fp["grad_c"] / np.linalg.norm(fp["grad_c"], axis=1)[:, None]
    assert np.abs(np.sum(shift[mid_top] * n[mid_top], axis=1)).max() < 1e-15
    # without the correction, the same particles would move out of the fluid
    sim.fluid.shifting = ParticleShifting("lind2012", free_surface=False)
    sim._apply_shifting(1e-3)
    assert np.all((fp["x"] - before - shift)[mid_top][:, 1] > 0.0)


class _Undeclared(DummyParticles):
    """Adami's dummy particles with "shifting" left out of the declaration."""

    @property
    def fluid_terms(self):
        return super().fluid_terms - {"shifting"}


def test_walls_count_in_the_concentration_through_their_declaration():
    declared = _free_block(walls=DummyParticles)
    undeclared = _free_block(walls=_Undeclared)
    assert "shifting" in declared.walls[0].model.fluid_terms
    assert "shifting" not in undeclared.walls[0].model.fluid_terms
    lam = {}
    for name, sim in (("declared", declared), ("undeclared", undeclared)):
        sim.evaluate(0.0)
        fp = sim.fluid.particles
        bottom = (fp["x"][:, 1] < DX) & (np.abs(fp["x"][:, 0] - 0.3) < 0.15)
        lam[name] = fp["lambda"][bottom]
    assert lam["declared"].min() > 0.9          # the wall completes the kernel support
    assert lam["undeclared"].max() < 0.75       # a particle beside an uncounted wall looks like a surface


def test_smallest_eigenvalue_closed_forms():
    rng = np.random.default_rng(3)
    for dim in (2, 3):
        for _ in range(20):
            a = rng.normal(size=(dim, dim))
            b = a @ a.T
            full = np.zeros((3, 3))
            full[:dim, :dim] = b
            got = smallest_eigenvalue(dim, full[0, 0], full[0, 1], full[0, 2], full[1, 1], full[1, 2], full[2, 2])
            assert got == pytest.approx(np.linalg.eigvalsh(b)[0], abs=1e-9)


def test_transport_velocity_with_zero_background_pressure_is_the_standard_scheme():
    runs = []
    for tvf in (None, TransportVelocity(background_pressure=0.0)):
        sim = build("taylor-green", n=20, threads=1)
        sim.set_regularisation(transport_velocity=tvf)
        sim.run(0.02, progress=False)
        fp = sim.fluid.particles
        order = np.argsort(fp["id"])
        runs.append((fp["x"][order].copy(), fp["v"][order].copy(), fp["rho"][order].copy(), sim.step))
    assert runs[0][3] == runs[1][3]
    for a, b in zip(runs[0][:3], runs[1][:3]):
        assert np.abs(a - b).max() <= 1e-14 * max(1.0, np.abs(a).max())


def test_transport_velocity_moves_particles_off_the_flow_and_back_to_order():
    # a perturbed periodic lattice at rest: the background pressure term pushes it towards uniformity
    rng = np.random.default_rng(1)
    sim = _periodic_lattice(shifting=None, velocity=(0.0, 0.0))
    sim.set_regularisation(transport_velocity=TransportVelocity(background_factor=1.0))
    fp = sim.fluid.particles
    fp["x"] += rng.uniform(-0.1, 0.1, fp["x"].shape) * DX
    sim.evaluate(0.0)
    spread0 = np.linalg.norm(fp["grad_c"], axis=1).max()
    sim.run(0.05, progress=False)
    sim.evaluate(sim.time)
    assert np.linalg.norm(fp["grad_c"], axis=1).max() < 0.5 * spread0


def test_case_options_and_refusals():
    sim = build("taylor-green", n=20, threads=1, shifting="lind2012")
    assert sim.fluid.shifting.kind == "lind2012"
    assert sim.metadata["parameters"]["shifting"] == "lind2012"
    with pytest.raises(ParameterError, match="^shifting must be one of"):
        build("taylor-green", n=20, threads=1, shifting="sun2018")
    with pytest.raises(ParameterError, match="^transport_velocity must be true or false"):
        build("taylor-green", n=20, threads=1, transport_velocity="maybe")
    with pytest.raises(ParameterError, match="^tvf_background must be a finite number"):
        build("taylor-green", n=20, threads=1, transport_velocity="true", tvf_background="-1")
    with pytest.raises(ParameterError, match="free-surface correction"):
        build("dam-break", dx=0.02, threads=1, transport_velocity="true")
    sim = build("dam-break", dx=0.02, threads=1, transport_velocity="true", tvf_free_surface="true")
    assert sim.fluid.transport_velocity.free_surface
    sim = build("cavity", threads=1, transport_velocity="true")
    assert sim.fluid.transport_velocity is not None
    with pytest.raises(ParameterError, match="^shifting must be one of"):
        FluidSystem(shapes.rectangle((0.0, 0.0), (0.2, 0.2), DX), eos=Linear(c0=10.0), shifting="sideways")


def test_restart_with_shifting_and_transport_velocity_continues_bit_for_bit(tmp_path):
    def make():
        return build("taylor-green", n=16, threads=1, shifting="sun2017", transport_velocity="true")

    path = str(tmp_path / "checkpoint.h5")
    reference = make()
    reference.add(every=0.005)
    reference.run(0.01, progress=False)
    reference.save_checkpoint(path)
    reference.run(0.02, progress=False)
    second = make()
    second.add(every=0.005)
    second.restart(path)
    assert 0.01 <= second.time < 0.02
    second.run(0.02, progress=False)
    assert second.step == reference.step
    for name in ("x", "v", "rho", "id"):
        assert np.array_equal(second.fluid.particles[name], reference.fluid.particles[name]), name
    # a checkpoint of another scheme is refused
    other = build("taylor-green", n=16, threads=1, shifting="lind2012", transport_velocity="true")
    with pytest.raises(ParameterError, match="shifting"):
        other.restart(path)
