"""Open boundaries ([TrixiBoundary]): characteristic inversion, zone geometry, particle exchange, buffer accounting."""

import numpy as np
import pytest

import seawall as sw
from seawall import shapes
from seawall.cases import build
from seawall.errors import ParameterError
from seawall.openboundary import (InFlow, OpenBoundary, OutFlow, characteristic_variables,
                                  invert_characteristics)


# ---------------------------------------------------------------- the characteristic relations
@pytest.mark.parametrize("dim", [2, 3])
def test_inversion_recovers_rho_v_p_exactly(dim):
    rng = np.random.default_rng(1)
    m = 50
    c = 17.0
    n = rng.normal(size=dim)
    n /= np.linalg.norm(n)
    rho_ref = 1000 + rng.normal(size=m)
    p_ref = rng.normal(size=m) * 100
    v_ref = rng.normal(size=(m, dim))
    rho = rho_ref + rng.normal(size=m) * 3
    p = p_ref + rng.normal(size=m) * 300
    # the characteristics carry the normal component only: v differs from v_ref along n
    v = v_ref + rng.normal(size=m)[:, None] * n
    J1, J2, J3 = characteristic_variables(rho, v @ n, p, rho_ref, v_ref @ n, p_ref, c)
    rho2, v2, p2 = invert_characteristics(J1, J2, J3, rho_ref, v_ref, p_ref, c, n)
    assert np.allclose(rho2, rho, rtol=1e-13, atol=0)
    assert np.allclose(p2, p, rtol=0, atol=1e-9)
    assert np.allclose(v2, v, rtol=0, atol=1e-12)


def test_characteristics_vanish_at_the_reference():
    J = characteristic_variables(998.0, 0.3, 12.0, 998.0, 0.3, 12.0, 20.0)
    assert np.allclose(J, 0.0)


# ---------------------------------------------------------------- zone geometry and input checks
def test_zone_boxes_2d_and_3d():
    inflow = InFlow(plane=((0, 0), (0, 0.1)), flow_direction=(1, 0), open_boundary_layers=4,
                    particle_spacing=0.01, density=1000)
    assert inflow.positions.shape == (40, 2)
    assert np.allclose(inflow.positions[:, 0].min(), -0.035) and np.allclose(inflow.positions[:, 0].max(), -0.005)
    outflow = OutFlow(plane=((0, 0, 0), (0.1, 0, 0), (0, 0.05, 0)), flow_direction=(0, 0, 1),
                      open_boundary_layers=3, particle_spacing=0.01, density=1000)
    assert outflow.positions.shape == (10 * 5 * 3, 3)
    assert np.allclose(np.sort(np.unique(outflow.positions[:, 2].round(9))), [0.005, 0.015, 0.025])
    # extruded geometry: points on the plane, extruded upstream
    line = np.column_stack([np.zeros(3), [0.015, 0.025, 0.035]])
    ex = InFlow(plane=((0, 0), (0, 0.1)), flow_direction=(1, 0), open_boundary_layers=2, particle_spacing=0.01,
                density=1000, extrude_geometry=line)
    assert ex.positions.shape == (6, 2) and np.all(ex.positions[:, 0] < 0)
    # initial condition cut to the box
    ic = shapes.rectangle((-0.1, 0.0), (0.05, 0.1), 0.01)
    cut = InFlow(plane=((0, 0), (0, 0.1)), flow_direction=(1, 0), open_boundary_layers=4, particle_spacing=0.01,
                 density=1000, initial_condition=ic)
    assert cut.positions.shape == (40, 2)


@pytest.mark.parametrize("kwargs, word", [
    (dict(flow_direction=(1, 1)), "normal"),
    (dict(open_boundary_layers=0), "open_boundary_layers"),
    (dict(plane=((0, 0), (0, 0))), "distinct"),
    (dict(reference_velocity=(1, 2, 3)), "reference_velocity"),
    (dict(reference_pressure=np.zeros(7)), "reference_pressure"),
    (dict(particle_spacing=-1), "particle_spacing"),
])
def test_bad_zone_input_names_the_parameter(kwargs, word):
    base = dict(plane=((0, 0), (0, 0.1)), flow_direction=(1, 0), open_boundary_layers=4,
                particle_spacing=0.01, density=1000)
    base.update(kwargs)
    with pytest.raises(ParameterError, match=word):
        InFlow(**base)


