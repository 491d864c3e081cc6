"""The block loops of seawall.blocks: blocks cover every particle once, and a loop split into
blocks gives every particle -- in full blocks and in the last, partial one -- its own sum.

The continuity rate of a box at uniform density with random velocities is compared with the
sum over every pair written out here, drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij ([Li2022]
eq. 8); at uniform density the density diffusion adds nothing.
"""

import numpy as np
import pytest

from seawall import shapes
from seawall.blocks import BLOCK, block_bounds, block_count
from seawall.eos import Linear
from seawall.fluid import FluidSystem
from seawall.kernels import kernel_gradient_factor
from seawall.simulation import Simulation


@pytest.mark.parametrize("n", [0, 1, BLOCK - 1, BLOCK, BLOCK + 1, 5 * BLOCK + 17])
def test_blocks_cover_every_particle_once(n):
    seen = np.zeros(n, dtype=np.int64)
    for b in range(block_count(n)):
        first, last = block_bounds(b, n)
        assert 0 < last - first <= BLOCK
        seen[first:last] += 1
    assert np.all(seen == 1)


def test_continuity_rate_of_every_block_matches_the_pair_sum():
    side = 19                                   # 361 particles: two full blocks and a partial one
    assert (side * side) % BLOCK != 0 and side * side > 2 * BLOCK
    block = shapes.rectangle((0.0, 0.0), (1.0, 1.0), 1.0 / side)
    rng = np.random.default_rng(19)
    velocity = rng.uniform(-1.0, 1.0, size=block.positions.shape)
    fluid = FluidSystem(block, rho0=1.0, eos=Linear(c0=10.0), viscosity=None, velocity=velocity)
    h = 1.3 / side
    sim = Simulation([fluid], h=h, gravity=(0.0, 0.0), domain=((0.0, 0.0), (1.0, 1.0)), threads=1)
    fp = fluid.particles
    fp["drho"][:] = np.nan
    sim.evaluate(0.0)
    prm = sim.physics
    x, v, m = fp["x"], fp["v"], fp["m"]
    d = x[:, None, :] - x[None, :, :]
    r = np.sqrt(np.sum(d * d, axis=-1))
    near = (r < np.sqrt(prm.support2)) & (r > 0.0)
    f = np.zeros_like(r)
    f[near] = [prm.sigma / h ** 2 * kernel_gradient_factor(prm.kernel, q) for q in r[near] / h]
    u = v[:, None, :] - v[None, :, :]
    expected = np.sum(m[None, :] * f * np.sum(u * d, axis=-1), axis=1)
    assert x.shape[0] == side * side
    np.testing.assert_allclose(fp["drho"], expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
