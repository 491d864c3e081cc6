"""Open boundaries: inflow and outflow zones with the method of characteristics.

The user-facing design follows [TrixiBoundary] ("OpenBoundarySPHSystem", "InFlow",
"OutFlow", "BoundaryModelLastiwka"):

* a zone is a plane (a segment in 2D given by two points A, B; a rectangle in
  3D given by A, B, C with AB orthogonal to AC) extruded by
  ``open_boundary_layers`` particle layers upstream (:class:`InFlow`, against
  ``flow_direction``) or downstream (:class:`OutFlow`, along it); the zone is
  filled with particles on the dx lattice of the plane, or with an extruded
  shape lying on the plane, or with a given initial condition cut to the box;
* :class:`OpenBoundary` holds one or more zones and a fixed number of spare
  particles (``buffer_size``). Zone ("buffer") particles live in the fluid's
  arrays, flagged by the per-particle integer ``zone`` (-1 for fluid, k for
  zone k), so the fluid sees them as ordinary neighbours; the fluid loops
  are unchanged. They move with their own velocity; their density and
  velocity are set after every step by the boundary model, never by the
  fluid's forces;
* after every step: an inflow particle that crossed the plane into the fluid
  becomes fluid and a spare particle is placed one zone depth upstream of it;
  fluid that crossed into an outflow zone becomes a zone particle, and an
  outflow particle that left through the far face returns to the spares. A
  zone particle leaving its zone any other way (upstream out of an inflow,
  sideways out of any zone) returns to the spares and is counted in the
  summary; an outflow particle moving back upstream becomes fluid again.
  When a particle is needed and no spare is left, the run stops with a
  :class:`~seawall.errors.ParameterError` naming ``buffer_size``.

:class:`Lastiwka` -- the method of characteristics (Lastiwka et al. 2009,
[TrixiBoundary]), with the characteristic variables of Giles (1990):

    J1 = -c_s^2 (rho - rho_ref) + (p - p_ref)
    J2 =  rho c_s (v - v_ref) . n + (p - p_ref)
    J3 = -rho c_s (v - v_ref) . n + (p - p_ref)

n the unit flow direction. Inflow: J1 = J2 = 0 prescribed, J3 transmitted;
outflow: J3 = 0 prescribed, J1 and J2 transmitted. A transmitted value at a
zone particle i is the Shepard interpolation of the fluid's values (Negi et
al. 2020, [TrixiBoundary])

    J_i = sum_j J_j W_ij / sum_j W_ij      (j: fluid particles only),

with the reference values of particle i in every J_j (so that array
references, given per zone particle, can be used; [TrixiBoundary] evaluates
function references at the fluid particle instead -- the two differ by
O(h grad ref)). Zone particles with no fluid particle in their support take
the Shepard average over their zone neighbours that have one (repeated
layer by layer), else keep their previous values. The state then follows
from the seed's inversion

    rho = rho_ref + (-J1 + (J2 + J3) / 2) / c_s^2
    v   = v_ref + (J2 - J3) / (2 rho c_s) n
    p   = p_ref + (J2 + J3) / 2

with c_s the fluid's reference sound speed c0 and pressures gauge (the EOS
background pressure removed). The model's density is stored; the fluid's
equation of state turns it into the pressure the neighbours see, which is
the model's p to first order (exactly for J1 = 0 and the linear EOS).
Choices where the seed is silent are listed in docs/open-boundaries.md.
"""

import math

import numpy as np
from numba import njit, prange

from .coupling import Coupling
from .eos import eos_density, eos_pressure
from .errors import ParameterError, require_positive
from .jit import particle_loop
from .kernels import kernel_shape
from .neighbors import cell_index, neighbour_range, point_of, separation, tag_dim, tag_periodic
from .probes import Probe

INFLOW = 0
OUTFLOW = 1