def test_open_boundary_checks():
    fluid = sw.FluidSystem(shapes.rectangle((0, 0), (0.2, 0.1), 0.01), eos=sw.Tait(c0=10))
    zone = InFlow(plane=((0, 0), (0, 0.1)), flow_direction=(1, 0), open_boundary_layers=4,
                  particle_spacing=0.02, density=1000)
    with pytest.raises(ParameterError, match="particle_spacing"):
        OpenBoundary(zone, fluid_system=fluid, buffer_size=10)
    zone = InFlow(plane=((0.05, 0), (0.05, 0.1)), flow_direction=(1, 0), open_boundary_layers=4,
                  particle_spacing=0.01, density=1000)
    with pytest.raises(ParameterError, match="buffer_size"):
        OpenBoundary(zone, fluid_system=fluid, buffer_size=-1)
    ob = OpenBoundary(zone, fluid_system=fluid, buffer_size=10)
    with pytest.raises(ParameterError, match="inside inflow zone"):  # the fluid block overlaps the zone
        sw.Simulation([fluid, ob], h=0.013)


# ---------------------------------------------------------------- particle exchange at every face
def _channel():
    sim = build("channel", boundary="adami-noslip", dx=0.01)
    return sim, sim.open_boundary


def _index_of(fp, pid):
    return int(np.flatnonzero(fp["id"] == pid)[0])


def test_crossing_each_face_of_each_zone_2d():
    sim, ob = _channel()
    fp = sim.fluid.particles
    dx = 0.01
    depth = 4 * dx
    L, H = sim.reference["length"], sim.reference["height"]
    zone = fp["zone"]
    inflow_ids = fp["id"][zone == 0][:3]
    outflow_ids = fp["id"][zone == 1][:3]
    fluid_ids = fp["id"][zone == -1][:2]
    n0 = fp.n
    moves = {
        inflow_ids[0]: (0.2 * dx, 0.05),            # inflow -> across the plane into the fluid
        inflow_ids[1]: (-depth - 0.2 * dx, 0.05),   # inflow -> out of the upstream face
        inflow_ids[2]: (-0.02, H + 0.3 * dx),       # inflow -> out of a lateral face
        outflow_ids[0]: (L + depth + 0.2 * dx, 0.05),  # outflow -> out of the far face (normal exit)
        outflow_ids[1]: (L - 0.2 * dx, 0.05),       # outflow -> back upstream into the fluid
        outflow_ids[2]: (L + 0.02, -0.3 * dx),      # outflow -> out of a lateral face
        fluid_ids[0]: (L + 0.3 * dx, 0.05),         # fluid -> into the outflow
        fluid_ids[1]: (-0.3 * dx, 0.05),            # fluid -> back into the inflow
    }
    for pid, pos in moves.items():
        fp["x"][_index_of(fp, pid)] = pos
    ob.convert(sim)
    fp = sim.fluid.particles
    ids = set(fp["id"].tolist())
    zone_of = {pid: int(fp["zone"][_index_of(fp, pid)]) for pid in moves if pid in ids}
    assert zone_of[inflow_ids[0]] == -1
    assert zone_of[outflow_ids[1]] == -1
    assert zone_of[fluid_ids[0]] == 1
    assert zone_of[fluid_ids[1]] == 0
    for gone in (inflow_ids[1], inflow_ids[2], outflow_ids[0], outflow_ids[2]):
        assert gone not in ids
    # a new inflow particle one zone depth upstream of the one that entered the fluid
    new = fp["id"] >= ob.next_id - 1
    assert new.sum() == 1 and fp["zone"][new][0] == 0
    assert np.allclose(fp["x"][new][0], (0.2 * dx - depth, 0.05))
    c = ob.counts
    assert c["to_fluid"] == [1, 1] and c["from_fluid"] == [1, 1] and c["spawned"] == [1, 0]
    assert c["recycled_out"] == [0, 1] and c["lost_upstream"] == [1, 0] and c["lost_lateral"] == [1, 1]
    assert fp.n == n0 + 1 - 4
    assert ob.free == ob.buffer_size - 1 + 4
    assert len(ob.lost_records) == 3


