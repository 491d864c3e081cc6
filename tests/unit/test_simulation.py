"""Simulation machinery: restart continues bit for bit, the blow-up guard, escaped particles."""

import numpy as np
import pytest

import seawall as sw
from seawall import shapes
from seawall.cases import build
from seawall.errors import InstabilityError, ParameterError


def small_tank(dx=0.05, boundary="adami"):
    return build("hydrostatic", dx=dx, length=0.5, depth=0.2, height=0.3, initial="rest", boundary=boundary)


@pytest.mark.parametrize("boundary", ["adami", "continuity", "dbc", "ghost-shepard"])
def test_restart_continues_identically(tmp_path, boundary):
    # the checkpoint written during an uninterrupted run (at the first step after 0.06 s)
    # must restart into exactly the same trajectory, wall models with their own state included
    reference = small_tank(boundary=boundary)
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.06), every=0.01)
    ref_result = reference.run(0.1, progress=False)
    path = tmp_path / "checkpoint.h5"
    assert path.exists()

    second = small_tank(boundary=boundary)
    second.add(every=0.01)
    second.restart(str(path))
    assert 0.06 <= second.time < 0.07
    result = second.run(0.1, progress=False)

    assert second.step == reference.step
    for name in ("x", "v", "rho", "id"):
        assert np.array_equal(second.fluid.particles[name], reference.fluid.particles[name]), name
    assert np.array_equal(result.times, ref_result.times)
    for name in ref_result.probes:
        assert np.array_equal(result.probes[name], ref_result.probes[name], equal_nan=True)


def test_restart_rejects_a_different_simulation(tmp_path):
    a = small_tank()
    a.run_steps(1)
    path = tmp_path / "a.h5"
    a.save_checkpoint(str(path))
    b = build("hydrostatic", dx=0.025, length=0.5, depth=0.2, height=0.3)
    with pytest.raises(ParameterError, match="does not match"):
        b.restart(str(path))


def test_guard_names_step_time_and_particle(tmp_path):
    sim = small_tank()
    sim.add(sw.output.Checkpoint(str(tmp_path), every=0.005))
    sim.run(0.01, progress=False)
    # poison one particle: the next step must stop with where and when
    victim = 7
    sim.fluid.particles["v"][victim, 0] = np.nan
    pid = int(sim.fluid.particles["id"][victim])
    with pytest.raises(InstabilityError) as info:
        sim.run(0.02, progress=False)
    err = info.value
    assert err.particle_id == pid
    assert err.step == sim.step and err.time == pytest.approx(sim.time)
    assert f"particle id {pid}" in str(err) and "step" in str(err)
    assert err.checkpoint is not None and (tmp_path / "checkpoint.h5").exists()


def test_density_band_guard():
    sim = small_tank()
    sim.run_steps(1)
    sim.fluid.particles["rho"][3] = 5000.0
    with pytest.raises(InstabilityError, match="density"):
        sim.run_steps(1)


def test_escaped_particles_are_removed_and_counted():
    # a free jet with no walls flies out of a small domain: removed, counted, no crash
    fluid = sw.FluidSystem(shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0),
                           velocity=(3.0, 0.0))
    sim = sw.Simulation([fluid], h=0.013, domain=((-0.05, -0.05), (0.3, 0.2)))
    sim.add(sw.probes.TotalMass())
    result = sim.run(0.15, progress=False)
    assert result.summary["escaped_particles"] == 100
    assert sim.fluid.n == 0
    assert abs(result.summary["mass_drift"]) < 1e-12
    assert len(result.escaped) == 100 and all(rec[2] >= 0.3 for rec in result.escaped)


def test_fluid_overlapping_wall_is_an_error():
    fluid = sw.FluidSystem(shapes.rectangle((-0.02, 0), (0.2, 0.1), 0.01), eos=sw.Tait(c0=10.0))
    wall = sw.WallSystem(shapes.tank((0, 0), (0.3, 0.2), 0.01))
    with pytest.raises(ParameterError, match="overlaps wall"):
        sw.Simulation([fluid, wall], h=0.013, gravity=(0, -9.81))


@pytest.mark.parametrize("kwargs,match", [
    ({"h": 0.0}, "h must be"), ({"h": -1.0}, "h must be"),
    ({"h": 0.013, "gravity": (0, 0, -9.81)}, "gravity"),
])
def test_bad_simulation_parameters(kwargs, match):
    fluid = sw.FluidSystem(shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0))
    with pytest.raises(ParameterError, match=match):
        sw.Simulation([fluid], **kwargs)


