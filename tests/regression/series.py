"""Stored short runs ("series") that pin seawall's results while its code is refactored.

Each series is a small case built through :func:`seawall.cases.build` with
*every* case parameter given explicitly (``test_every_case_parameter_is_pinned``
fails when a case gains a parameter that a series does not pin), run for a
few hundred steps. What is stored (``tests/regression/data/NAME.npz``):

* ``steps``, ``n_fluid``, ``n_wall``, ``wall_lo`` / ``wall_hi`` (the tank
  geometry, compared exactly: a changed case default shows up here first);
* ``t`` and ``probe:NAME`` for every probe of the case plus the wall force
  (``WallForce`` x and y on every wall), sampled at a pinned interval;
* the final fluid state of every other particle (ids 0, 2, 4, ...):
  ``x``, ``v``, ``rho`` ordered by particle id.

Comparison (:func:`deviations`): for each stored float array the largest
absolute difference divided by the largest magnitude of the stored array
(per column for x and v), so a quantity that passes through zero is not
blown up. Measured between a run with 1 thread and the stored data (2 threads):
0.0 for 41 of the 42 series, 6.1e-14 for ``cavity-liu2015`` (in ``v``; one loop
on the liu2015 fluid's path is not bitwise independent of the thread count); of the
two transport-velocity cavity series added later, ``cavity-tvf`` 0.0 and
``cavity-liu2015-tvf`` 2.7e-14 (1.1e-12 with the serial build the tests use).
The same code also moves by round-off with the state of Numba's compiled code:
cold compile against cached machine code, and one series run alone against the
same series after the others in one process (the dispatcher then reuses
specialisations compiled for other argument types), measured up to 2.4e-12
(``hydrostatic-mdbc-noslip``, probe P3; ``dam-break-ghost-mls2`` 1.6e-12 in the
full sequence, 0.0 alone). The test tolerance ``RTOL`` is 4x that spread: room
for it and for sums reordered by fastmath after a refactor; a changed formula
moves a series by orders of magnitude more.

Regenerating, after a deliberate change of the physics::

    python -m tests.regression.regenerate                # every series, reports the change of each
    python -m tests.regression.regenerate '*-idbc'       # fnmatch patterns; only these are rewritten
    python -m tests.regression.regenerate --check        # report only, write nothing

(see ``regenerate.py``).
"""

import fnmatch
import os
from dataclasses import dataclass, field

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")

#: test tolerance on the scaled deviation (module docstring); measured reproduction spread <= 2.4e-12
RTOL = 1e-11

#: keep every STRIDE-th particle (by id) of the final state
STRIDE = 2


@dataclass
class Series:
    """One stored run: case, wall model (+ its options), every case parameter, and the run length."""

    case: str
    boundary: str
    params: dict
    t_end: float
    probe_every: float
    boundary_options: dict = field(default_factory=dict)

    def build(self, threads=None):
        from seawall import probes
        from seawall.cases import build

        sim = build(self.case, boundary=self.boundary, threads=threads, **self.params, **self.boundary_options)
        for wall in sim.walls:
            for axis, label in enumerate("xy"):
                sim.add(probes.WallForce(f"force_{wall.name}_{label}", wall.name, axis=axis))
        sim.add(every=self.probe_every)
        return sim


# ---------------------------------------------------------------- the pinned cases
#: still water in a small tank, released from rest (p = 0): a pressure wave settles against every wall
HYDROSTATIC = dict(dx=0.0125, h_factor=1.3, c0=22.0, alpha=0.02, delta=0.1, cfl=0.2, rho0=1000.0,
                   lagged_gradient=True, scheme="standard", dt=0.0,
                   depth=0.25, length=0.5, height=0.3, initial="rest", riemann=False, riemann_eta=3.0)
HYDROSTATIC_T = 0.045        # ~300 steps with dt = 0.2 h / c0
#: a small dam break (column 0.1 x 0.05 m in a tank 5.366 H x 2 H): the column slumps along the floor
DAM_BREAK = dict(dx=0.0025, h_factor=1.3, c0=10.0, alpha=0.02, delta=0.1, cfl=0.2, rho0=1000.0,
                 lagged_gradient=True, scheme="standard", dt=0.0, H=0.05, initial="rest",
                 tank_height=2.0, lid=False, diffusion="renormalised", riemann=False, riemann_eta=3.0)
DAM_BREAK_T = 0.02           # ~300 steps
#: the lid-driven cavity at Re = 100, 25 x 25 particles
CAVITY = dict(dx=4e-5, side=1e-3, lid_speed=1e-3, reynolds=100.0, h_factor=1.2, rho0=1000.0, c0=0.01,
              fluid="standard", background=0.05, delta=0.1, alpha=0.02, cfl=0.2, dt=0.0, layers=3,
              density="continuity", kernel="cubic", transport_velocity=False)
#: the same cavity with the case's default scheme since issue 17, [Adami2013]'s: the transport velocity
#: (p_b = rho0 c0^2) and, for the standard fluid, the summed density without delta-SPH or EOS background
CAVITY_TVF = dict(CAVITY, transport_velocity=True, tvf_background=1.0)


def _registered():
    from seawall.boundary.registry import BOUNDARIES

    return list(BOUNDARIES)


