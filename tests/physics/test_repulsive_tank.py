"""Monaghan-Kajtar walls hold still water (dx = 0.02 m, hydrostatic start, 1.5 s).

Measured over 1.0-1.5 s (K = g D, beta = 3): no particle left or sank below the
wall row (lowest particle 0.012 m above it); the extrapolated wall pressure is
biased because the fluid stands off a repulsive wall: P0 +12.6 %, P1 -13.6 %,
P2 +3.8 % (means), deviations up to 31 %. Recorded in docs/boundaries.md.
"""


from seawall.cases import build


def test_monaghan_kajtar_holds_still_water():
    sim = build("hydrostatic", dx=0.02, boundary="monaghan-kajtar")
    sim.add(every=0.01)
    result = sim.run(1.5, progress=False)
    x = sim.fluid.particles["x"]
    assert result.summary["escaped_particles"] == 0
    assert x[:, 1].min() > 0.0 and x[:, 0].min() > 0.0 and x[:, 0].max() < 1.0
    late = result.times >= 1.0
    # the bottom pressure carries the weight of the column: its mean is within 20 % (measured 12.6 %)
    exact = 1000 * 9.81 * 0.3
    assert abs(result["P0"][late].mean() - exact) < 0.2 * exact


def test_monaghan_kajtar_runs_the_collapse():
    sim = build("collapse", dx=0.146 / 20, boundary="monaghan-kajtar")
    result = sim.run(0.15, progress=False)
    assert result.summary["escaped_particles"] == 0
    assert sim.fluid.particles["x"][:, 1].min() > 0.0
    assert result["front"][-1] > 1.5 * 0.146
