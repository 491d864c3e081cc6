"""The wall-model contract, checked for every registered model (read from the registry).

A model added to ``seawall.boundary.registry.BOUNDARIES`` is covered automatically:

* ``prepare`` / ``update`` / ``interact`` keep the shapes and dtypes of the fluid's and the
  wall's arrays and give finite rates;
* the registry builds it and it declares the contract (layout, fluid terms, options; its ``--set``
  keys collide with no case parameter);
* a short run stays finite;
* a checkpoint restarts into the uninterrupted run bit for bit;
* the force the ``WallForce`` probe reports is minus the change of the fluid's momentum that
  the wall causes (the fluid-fluid terms and gravity account for the rest);
* for models that declare ``pairwise_momentum`` (``seawall.boundary.base.WallModel``), the
  wall's push on the fluid is a sum of one pair force per wall particle: splitting the wall
  particles into two sets adds up to the whole wall, so the wall's reaction is the sum of
  the pair reactions and fluid + wall conserve momentum.
"""

import copy

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.base import WallModel, check_contract
from seawall.boundary.registry import BOUNDARIES, boundary_by_name, boundary_option_defaults, boundary_options
from seawall.cases import CASES, build
from seawall.pairs import FLUID_TERMS
from seawall.particles import ParticleArrays

MODELS = list(BOUNDARIES)


def tank(boundary, dx=0.05):
    """Water 0.2 m deep at rest (p = 0) in a 0.5 m tank: it compresses under gravity and sloshes."""
    sim = build("hydrostatic", dx=dx, length=0.5, depth=0.2, height=0.3, initial="rest", boundary=boundary)
    sim.add(sw.probes.WallForce("fx", "tank", axis=0), sw.probes.WallForce("fy", "tank", axis=1))
    return sim


def moving_tank(boundary, steps=20):
    """The tank after a few steps, so that velocities (and viscous wall terms) are not zero."""
    sim = tank(boundary)
    sim.run_steps(steps)
    sim.evaluate(sim.time)
    return sim


def layouts(particles):
    return {name: (a.shape, a.dtype) for name, a in particles.items()}


@pytest.mark.parametrize("boundary", MODELS)
def test_registry_builds_a_wall_model_that_declares_the_contract(boundary):
    model = boundary_by_name(boundary)
    assert isinstance(model, WallModel)
    check_contract(model)
    assert isinstance(type(model).pairwise_momentum, bool)
    assert model.layout in ("layers", "surface") and model.wall_layout == model.layout
    assert set(model.fluid_terms) <= set(FLUID_TERMS)
    assert isinstance(model.joins_summation_density, bool)
    assert all(isinstance(a, str) for a in model.integrated_arrays)
    options = type(model).options()
    assert all(isinstance(o, str) for o in options) and options == tuple(type(model).option_defaults())
    # the registry's --set keys are consumed by the factory, none collides with a case parameter
    keys = boundary_options(boundary)
    assert keys == tuple(boundary_option_defaults(boundary))
    for case in CASES.values():
        assert not set(keys) & set(case.parameters), (boundary, case.name)


@pytest.mark.parametrize("boundary", MODELS)
def test_update_and_interact_keep_arrays_and_give_finite_rates(boundary):
    sim = tank(boundary)            # prepare has run
    wall = sim.walls[0]
    fp = sim.fluid.particles
    wall_prepared = layouts(wall.particles)
    sim.run_steps(20)               # update and interact at every evaluation; the water is moving now
    fluid_running = layouts(fp)
    # update may add its state arrays at the first evaluation; no prepared array changes shape or dtype
    wall_running = layouts(wall.particles)
    for name, layout in wall_prepared.items():
        assert wall_running[name] == layout, name
    ctx = sw.boundary.base.EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.fluid_cells,
                                             time=sim.time, dx=sim.fluid.spacing)
    dv = np.zeros_like(fp["dv"])
    drho = np.zeros_like(fp["drho"])
    wall.model.update(wall, sim.fluid, ctx)
    wall.model.interact(sim.fluid, wall, ctx, dv, drho)
    assert layouts(wall.particles) == wall_running
    assert layouts(fp) == fluid_running
    assert dv.shape == (fp.n, 2) and dv.dtype == np.float64
    assert drho.shape == (fp.n,) and drho.dtype == np.float64
    assert np.all(np.isfinite(dv)) and np.all(np.isfinite(drho))
    # the water presses on the wall by now, so the wall pushes back on some particle
    assert np.abs(dv).max() > 0.0


