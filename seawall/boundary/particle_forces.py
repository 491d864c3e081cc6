"""The fluid's force on each wall particle, for wall models that push by one pair force per wall particle.

A model that declares ``pairwise_momentum = True`` (:class:`~seawall.boundary.base.WallModel`) adds
to fluid particle i's acceleration a sum over wall particles b of terms f_ib / m_i, each depending
only on the states of i and b, nonzero only within the kernel support. Then the force of the fluid
on wall particle b is F_b = -sum_i f_ib (Newton's third law; [Huang2019] eq. 29 sums the same
reactions over the whole wall), and sum_b F_b is the wall's total force, which the ``WallForce``
probe reports.

The compiled loops gather per fluid particle and never see f_ib alone, so F_b is recovered from the
model's own ``interact`` without touching it: the wall particles are split into colour classes in
which no two particles are closer than two kernel supports. A fluid particle then lies within the
support of at most one particle of a class, so its acceleration change from ``interact`` on that
class alone is exactly f_ib / m_i of that one b. Summing -m_i dv_i over the fluid particles near b
gives F_b. The split is the property ``tests/contract`` checks for every pairwise model (the push
is additive over any split of the wall particles). The colouring is greedy, so a 2D wall of three
layers needs about 30 classes and a 3D one a few hundred: each is one ``interact`` over a part of
the wall, so this runs only at output times (``Simulation.evaluate`` with the runner's request).

Models whose push is not such a sum (of the registered ones, ``lust``: its nodes carry the fluid particle's own state)
get no per-particle force: :func:`defines_particle_forces` is False, and the VTU files carry only
the wall's total (``wall_force``). Adhesion (``WallSystem(adhesion_coefficient=...)``) is a force
of its own on top of the model's; a wall with adhesion gets no per-particle force either, so that
the field always sums to ``wall_force``.
"""

import copy
import dataclasses

import numpy as np
from numba import njit

from ..neighbors import CellGrid, neighbour_pairs
from ..particles import ParticleArrays


def defines_particle_forces(wall):
    """Whether the force on each of ``wall``'s particles is defined (see the module docstring)."""
    model = getattr(wall, "model", None)
    return (bool(getattr(type(model), "pairwise_momentum", False)) and wall.n > 0
            and getattr(wall, "adhesion_coefficient", 0.0) == 0.0)


@njit(cache=True)
def greedy_colours(n, pairs_i, pairs_j):
    """Colour n nodes so that no pair (pairs_i[k], pairs_j[k]) shares a colour (pairs sorted by i)."""
    colour = np.full(n, -1, dtype=np.int64)
    offsets = np.zeros(n + 1, dtype=np.int64)
    for k in range(pairs_i.shape[0]):
        offsets[pairs_i[k] + 1] += 1
    for a in range(n):
        offsets[a + 1] += offsets[a]
    taken = np.full(n + 1, -1, dtype=np.int64)   # taken[c] == a: colour c is used by a neighbour of a
    for a in range(n):
        for k in range(offsets[a], offsets[a + 1]):
            c = colour[pairs_j[k]]
            if c >= 0:
                taken[c] = a
        c = 0
        while taken[c] == a:
            c += 1
        colour[a] = c
    return colour


def wall_colours(wall, grid):
    """Colour classes of ``wall``'s particles, no two in a class closer than two kernel supports;
    None where a periodic axis is too short for a search grid of that radius."""
    from ..errors import ParameterError

    x = wall.particles["x"]
    dim = x.shape[1]
    reach = 2.0 * grid.radius
    try:
        wide = CellGrid(grid.lo[:dim], grid.hi[:dim], reach, grid.periodic if grid.periodic_any else None)
    except ParameterError:
        return None
    i, j = neighbour_pairs(wide, x, radius=reach)
    return greedy_colours(x.shape[0], i, j)


def _wall_part(wall, keep, grid):
    """A copy of ``wall`` holding only the particles ``keep`` (their state as after the last update)."""
    part = copy.copy(wall)
    part.particles = ParticleArrays(wall.dim)
    for name, a in wall.particles.items():
        part.particles.add(name, a[keep])
    part.cells = grid.build(part.particles["x"])
    return part