def test_crossing_faces_3d_and_model_state_in_3d():
    dx = 0.01
    fluid = sw.FluidSystem(shapes.box((0, 0, 0), (0.08, 0.06, 0.1), dx), eos=sw.Tait(c0=10.0),
                           velocity=(0, 0, 0.3), pressure=np.full(480, 40.0))
    rho_f = fluid.particles["rho"][0]
    inflow = InFlow(plane=((0, 0, 0), (0.08, 0, 0), (0, 0.06, 0)), flow_direction=(0, 0, 1),
                    open_boundary_layers=3, particle_spacing=dx, density=1000,
                    reference_velocity=(0.0, 0.1, 0.5), reference_pressure=10.0)
    outflow = OutFlow(plane=((0, 0, 0.1), (0, 0.06, 0.1), (0.08, 0, 0.1)), flow_direction=(0, 0, 1),
                      open_boundary_layers=3, particle_spacing=dx, density=1000,
                      reference_velocity=lambda x, t: np.tile([0.0, 0.0, 0.2], (x.shape[0], 1)),
                      reference_pressure=lambda x, t: 0.0 * x[:, 2])
    ob = OpenBoundary([inflow, outflow], fluid_system=fluid, buffer_size=100)
    sim = sw.Simulation([fluid, ob], h=0.013, domain=((-0.05, -0.05, -0.1), (0.13, 0.11, 0.2)))
    fp = sim.fluid.particles
    c = 10.0
    # uniform fluid: every zone particle (with or without fluid neighbours) gets the inversion of
    # the fluid's characteristics, exactly
    rho_ref_in = sim.fluid.eos.density(np.array([10.0]), 1000.0)[0]
    J1, J2, J3 = characteristic_variables(rho_f, 0.3, 40.0, rho_ref_in, 0.5, 10.0, c)
    rho_in, v_in, _ = invert_characteristics(0.0, 0.0, J3, rho_ref_in, np.array([0.0, 0.1, 0.5]), 10.0, c,
                                             np.array([0, 0, 1.0]))
    zin = fp["zone"] == 0
    assert np.allclose(fp["rho"][zin], rho_in, rtol=1e-12)
    assert np.allclose(fp["v"][zin], v_in, atol=1e-12)
    J1, J2, J3 = characteristic_variables(rho_f, 0.3, 40.0, 1000.0, 0.2, 0.0, c)
    rho_out, v_out, _ = invert_characteristics(J1, J2, 0.0, 1000.0, np.array([0.0, 0.0, 0.2]), 0.0, c,
                                               np.array([0, 0, 1.0]))
    zout = fp["zone"] == 1
    assert np.allclose(fp["rho"][zout], rho_out, rtol=1e-12)
    assert np.allclose(fp["v"][zout], v_out, atol=1e-12)
    # faces in 3D: lateral along each spanning vector, downstream, upstream
    ids_in = fp["id"][zin][:3]
    ids_out = fp["id"][zout][:2]
    moves = {ids_in[0]: (0.085, 0.03, -0.015), ids_in[1]: (0.04, -0.002, -0.015),
             ids_in[2]: (0.04, 0.03, 0.001), ids_out[0]: (0.04, 0.03, 0.131), ids_out[1]: (0.04, 0.061, 0.115)}
    for pid, pos in moves.items():
        fp["x"][_index_of(fp, pid)] = pos
    ob.convert(sim)
    assert ob.counts["lost_lateral"] == [2, 1]
    assert ob.counts["to_fluid"] == [1, 0] and ob.counts["spawned"] == [1, 0]
    assert ob.counts["recycled_out"] == [0, 1]
    fp = sim.fluid.particles
    assert int(fp["zone"][_index_of(fp, ids_in[2])]) == -1