def _all_series():
    out = {}
    for model in _registered():
        out[f"hydrostatic-{model}"] = Series("hydrostatic", model, HYDROSTATIC, HYDROSTATIC_T, HYDROSTATIC_T / 30)
        out[f"dam-break-{model}"] = Series("dam-break", model, DAM_BREAK, DAM_BREAK_T, DAM_BREAK_T / 30)
    # wall-model options with their own code path
    for case, params, t in (("hydrostatic", HYDROSTATIC, HYDROSTATIC_T), ("dam-break", DAM_BREAK, DAM_BREAK_T)):
        out[f"{case}-continuity-noslip"] = Series(case, "continuity", params, t, t / 30, {"slip": "noslip"})
        out[f"{case}-ghost-mls1-noslip"] = Series(case, "ghost-mls1", params, t, t / 30, {"slip": "noslip"})
        out[f"{case}-lust-noslip"] = Series(case, "lust", params, t, t / 30, {"slip": "noslip"})
        # the fluid scheme of [Huang2019] (linear EOS, Gaussian kernel, delta-SPH)
        out[f"{case}-marrone2011"] = Series(case, "adami", {**params, "scheme": "marrone2011"}, t, t / 30)
    # the two cavity fluids: laminar viscosity with a linear EOS, and the liu2015 preset ([Liu2015] sec. 2), each
    # without regularisation (the case's default until issue 17) and with the transport velocity (its default since)
    cavity_t = 0.3                # 30 % of a lid passage L / U; ~300 steps (dt = 0.2 h / c0)
    out["cavity-standard"] = Series("cavity", "adami-noslip", CAVITY, cavity_t, cavity_t / 30)
    out["cavity-liu2015"] = Series("cavity", "liu2015-noslip", {**CAVITY, "fluid": "liu2015", "background": 0.0}, cavity_t,
                                   cavity_t / 30)
    out["cavity-tvf"] = Series("cavity", "adami-noslip", {**CAVITY_TVF, "density": "summation", "background": 0.0,
                                                          "delta": 0.0}, cavity_t, cavity_t / 30)
    out["cavity-liu2015-tvf"] = Series("cavity", "liu2015-noslip", {**CAVITY_TVF, "fluid": "liu2015", "background": 0.0},
                                       cavity_t, cavity_t / 30)
    return out


SERIES = _all_series()


def select(patterns):
    """Names of the series matching any fnmatch pattern (all of them for no pattern)."""
    if not patterns:
        return list(SERIES)
    names = [n for n in SERIES if any(fnmatch.fnmatchcase(n, p) for p in patterns)]
    return names


def path(name):
    return os.path.join(DATA, f"{name}.npz")


def run(name, threads=None):
    """Run series ``name``; return the dict of arrays that is stored."""
    spec = SERIES[name]
    sim = spec.build(threads=threads)
    result = sim.run(spec.t_end, progress=False)
    fp = sim.fluid.particles
    by_id = np.argsort(fp["id"], kind="stable")
    keep = by_id[fp["id"][by_id] % STRIDE == 0]
    wall_x = np.concatenate([w.x for w in sim.walls])
    out = {
        "steps": np.int64(sim.step),
        "n_fluid": np.int64(fp.n),
        "n_wall": np.int64(wall_x.shape[0]),
        "wall_lo": wall_x.min(axis=0),
        "wall_hi": wall_x.max(axis=0),
        "t": result.times,
        "id": fp["id"][keep].astype(np.int64),
        "x": fp["x"][keep],
        "v": fp["v"][keep],
        "rho": fp["rho"][keep],
    }
    for probe, values in result.probes.items():
        out[f"probe:{probe}"] = values
    return out


def load(name):
    with np.load(path(name)) as f:
        return {k: f[k] for k in f.files}


def save(name, arrays):
    os.makedirs(DATA, exist_ok=True)
    np.savez_compressed(path(name), **arrays)


#: compared exactly: counts, geometry and particle ids
EXACT = ("steps", "n_fluid", "n_wall", "wall_lo", "wall_hi", "id")


def deviations(stored, new):
    """{key: scaled deviation} of ``new`` against ``stored``; inf for a key missing, added or of another shape.

    Float arrays: max |new - stored| / max |stored| (per column for 2-D arrays; a zero
    array is scaled by 1). The components of a wall force (``probe:force_<wall>_x`` ...) are
    scaled together by the force's largest component: in a symmetric tank the sideways force
    is round-off about zero, and scaled by itself any reordering of a sum would look like an
    O(1) change. Exact keys (counts, geometry, ids): 0 when equal, inf otherwise.
    """
    out = {}
    force_scale = {}
    for key in stored:
        if key.startswith("probe:force_") and key[-2:] in ("_x", "_y", "_z"):
            group = key[:-2]
            force_scale[group] = max(force_scale.get(group, 0.0), float(np.nanmax(np.abs(stored[key]), initial=0.0)))
    for key in sorted(set(stored) | set(new)):
        if key not in stored or key not in new:
            out[key] = np.inf
            continue
        a = np.asarray(stored[key])
        b = np.asarray(new[key])
        if a.shape != b.shape:
            out[key] = np.inf
        elif key in EXACT:
            out[key] = 0.0 if np.array_equal(a, b) else np.inf
        elif a.size == 0:
            out[key] = 0.0
        else:
            nan_a, nan_b = np.isnan(a), np.isnan(b)
            if not np.array_equal(nan_a, nan_b):
                out[key] = np.inf
                continue
            a = np.where(nan_a, 0.0, a)
            b = np.where(nan_b, 0.0, b)
            scale = np.max(np.abs(a), axis=0)
            if key[:-2] in force_scale:
                scale = force_scale[key[:-2]]
            scale = np.where(scale > 0.0, scale, 1.0)
            out[key] = float(np.max(np.abs(b - a) / scale))
    return out


def worst(devs):
    """(key, deviation) of the largest deviation."""
    key = max(devs, key=lambda k: devs[k])
    return key, devs[key]