@pytest.mark.parametrize("boundary", MODELS)
def test_short_run_stays_finite(boundary):
    sim = tank(boundary)
    result = sim.run(0.05, progress=False)
    fp = sim.fluid.particles
    for name in ("x", "v", "rho", "p", "dv", "drho"):
        assert np.all(np.isfinite(fp[name])), name
    for name, values in result.probes.items():
        assert np.all(np.isfinite(values)), name
    assert result.summary["escaped_particles"] == 0


@pytest.mark.parametrize("boundary", MODELS)
def test_restart_reproduces_the_uninterrupted_run_bit_for_bit(tmp_path, boundary):
    reference = tank(boundary)
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.03), every=0.01)
    ref_result = reference.run(0.05, progress=False)
    path = tmp_path / "checkpoint.h5"
    assert path.exists()
    second = tank(boundary)
    second.add(every=0.01)
    second.restart(str(path))
    assert 0.03 <= second.time < 0.05
    result = second.run(0.05, progress=False)
    assert second.step == reference.step
    for name in ("x", "v", "rho", "id"):
        assert np.array_equal(second.fluid.particles[name], reference.fluid.particles[name]), name
    for name in reference.walls[0].particles.names():
        assert np.array_equal(second.walls[0].particles[name], reference.walls[0].particles[name]), name
    assert np.array_equal(result.times, ref_result.times)
    for name in ref_result.probes:
        assert np.array_equal(result.probes[name], ref_result.probes[name], equal_nan=True), name


@pytest.mark.parametrize("boundary", MODELS)
def test_wall_force_is_minus_the_fluid_momentum_change_it_causes(boundary):
    sim = moving_tank(boundary)
    fp = sim.fluid.particles
    m = fp["m"][:, None]
    total = np.sum(m * fp["dv"], axis=0)                  # rate of change of the fluid's momentum
    weight = np.sum(fp["m"]) * sim.gravity
    force = np.array([sim.wall_forces["tank"][0], sim.wall_forces["tank"][1]])
    scale = np.sum(np.abs(m * fp["dv"]))
    # fluid-fluid pairs cancel (to rounding, ~1e-16 of the summed magnitudes), so the only momentum
    # the fluid gains besides its weight is what the wall gives it: minus the force on the wall
    assert np.allclose(total, weight - force, rtol=0.0, atol=1e-12 * scale)
    # the water presses the floor down (its size still oscillates: released at p = 0, it is compressing)
    assert force[1] < 0.0


def wall_part(wall, keep, grid):
    """A copy of ``wall`` holding only the particles ``keep`` (state as after the last update)."""
    part = copy.copy(wall)
    part.particles = ParticleArrays(wall.dim)
    for name, a in wall.particles.items():
        part.particles.add(name, a[keep])
    part.cells = grid.build(part.particles["x"])
    return part


@pytest.mark.parametrize("boundary", [b for b in MODELS if type(boundary_by_name(b)).pairwise_momentum])
def test_pairwise_models_push_the_fluid_by_one_pair_force_per_wall_particle(boundary):
    sim = moving_tank(boundary)
    wall = sim.walls[0]
    fp = sim.fluid.particles
    ctx = sw.boundary.base.EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.fluid_cells,
                                             time=sim.time, dx=sim.fluid.spacing)
    # the wall's state was set by update() in the last evaluation; interact alone is a sum over wall particles
    whole = np.zeros_like(fp["dv"])
    wall.model.interact(sim.fluid, wall, ctx, whole, np.zeros(fp.n))
    odd = (np.arange(wall.n) % 2).astype(bool)
    split = np.zeros_like(fp["dv"])
    for keep in (odd, ~odd):
        wall.model.interact(sim.fluid, wall_part(wall, keep, sim.grid), ctx, split, np.zeros(fp.n))
    scale = np.abs(whole).max()
    assert scale > 0.0
    # same pair terms summed in another order: equal to rounding (measured <= 1e-15 of the largest)
    assert np.allclose(split, whole, rtol=0.0, atol=1e-12 * scale)
    # and the reaction the wall feels, the sum of the pair reactions, is what WallForce reports
    reaction = -np.sum(fp["m"][:, None] * whole, axis=0)
    assert np.allclose(reaction, sim.wall_forces["tank"], rtol=0.0, atol=1e-12 * np.sum(fp["m"] * np.abs(whole).max()))