# ---------------------------------------------------------------- buffer accounting
def test_buffer_accounting_conserves_particles():
    sim, ob = _channel()
    fp = sim.fluid.particles
    n_start = fp.n
    n_zone0 = ob.zone_particles()
    n_fluid0 = int(np.count_nonzero(fp["zone"] < 0))
    sim.run(2.0, progress=False)
    fp = sim.fluid.particles
    c = ob.counts
    assert sum(c["to_fluid"]) > 50 and sum(c["recycled_out"]) > 50   # particles did flow through
    # every particle is in the fluid, in a zone, a spare, or escaped from the domain
    assert fp.n + ob.free + len(sim.escaped) == n_start + ob.buffer_size
    for k in range(2):
        expect = (n_zone0[k] + c["spawned"][k] + c["from_fluid"][k] - c["to_fluid"][k] - c["recycled_out"][k]
                  - c["lost_upstream"][k] - c["lost_lateral"][k])
        assert ob.zone_particles()[k] == expect
    n_fluid = int(np.count_nonzero(fp["zone"] < 0))
    assert n_fluid == n_fluid0 + sum(c["to_fluid"]) - sum(c["from_fluid"]) - len(sim.escaped)
    assert len(set(fp["id"].tolist())) == fp.n   # ids stay unique
    summary = sim.summary(wall_time=0, loop_time=1, particle_steps=0, steps=0, startup=0)
    assert abs(summary["mass_drift"]) < 1e-12


def test_full_buffer_is_a_clear_error():
    sim = build("channel", boundary="adami-noslip", dx=0.01, buffer_size=1)
    with pytest.raises(ParameterError, match="buffer_size"):
        sim.run(0.5, progress=False)


def test_channel_needs_noslip_walls():
    with pytest.raises(ParameterError, match="no-slip"):
        build("channel", boundary="adami", dx=0.01)


def test_restart_continues_bit_for_bit(tmp_path):
    sim, _ = _channel()
    sim.run(0.1, progress=False)
    path = str(tmp_path / "ob.h5")
    sim.save_checkpoint(path)
    sim.run(0.2, progress=False)
    again, ob2 = _channel()
    again.restart(path)
    again.run(0.2, progress=False)
    a, b = sim.fluid.particles, again.fluid.particles
    assert a.n == b.n
    for name in ("x", "v", "rho", "zone", "id"):
        assert np.array_equal(a[name], b[name]), name
    assert ob2.counts == sim.open_boundary.counts


# ---------------------------------------------------------------- the other cases run
def test_s_cavity_fills_through_the_gate():
    sim = build("s-cavity", dx=0.002)
    sim.add(every=5e-4)
    result = sim.run(0.003, progress=False)
    ref = sim.reference
    # the gate delivered ~v_in * width * rho0 * t of water, and the fill fraction counts it
    delivered = result["mass_in"][-1]
    nominal = ref["rho0"] * ref["v_in"] * ref["width"] * 0.003
    assert 0.8 * nominal < delivered < 1.05 * nominal
    assert result["fill"][-1] > 0.5 * delivered / ref["rho0"] / ref["cavity_area"]
    assert result["front"][-1] > 0.02   # the water has left the gate
    assert result.summary["escaped_particles"] == 0
    assert result.summary["couplings"]["open_boundary"]["particles_left_zone_wrongly"] == 0


def test_pipe_3d_runs_and_exchanges_particles():
    sim = build("pipe-3d", boundary="adami-noslip", dx=0.1 / 6)
    sim.add(every=0.05)
    result = sim.run(1.0, progress=False, max_steps=150)
    ob = result.summary["couplings"]["open_boundary"]
    assert ob["zones"]["inflow"]["to_fluid"] > 0 and ob["zones"]["outflow"]["recycled_out"] > 0
    assert ob["particles_left_zone_wrongly"] == 0 and result.summary["escaped_particles"] == 0
    assert abs(result.summary["mass_drift"]) < 1e-12