# ---------------------------------------------------------------- compiled loops
@particle_loop()
def characteristic_sums(layout, idx, x, v, rho, zone, normals, start, order, lo, inv_cell, ncell, period, prm, out):
    """Shepard sums over the fluid neighbours j (zone[j] < 0) of each zone particle i = idx[k].

    out[k] = (sum W, sum W rho_j, sum W p_j, sum W rho_j v_j . n_i), p_j the
    gauge pressure EOS(rho_j) - p_background and n_i the flow direction of
    the particle's zone. The characteristic variables follow linearly
    (Negi et al. 2020 Shepard interpolation, [TrixiBoundary]).
    """
    inv_h = 1.0 / prm.h
    for k in prange(idx.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        i = idx[k]
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        z = zone[i]
        n0 = normals[z, 0]
        n1 = normals[z, 1]
        n2 = normals[z, 2]
        sw = 0.0
        sr = 0.0
        sp = 0.0
        sq = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for kk in range(ka, kb):
                    j = order[kk]
                    if zone[j] >= 0:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, x, j, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    rj = rho[j]
                    u0, u1, u2 = point_of(v, j, dim)
                    sw += w
                    sr += w * rj
                    sp += w * (eos_pressure(prm.eos, rj, prm.rho0, prm.c0, prm.gamma, prm.p_background)
                               - prm.p_background)
                    sq += w * rj * (u0 * n0 + u1 * n1 + u2 * n2)
        out[k, 0] = sw
        out[k, 1] = sr
        out[k, 2] = sp
        out[k, 3] = sq


@particle_loop()
def zone_neighbour_average(layout, idx, x, zone, supported, J, start, order, lo, inv_cell, ncell, period, prm,
                           out, found):
    """Shepard average of J over the same-zone neighbours with ``supported`` set, for unsupported idx[k]."""
    inv_h = 1.0 / prm.h
    for k in prange(idx.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        periodic = tag_periodic(layout)
        nrows = 25 if dim == 3 else 5
        i = idx[k]
        found[k] = 0
        if supported[i]:
            continue
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        z = zone[i]
        sw = 0.0
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for kk in range(ka, kb):
                    j = order[kk]
                    if zone[j] != z or supported[j] == 0:
                        continue
                    d0, d1, d2, r2 = separation(p0, p1, p2, x, j, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    sw += w
                    s0 += w * J[j, 0]
                    s1 += w * J[j, 1]
                    s2 += w * J[j, 2]
        if sw > 0.0:
            out[k, 0] = s0 / sw
            out[k, 1] = s1 / sw
            out[k, 2] = s2 / sw
            found[k] = 1


@njit(cache=True)
def _eos_density_array(p_gauge, prm, out):
    for i in range(p_gauge.shape[0]):
        out[i] = eos_density(prm.eos, p_gauge[i] + prm.p_background, prm.rho0, prm.c0, prm.gamma,
                             prm.p_background)


# ---------------------------------------------------------------- the characteristic relations
def characteristic_variables(rho, v_n, p, rho_ref, v_ref_n, p_ref, c):
    """(J1, J2, J3) of Giles (1990) as given in [TrixiBoundary] (BoundaryModelLastiwka).

    ``v_n``, ``v_ref_n``: velocity components along the flow direction;
    pressures gauge. Works on scalars or numpy arrays.
    """
    rho = np.asarray(rho, dtype=np.float64)
    dp = np.asarray(p, dtype=np.float64) - p_ref
    dv = rho * c * (np.asarray(v_n, dtype=np.float64) - v_ref_n)
    return -c * c * (rho - rho_ref) + dp, dv + dp, -dv + dp


def invert_characteristics(J1, J2, J3, rho_ref, v_ref, p_ref, c, normal):
    """rho, v, p from (J1, J2, J3): the inversion of [TrixiBoundary] (BoundaryModelLastiwka).

        rho = rho_ref + (-J1 + (J2 + J3)/2) / c^2,   v = v_ref + (J2 - J3)/(2 rho c) n,
        p = p_ref + (J2 + J3)/2

    ``v_ref`` is an (m, d) array (or a d-vector), ``normal`` the unit flow direction.
    """
    J1 = np.asarray(J1, dtype=np.float64)
    J2 = np.asarray(J2, dtype=np.float64)
    J3 = np.asarray(J3, dtype=np.float64)
    rho = rho_ref + (-J1 + 0.5 * (J2 + J3)) / (c * c)
    p = p_ref + 0.5 * (J2 + J3)
    dv = (J2 - J3) / (2.0 * rho * c)
    v = np.asarray(v_ref, dtype=np.float64) + np.multiply.outer(dv, np.asarray(normal, dtype=np.float64))
    return rho, v, p


# ---------------------------------------------------------------- reference values
class Reference:
    """A reference value of a zone: constant, one value per zone particle, or a function f(x, t).

    A function receives the (m, d) positions and the time and returns m values
    (an (m,) array for scalars, an (m, d) array for the velocity) or one value
    for all. An array holds one value per initial zone particle; particles
    that enter the zone later take the value of the initial particle whose
    position is closest to theirs when they enter (an inflow particle placed
    upstream of one that left inherits its value).
    """

    def __init__(self, name, value, dim, vector, n_initial):
        self.name = name
        self.dim = dim
        self.vector = vector
        self.function = None
        self.values = None
        self.constant = None
        if callable(value):
            self.function = value
            return
        try:
            a = np.array(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} must be a number, an array or a function of (x, t); got {value!r}") from None
        if not np.all(np.isfinite(a)):
            raise ParameterError(f"{name} must be finite")
        if vector:
            if a.shape == (dim,):
                self.constant = a
            elif a.shape == (n_initial, dim):
                self.values = a
            else:
                raise ParameterError(f"{name} must be a {dim}-vector, an ({n_initial}, {dim}) array (one row per "
                                     f"zone particle) or a function of (x, t); got shape {a.shape}")
        else:
            if a.ndim == 0:
                self.constant = a
            elif a.shape == (n_initial,):
                self.values = a
            else:
                raise ParameterError(f"{name} must be a number, an array of {n_initial} values (one per zone "
                                     f"particle) or a function of (x, t); got shape {a.shape}")

    @property
    def per_particle(self):
        return self.values is not None

    def at(self, x, slots, t):
        m = x.shape[0]
        shape = (m, self.dim) if self.vector else (m,)
        if self.constant is not None:
            return np.broadcast_to(self.constant, shape).copy()
        if self.values is not None:
            return self.values[slots].copy()
        try:
            out = np.asarray(self.function(x.copy(), float(t)), dtype=np.float64)
            out = np.broadcast_to(out, shape).copy()
        except ValueError:
            raise ParameterError(f"{self.name}: the function must return {shape} values for {m} positions") from None
        if not np.all(np.isfinite(out)):
            raise ParameterError(f"{self.name}: the function returned a non-finite value at t = {t:g}")
        return out


# ---------------------------------------------------------------- zones
def _points(name, value, dim=None):
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an array of coordinates, got {value!r}") from None
    if not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must contain finite numbers only")
    return a


class _Zone:
    """Common part of :class:`InFlow` and :class:`OutFlow`."""

    kind = -1
    label = "zone"

    def __init__(self, *, plane, flow_direction, open_boundary_layers, particle_spacing, density,
                 initial_condition=None, extrude_geometry=None, reference_velocity=None,
                 reference_pressure=None, reference_density=None, name=None):
        pts = _points("plane", plane)
        if pts.ndim != 2 or pts.shape not in ((2, 2), (3, 3)):
            raise ParameterError("plane must be two points (A, B) in 2D or three points (A, B, C) in 3D, "
                                 f"got shape {pts.shape}")
        dim = pts.shape[1]
        self.dim = dim
        self.origin = pts[0].copy()
        spans = pts[1:] - pts[0]
        lengths = np.linalg.norm(spans, axis=1)
        if np.any(lengths <= 0.0):
            raise ParameterError("plane points must be distinct")
        self.axes = spans / lengths[:, None]
        self.extent = lengths
        if dim == 3 and abs(float(self.axes[0] @ self.axes[1])) > 1e-6:
            raise ParameterError("plane: the vectors AB and AC must be orthogonal")
        n = _points("flow_direction", flow_direction)
        if n.shape != (dim,) or not np.linalg.norm(n) > 0.0:
            raise ParameterError(f"flow_direction must be a non-zero {dim}-vector, got {flow_direction!r}")
        n = n / np.linalg.norm(n)
        if np.any(np.abs(self.axes @ n) > 1e-6):
            raise ParameterError("flow_direction must be normal to the plane")
        self.normal = n
        if isinstance(open_boundary_layers, bool) or int(open_boundary_layers) != open_boundary_layers \
                or open_boundary_layers < 1:
            raise ParameterError(f"open_boundary_layers must be a positive integer, got {open_boundary_layers!r}")
        self.layers = int(open_boundary_layers)
        self.spacing = require_positive("particle_spacing", particle_spacing)
        self.density = require_positive("density", density)
        self.depth = self.layers * self.spacing
        self.side = -1.0 if self.kind == INFLOW else 1.0
        self.name = str(name) if name is not None else self.label
        if initial_condition is not None and extrude_geometry is not None:
            raise ParameterError("give initial_condition or extrude_geometry, not both")
        dx = self.spacing
        if initial_condition is not None:
            x = _points("initial_condition", getattr(initial_condition, "positions", initial_condition))
            if x.ndim != 2 or x.shape[1] != dim:
                raise ParameterError(f"initial_condition must be {dim}D positions, got shape {x.shape}")
            x = x[self.inside(x)]
        elif extrude_geometry is not None:
            g = _points("extrude_geometry", getattr(extrude_geometry, "positions", extrude_geometry))
            if g.ndim == 2 and g.shape[1] == dim - 1:
                g = np.concatenate([g, np.zeros((g.shape[0], 1))], axis=1)
            if g.ndim != 2 or g.shape[1] != dim:
                raise ParameterError(f"extrude_geometry must be {dim}D (or {dim - 1}D) points, got shape {g.shape}")
            s, lateral = self.coordinates(g)
            if np.any(np.abs(s) > 1e-6 * max(1.0, float(self.extent.max()))) or not np.all(lateral):
                raise ParameterError("extrude_geometry must lie on the plane, inside it")
            off = self.side * (np.arange(self.layers) + 0.5) * dx
            x = (g[None, :, :] + off[:, None, None] * n[None, None, :]).reshape(-1, dim)
        else:
            counts = [int(math.floor(length / dx + 1e-9)) for length in self.extent]
            if min(counts) < 1:
                raise ParameterError(f"the plane must be at least particle_spacing = {dx:g} wide")
            grids = np.meshgrid(*[(np.arange(c) + 0.5) * dx for c in counts],
                                (np.arange(self.layers) + 0.5) * dx * self.side, indexing="ij")
            coords = [g.ravel() for g in grids]
            x = np.repeat(self.origin[None, :], coords[0].size, axis=0)
            for k in range(dim - 1):
                x += coords[k][:, None] * self.axes[k][None, :]
            x += coords[-1][:, None] * n[None, :]
        if x.shape[0] == 0:
            raise ParameterError(f"{self.label} zone {self.name!r} holds no particle")
        self.positions = np.ascontiguousarray(x)
        n0 = x.shape[0]
        self.reference_velocity = Reference("reference_velocity",
                                            np.zeros(dim) if reference_velocity is None else reference_velocity,
                                            dim, True, n0)
        self.reference_pressure = Reference("reference_pressure",
                                            0.0 if reference_pressure is None else reference_pressure, dim, False, n0)
        self.reference_density = None if reference_density is None else \
            Reference("reference_density", reference_density, dim, False, n0)

    # geometry
    def coordinates(self, x):
        """Signed distance s = (x - A) . n from the plane and whether x lies within the plane's extent."""
        r = x - self.origin
        s = r @ self.normal
        lateral = np.ones(x.shape[0], dtype=bool)
        for k in range(self.dim - 1):
            t = r @ self.axes[k]
            lateral &= (t >= 0.0) & (t <= self.extent[k])
        return s, lateral

    def inside_normal(self, s):
        if self.kind == INFLOW:
            return (s >= -self.depth) & (s < 0.0)
        return (s >= 0.0) & (s < self.depth)

    def inside(self, x):
        s, lateral = self.coordinates(x)
        return lateral & self.inside_normal(s)

    def nearest_slot(self, x):
        """Index of the closest initial zone particle to each position."""
        out = np.empty(x.shape[0], dtype=np.int64)
        for k in range(x.shape[0]):
            out[k] = int(np.argmin(np.sum((self.positions - x[k]) ** 2, axis=1)))
        return out

    @property
    def per_particle_references(self):
        refs = [self.reference_velocity, self.reference_pressure, self.reference_density]
        return any(r is not None and r.per_particle for r in refs)

    def __repr__(self):
        return f"{type(self).__name__}({self.name!r}, {self.positions.shape[0]} particles, depth {self.depth:g} m)"


class InFlow(_Zone):
    """Inflow zone ([TrixiBoundary], InFlow): the plane extruded upstream by ``open_boundary_layers`` layers.

    Parameters
    ----------
    plane : points
        (A, B) in 2D: the inflow surface is the segment [A, B]; (A, B, C) in
        3D: the rectangle spanned by AB and AC (orthogonal).
    flow_direction : vector
        Direction of the flow (normal to the plane, into the fluid).
    open_boundary_layers : int
        Number of particle layers upstream.
    particle_spacing : float
        Spacing [m] (must equal the fluid's).
    density : float
        Density [kg/m^3] of the zone particles (their mass is density dx^d).
    initial_condition : Shape or (N, d) array, optional
        Particles to use instead of the full box (those outside the box are dropped).
    extrude_geometry : Shape or (N, d) / (N, d-1) array, optional
        Points on the plane extruded upstream instead of the full plane.
    reference_velocity, reference_pressure, reference_density : optional
        The reference flow: a constant (vector), an array with one value per
        zone particle, or a function f(x, t) of the (m, d) positions and the
        time. Defaults: zero velocity, zero gauge pressure, density from the
        fluid's EOS at the reference pressure.
    name : str, optional
    """

    kind = INFLOW
    label = "inflow"


class OutFlow(_Zone):
    """Outflow zone ([TrixiBoundary], OutFlow): the plane extruded downstream; parameters as :class:`InFlow`.

    Give the expected outflow velocity as ``reference_velocity``: with
    J3 = 0 the outflow state lies on p - p_ref = rho c (v - v_ref) . n, so a
    reference far from the actual velocity builds a back pressure of
    rho c |v - v_ref|.
    """

    kind = OUTFLOW
    label = "outflow"


# ---------------------------------------------------------------- model
class Lastiwka:
    """Method of characteristics (Lastiwka et al. 2009; [TrixiBoundary], BoundaryModelLastiwka).

    Inflow: J1 = J2 = 0 prescribed, J3 transmitted; outflow: J3 = 0
    prescribed, J1, J2 transmitted (Shepard interpolation from the fluid,
    Negi et al. 2020). See the module docstring for the formulas.
    """

    name = "lastiwka"
    #: per zone kind, which of J1, J2, J3 are transmitted from the fluid (the others are zero)
    TRANSMITTED = {INFLOW: (False, False, True), OUTFLOW: (True, True, False)}

    def describe(self):
        return "Lastiwka et al. (2009) method of characteristics"


# ---------------------------------------------------------------- the coupling
class OpenBoundary(Coupling):
    """Inflow/outflow zones of one fluid with a fixed buffer of spare particles ([TrixiBoundary]).

    Parameters
    ----------
    zones : InFlow | OutFlow | list of them
        The open boundary zones (they must not overlap).
    fluid_system : FluidSystem
        The fluid the zone particles join. The zone particles are added to
        its arrays when this object is created, so create it before the
        :class:`~seawall.Simulation` (and pass it among the systems).
    buffer_size : int
        Number of spare particles: how many more particles than at the start
        the fluid and the zones may hold together at any time. A run that
        needs more stops with a ParameterError naming buffer_size.
    boundary_model : Lastiwka, optional
        The open boundary model (default :class:`Lastiwka`).
    name : str
        Name in checkpoints and summary.json.
    """

    edac_refusal = ("its zone pressure is the equation of state of the fluid density, and with EDAC the "
                    "fluid's density does not set its pressure")

    def __init__(self, zones, *, fluid_system, buffer_size, boundary_model=None, name="open_boundary"):
        from .fluid.system import FluidSystem

        if isinstance(zones, _Zone):
            zones = [zones]
        zones = list(zones)
        if not zones or not all(isinstance(z, _Zone) for z in zones):
            raise ParameterError("zones must be one or more InFlow / OutFlow zones")
        if not isinstance(fluid_system, FluidSystem):
            raise ParameterError("fluid_system must be the seawall.FluidSystem the zones feed")
        if isinstance(buffer_size, bool) or int(buffer_size) != buffer_size or buffer_size < 0:
            raise ParameterError(f"buffer_size must be a non-negative integer, got {buffer_size!r}")
        self.model = Lastiwka() if boundary_model is None else boundary_model
        if not isinstance(self.model, Lastiwka):
            raise ParameterError(f"boundary_model must be seawall.openboundary.Lastiwka(), got {boundary_model!r}")
        fp = fluid_system.particles
        if "zone" in fp:
            raise ParameterError("this fluid already has an OpenBoundary: put all zones into one")
        for z in zones:
            if z.dim != fluid_system.dim:
                raise ParameterError(f"zone {z.name!r} is {z.dim}D but the fluid is {fluid_system.dim}D")
            if not math.isclose(z.spacing, fluid_system.spacing, rel_tol=1e-9):
                raise ParameterError(f"zone {z.name!r}: particle_spacing {z.spacing:g} must equal the fluid's "
                                     f"dx = {fluid_system.spacing:g}")
        self.name = str(name)
        self.fluid = fluid_system
        self.zones = zones
        self.buffer_size = int(buffer_size)
        self.free = self.buffer_size
        dim = fluid_system.dim
        n_fluid = fp.n
        fp.add("zone", np.full(n_fluid, -1, dtype=np.int64))
        fp.add("ob_slot", np.full(n_fluid, -1, dtype=np.int64))
        fp.add("ob_J", np.zeros((n_fluid, 3)))
        self.next_id = int(fp["id"].max()) + 1 if n_fluid else 0
        added = 0.0
        for k, z in enumerate(zones):
            x = z.positions
            m = x.shape[0]
            mass = z.density * z.spacing ** dim
            v0 = z.reference_velocity.at(x, np.arange(m), 0.0)
            fp.append(m, x=x, v=v0, m=mass, rho=z.density, zone=k, ob_slot=np.arange(m),
                      id=np.arange(self.next_id, self.next_id + m))
            self.next_id += m
            added += mass * m
        fluid_system.initial_mass += added
        self.n_initial_total = fp.n
        nz = len(zones)
        self.counts = {key: [0] * nz for key in
                       ("spawned", "to_fluid", "from_fluid", "recycled_out", "lost_upstream", "lost_lateral")}
        self.masses = {key: [0.0] * nz for key in ("spawned", "to_fluid", "from_fluid", "recycled_out", "lost")}
        self.lost_records = []   # (time, id, zone, face) of particles that left a zone the wrong way
        self._normals = np.zeros((nz, 3))
        for k, z in enumerate(zones):
            self._normals[k, :dim] = z.normal
        self._prm = None
        self._layout = None

    # ---------------------------------------------------------------- hooks
    def prepare(self, sim):
        if sim.fluid is not self.fluid:
            raise ParameterError(f"open boundary {self.name!r} was made for another fluid system")
        fp = sim.fluid.particles
        x = fp["x"]
        zone = fp["zone"]
        for k, z in enumerate(self.zones):
            bad = (zone == -1) & z.inside(x)
            if bad.any():
                i = int(np.argmax(bad))
                raise ParameterError(f"fluid particle at {x[i].tolist()} lies inside {z.label} zone {z.name!r}: "
                                     "the fluid block must end at the zone's plane")
        outside = ~sim.grid.inside(x[zone >= 0])
        if outside.any():
            raise ParameterError("open boundary zone particles lie outside the simulation domain: "
                                 "give a domain that contains every zone")
        self._prm = sim.physics
        self.apply_model(sim)

    def add_rates(self, sim, ctx):
        """Zone particles are not accelerated by the fluid: their state comes from the model."""
        fp = sim.fluid.particles
        idx = np.flatnonzero(fp["zone"] >= 0)
        if idx.size:
            fp["dv"][idx] = 0.0
            fp["drho"][idx] = 0.0
            fp["xsph"][idx] = 0.0

    def after_step(self, sim, dt):
        self.convert(sim)
        self.apply_model(sim)

    # ---------------------------------------------------------------- particle exchange
    def convert(self, sim):
        """Turn particles that crossed a zone's faces into fluid, zone particles or spares."""
        fp = sim.fluid.particles
        x = fp["x"]
        zone = fp["zone"]
        m = fp["m"]
        remove = np.zeros(fp.n, dtype=bool)
        spawn_src = []
        spawn_x = []
        spawn_zone = []
        spawn_slot = []
        for k, z in enumerate(self.zones):
            s, lateral = z.coordinates(x)
            in_box = lateral & z.inside_normal(s)
            enter = (zone == -1) & in_box
            if enter.any():
                zone[enter] = k
                fp["ob_slot"][enter] = z.nearest_slot(x[enter]) if z.per_particle_references else 0
                self.counts["from_fluid"][k] += int(enter.sum())
                self.masses["from_fluid"][k] += float(m[enter].sum())
            left = (zone == k) & ~in_box
            if not left.any():
                continue
            if z.kind == INFLOW:
                to_fluid = left & lateral & (s >= 0.0)
                upstream = left & lateral & (s < -z.depth)
                if to_fluid.any():
                    src = np.flatnonzero(to_fluid)
                    spawn_src.append(src)
                    spawn_x.append(x[src] - z.depth * z.normal)
                    spawn_zone.append(np.full(src.size, k))
                    spawn_slot.append(fp["ob_slot"][src].copy())
            else:
                to_fluid = left & lateral & (s < 0.0)
                out = left & lateral & (s >= z.depth)
                upstream = np.zeros_like(left)
                if out.any():
                    remove |= out
                    self.counts["recycled_out"][k] += int(out.sum())
                    self.masses["recycled_out"][k] += float(m[out].sum())
            side = left & ~lateral
            for mask, face in ((upstream, "upstream"), (side, "lateral")):
                if mask.any():
                    remove |= mask
                    self.counts[f"lost_{face}"][k] += int(mask.sum())
                    self.masses["lost"][k] += float(m[mask].sum())
                    for i in np.flatnonzero(mask)[:100]:
                        if len(self.lost_records) < 1000:
                            self.lost_records.append((sim.time, int(fp["id"][i]), k, face))
            if to_fluid.any():
                zone[to_fluid] = -1
                fp["ob_slot"][to_fluid] = -1
                self.counts["to_fluid"][k] += int(to_fluid.sum())
                self.masses["to_fluid"][k] += float(m[to_fluid].sum())
        n_spawn = sum(a.size for a in spawn_src)
        n_recycled = int(remove.sum())
        if n_spawn > self.free + n_recycled:
            raise ParameterError(
                f"open boundary {self.name!r}: the buffer is full at t = {sim.time:.6g} s ({n_spawn} particles "
                f"needed, {self.free + n_recycled} spare): increase buffer_size (now {self.buffer_size})")
        self.free += n_recycled
        if n_spawn:
            src = np.concatenate(spawn_src)
            new_zone = np.concatenate(spawn_zone)
            ids = np.arange(self.next_id, self.next_id + n_spawn)
            self.next_id += n_spawn
            fp.append_rows(src, x=np.concatenate(spawn_x), zone=new_zone, id=ids, ob_slot=np.concatenate(spawn_slot))
            self.free -= n_spawn
            for k in range(len(self.zones)):
                sel = new_zone == k
                if sel.any():
                    self.counts["spawned"][k] += int(sel.sum())
                    self.masses["spawned"][k] += float(fp["m"][src[sel]].sum())
            remove = np.concatenate([remove, np.zeros(n_spawn, dtype=bool)])
        if n_recycled:
            fp.keep(~remove)

    # ---------------------------------------------------------------- the model
    def references(self, k, x, slots, t):
        """(rho_ref, v_ref, p_ref) of zone k at positions x (gauge pressure)."""
        z = self.zones[k]
        v_ref = z.reference_velocity.at(x, slots, t)
        p_ref = z.reference_pressure.at(x, slots, t)
        if z.reference_density is not None:
            rho_ref = z.reference_density.at(x, slots, t)
        else:
            rho_ref = np.empty(x.shape[0])
            _eos_density_array(p_ref, self._prm, rho_ref)
        return rho_ref, v_ref, p_ref

    def apply_model(self, sim):
        """Set the density and velocity of every zone particle from the characteristic variables."""
        fp = sim.fluid.particles
        zone = fp["zone"]
        idx = np.flatnonzero(zone >= 0)
        if idx.size == 0:
            return
        g = sim.grid
        prm = sim.physics
        c = prm.c0
        x = fp["x"]
        cells = g.build(x)
        sums = np.zeros((idx.size, 4))
        characteristic_sums(g.layout, idx, x, fp["v"], fp["rho"], zone, self._normals, cells.start, cells.order,
                            g.lo, g.inv_cell, g.ncell, g.period, prm, sums)
        J = fp["ob_J"]
        supported = np.zeros(fp.n, dtype=np.uint8)
        zk = zone[idx]
        refs = []
        for k, z in enumerate(self.zones):
            sel = np.flatnonzero(zk == k)
            if sel.size == 0:
                refs.append(None)
                continue
            ii = idx[sel]
            rho_ref, v_ref, p_ref = self.references(k, x[ii], fp["ob_slot"][ii], sim.time)
            refs.append((sel, rho_ref, v_ref, p_ref))
            sw = sums[sel, 0]
            ok = sw > 0.0
            if ok.any():
                w = sw[ok]
                rbar = sums[sel, 1][ok] / w
                pbar = sums[sel, 2][ok] / w
                qbar = sums[sel, 3][ok] / w
                vref_n = v_ref[ok] @ z.normal
                dp = pbar - p_ref[ok]
                dq = c * (qbar - rbar * vref_n)
                Jk = np.stack([-c * c * (rbar - rho_ref[ok]) + dp, dq + dp, -dq + dp], axis=1)
                Jk[:, ~np.array(self.model.TRANSMITTED[z.kind])] = 0.0
                J[ii[ok]] = Jk
                supported[ii[ok]] = 1
        # zone particles out of the fluid's reach: average over supported zone neighbours, layer by layer
        out = np.zeros((idx.size, 3))
        found = np.zeros(idx.size, dtype=np.uint8)
        for _ in range(64):
            if supported[idx].all():
                break
            zone_neighbour_average(g.layout, idx, x, zone, supported, J, cells.start, cells.order, g.lo,
                                   g.inv_cell, g.ncell, g.period, prm, out, found)
            hit = found.astype(bool)
            if not hit.any():
                break
            J[idx[hit]] = out[hit]
            supported[idx[hit]] = 1
        for k, z in enumerate(self.zones):
            if refs[k] is None:
                continue
            sel, rho_ref, v_ref, p_ref = refs[k]
            ii = idx[sel]
            Jk = J[ii]
            Jk[:, ~np.array(self.model.TRANSMITTED[z.kind])] = 0.0
            J[ii] = Jk
            rho, v, _ = invert_characteristics(Jk[:, 0], Jk[:, 1], Jk[:, 2], rho_ref, v_ref, p_ref, c, z.normal)
            fp["rho"][ii] = rho
            fp["v"][ii] = v

    # ---------------------------------------------------------------- accounting
    def zone_particles(self, sim=None):
        """Number of particles in each zone."""
        zone = self.fluid.particles["zone"]
        return [int(np.count_nonzero(zone == k)) for k in range(len(self.zones))]

    def mass_added(self):
        """Mass the buffer put into the simulation minus what returned to it [kg (per m in 2D)]."""
        return float(sum(self.masses["spawned"]) - sum(self.masses["recycled_out"]) - sum(self.masses["lost"]))

    def net_inflow(self, k):
        """Net mass that entered the fluid region through zone k so far [kg (per m in 2D)]."""
        return self.masses["to_fluid"][k] - self.masses["from_fluid"][k]

    def state(self):
        return {"free": self.free, "next_id": self.next_id, "counts": self.counts, "masses": self.masses,
                "lost_records": [list(r) for r in self.lost_records]}

    def set_state(self, state):
        if not state:
            return
        self.free = int(state["free"])
        self.next_id = int(state["next_id"])
        self.counts = {k: [int(v) for v in vals] for k, vals in state["counts"].items()}
        self.masses = {k: [float(v) for v in vals] for k, vals in state["masses"].items()}
        self.lost_records = [tuple(r) for r in state.get("lost_records", [])]

    def summary(self):
        n_zone = self.zone_particles()
        zones = {}
        for k, z in enumerate(self.zones):
            zones[z.name] = {"type": z.label, "particles": n_zone[k],
                             **{key: vals[k] for key, vals in self.counts.items()},
                             "mass_into_fluid": self.net_inflow(k)}
        inflow = sum(self.net_inflow(k) for k, z in enumerate(self.zones) if z.kind == INFLOW)
        outflow = -sum(self.net_inflow(k) for k, z in enumerate(self.zones) if z.kind == OUTFLOW)
        lost = sum(self.counts["lost_upstream"]) + sum(self.counts["lost_lateral"])
        return {"buffer_size": self.buffer_size, "spare_particles": self.free, "zones": zones,
                "mass_in": inflow, "mass_out": outflow, "mass_added_by_buffer": self.mass_added(),
                "particles_left_zone_wrongly": lost,
                "n_fluid_proper": int(np.count_nonzero(self.fluid.particles["zone"] < 0))}

    def describe(self):
        kinds = ", ".join(f"{z.label} {z.name!r}" for z in self.zones)
        return f"open boundary ({kinds}; {self.model.describe()})"


# ---------------------------------------------------------------- probes
class FluidCount(Probe):
    """Number of fluid particles, zone (buffer) particles excluded."""

    def __init__(self, name="n_fluid"):
        super().__init__(name)

    def sample(self, sim):
        fp = sim.fluid.particles
        return float(np.count_nonzero(fp["zone"] < 0)) if "zone" in fp else float(fp.n)


class MaxSpeed(Probe):
    """Largest particle speed |v| of the fluid, zone particles excluded [m/s]."""

    unit = "m/s"

    def __init__(self, name="max_speed"):
        super().__init__(name)

    def sample(self, sim):
        fp = sim.fluid.particles
        v = fp["v"] if "zone" not in fp else fp["v"][fp["zone"] < 0]
        return float(np.sqrt((v * v).sum(axis=1)).max()) if v.shape[0] else 0.0


class ZoneInflow(Probe):
    """Net mass that entered the fluid through an open boundary zone so far [kg (per m in 2D)].

    With ``outward=True`` the net mass that left the fluid through it (an outflow's throughput).
    """

    def __init__(self, name, boundary, zone=0, outward=False):
        super().__init__(name)
        self.boundary = boundary
        self.zone = int(zone)
        self.sign = -1.0 if outward else 1.0

    def sample(self, sim):
        return float(self.sign * self.boundary.net_inflow(self.zone))