@pytest.mark.parametrize("kwargs,match", [
    ({"rho0": 0.0}, "rho0"), ({"rho0": -5.0}, "rho0"),
])
def test_bad_fluid_parameters(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        sw.FluidSystem(shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0), **kwargs)


def test_periodic_shear_free_flow_is_uniform_translation():
    # a fully periodic box of fluid moving uniformly: no force, nothing leaves, exact translation
    dx = 0.01
    fluid = sw.FluidSystem(shapes.rectangle((0, 0), (0.2, 0.2), dx), eos=sw.Tait(c0=10.0),
                           velocity=(1.0, 0.5), density_diffusion=sw.DeltaSPH())
    sim = sw.Simulation([fluid], h=1.3 * dx, domain=((0, 0), (0.2, 0.2)), periodic=(True, True))
    x0 = sim.fluid.particles["x"].copy()
    sim.run(0.05, progress=False)
    v = sim.fluid.particles["v"]
    assert np.allclose(v, [1.0, 0.5], atol=1e-9)
    order = np.argsort(sim.fluid.particles["id"])
    moved = (sim.fluid.particles["x"][order] - x0) % 0.2
    assert np.allclose(moved, [0.05 % 0.2, 0.025], atol=1e-9)


def test_lagged_and_exact_renormalised_gradient_agree_in_still_water():
    # the one-pass (lagged) delta-SPH gradient must not change a settled hydrostatic state
    results = []
    for lagged in (True, False):
        sim = build("hydrostatic", dx=0.04, length=0.6, depth=0.24, height=0.32, lagged_gradient=lagged)
        sim.add(every=0.01)
        results.append(sim.run(0.3, progress=False))
    a, b = results
    for name in ("P0", "P1"):
        assert np.allclose(a[name], b[name], rtol=2e-3), name


def test_lagged_gradient_equals_exact_gradient_of_the_previous_state():
    # after one evaluation the stored "next" gradient is the exact gradient of that state
    from seawall.fluid.rates import renormalised_density_gradient
    sim = build("dam-break", dx=0.02, lagged_gradient=True)
    sim.run_steps(3)
    fp = sim.fluid.particles
    g = sim.grid
    sim.evaluate(sim.time)
    lagged = fp["grad_rho"].copy()  # swapped in: the gradient of the state just evaluated
    exact = np.zeros_like(lagged)
    renormalised_density_gradient(g.layout, fp["x"], fp["rho"], fp["volume"], sim.fluid_cells.start,
                                  sim.fluid_cells.order, g.lo, g.inv_cell, g.ncell, g.period, sim.physics, exact)
    assert np.allclose(lagged, exact, rtol=1e-9, atol=1e-9 * np.abs(exact).max())


class _CountingPush(sw.coupling.Coupling):
    """Adds a constant acceleration and counts its calls; its counter is checkpointed state."""

    name = "push"

    def __init__(self, acceleration):
        self.acceleration = acceleration
        self.steps = 0
        self.evaluations = 0

    def add_rates(self, sim, ctx):
        self.evaluations += 1
        sim.fluid.particles["dv"][:, 0] += self.acceleration

    def after_step(self, sim, dt):
        self.steps += 1

    def state(self):
        return {"steps": self.steps, "evaluations": self.evaluations}

    def set_state(self, state):
        self.steps = state["steps"]
        self.evaluations = state["evaluations"]

    def summary(self):
        return {"steps": self.steps}


def test_coupling_hooks_are_called_every_step_and_checkpointed(tmp_path):
    plain = small_tank()
    plain.evaluate(0.0)
    sim = small_tank()
    push = _CountingPush(0.5)
    sim.couple(push)
    sim.evaluate(0.0)
    # the coupling's acceleration is added on top of everything else, exactly
    assert np.allclose(sim.fluid.particles["dv"][:, 0] - plain.fluid.particles["dv"][:, 0], 0.5, atol=1e-12)
    assert np.array_equal(sim.fluid.particles["dv"][:, 1], plain.fluid.particles["dv"][:, 1])
    push.evaluations = 0
    with pytest.raises(ParameterError, match="unique"):
        sim.couple(_CountingPush(1.0))
    result = sim.run(0.02, progress=False)
    assert push.steps == sim.step
    assert push.evaluations == sim.step + 1          # one evaluation per step plus the first
    assert result.summary["couplings"]["push"]["steps"] == sim.step

    path = tmp_path / "c.h5"
    sim.save_checkpoint(str(path))
    again = small_tank()
    restored = _CountingPush(0.5)
    again.couple(restored).restart(str(path))
    assert restored.steps == push.steps and restored.evaluations == push.evaluations