def particle_forces(sim, wall, ctx):
    """(n_wall, dim) force of the fluid on each particle of ``wall`` [N, per metre of depth in 2D];
    None if the wall cannot be coloured (a periodic axis shorter than about five kernel supports).

    Called by ``Simulation.evaluate`` after the wall's ``update`` and ``interact`` of this
    evaluation (the wall's state is then the one the fluid felt). The fluid's rates are not
    touched: each colour class is pushed into scratch arrays.
    """
    from ..views import Rates

    fp = sim.fluid.particles
    grid = sim.grid
    colours = getattr(wall, "_force_colours", None)
    if colours is None or colours.shape[0] != wall.n or wall.movement is not None:
        colours = wall_colours(wall, grid)
        if colours is None:
            return None
        wall._force_colours = colours
    n_fluid, dim = fp["dv"].shape
    dv = np.zeros((n_fluid, dim))
    drho = np.zeros(n_fluid)
    scratch = dataclasses.replace(ctx, rates=Rates(dv, drho, np.zeros_like(fp["xsph"]), np.zeros_like(fp["mu_max"])))
    force = np.zeros((wall.n, dim))
    xf = fp["x"]
    for c in range(int(colours.max()) + 1):
        members = np.flatnonzero(colours == c)
        part = _wall_part(wall, colours == c, grid)
        dv[:] = 0.0
        wall.model.interact(sim.fluid, part, scratch, dv, drho)
        pushed = np.flatnonzero(np.any(dv != 0.0, axis=1))
        if pushed.size == 0:
            continue
        # each pushed fluid particle has exactly one member of this class within the support
        fi, bk = neighbour_pairs(grid, xf[pushed], part.particles["x"])
        owner = np.full(pushed.size, -1, dtype=np.int64)
        owner[fi] = bk
        if np.any(np.bincount(fi, minlength=pushed.size) > 1):   # the colouring guarantees one at most
            raise RuntimeError(f"wall {wall.name!r}: two wall particles of one colour class share a fluid neighbour")
        if np.any(owner < 0):
            k = pushed[int(np.argmax(owner < 0))]
            raise RuntimeError(f"wall {wall.name!r}: model {type(wall.model).__name__} pushes fluid particle {k} "
                               "from beyond the kernel support; it cannot declare pairwise_momentum")
        reaction = -fp["m"][pushed, None] * dv[pushed]
        for axis in range(dim):
            force[:, axis] += np.bincount(members[owner], weights=reaction[:, axis], minlength=wall.n)
    return force


def part_force(sim, wall, ctx, box):
    """The fluid's force on the particles of ``wall`` inside ``box`` = (lo, hi) [N, per metre in 2D]:
    minus what the model (and the wall's adhesion) adds to m_i dv_i acting through those particles
    alone, over the fluid rows this process owns. Exact for a ``pairwise_momentum`` model, whose
    push is additive over any split of the wall; called by ``Simulation.evaluate`` where the
    wall's total is taken, into scratch arrays."""
    from ..views import Rates
    from .adhesion import add_adhesion

    fp = sim.fluid.particles
    lo, hi = (np.asarray(c) for c in box)
    keep = np.all((wall.particles["x"] >= lo) & (wall.particles["x"] <= hi), axis=1)
    if not keep.any():          # a moving wall may leave the box
        return np.zeros(wall.dim)
    part = _wall_part(wall, keep, sim.grid)
    dv = np.zeros_like(fp["dv"])
    drho = np.zeros_like(fp["drho"])
    scratch = dataclasses.replace(ctx, rates=Rates(dv, drho, np.zeros_like(fp["xsph"]), np.zeros_like(fp["mu_max"])))
    wall.model.interact(sim.fluid, part, scratch, dv, drho)
    if wall.adhesion_coefficient > 0.0:
        add_adhesion(part, sim.fluid, scratch, sim.kernel.support(sim.h), dv)
    n = sim._owned_rows()
    return -np.sum(fp["m"][:n, None] * dv[:n], axis=0)
