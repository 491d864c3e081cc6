"""The wall interface: a wall system is particles plus a swappable wall model.

A :class:`WallModel` has two duties each time the fluid's rates are computed
(DESIGN.md, layer 6):

``update(wall, fluid, ctx)``
    set the wall particles' state (pressure, density, velocity used for
    viscosity) from the fluid, or advance it, before the fluid's rates;
``interact(fluid, wall, ctx, dv, drho)``
    add the wall's contribution to the fluid's acceleration ``dv`` and
    density rate ``drho``.

``ctx`` (:class:`EvaluationContext`) carries the compiled-parameter bundle,
the neighbour grid and the current cell lists. Models keep their compiled
loops in their own module, so adding a model never touches the fluid code.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import ParameterError, require_nonnegative
from ..particles import ParticleArrays, initial_velocity


@dataclass
class EvaluationContext:
    """What a wall model may read during one evaluation of the rates."""

    physics: object          # seawall.fluid.params.Physics
    grid: object             # seawall.neighbors.CellGrid
    fluid_cells: object      # CellList of the fluid at the evaluation positions
    time: float
    dx: float                # fluid particle spacing
    #: the fluid's rates of this evaluation (seawall.views.Rates: dv, drho, xsph, mu_max); None in
    #: contexts built by hand, where :func:`rates_bundle` falls back to the fluid's own arrays
    rates: object = None


def rates_bundle(fluid, ctx, dv, drho):
    """The :class:`~seawall.views.Rates` an ``interact`` writes: ``dv``, ``drho`` as given, and the
    XSPH correction and time-step viscosity (``xsph``, ``mu_max``) of this evaluation."""
    from ..views import Rates

    if ctx.rates is not None:
        return Rates(dv, drho, ctx.rates.xsph, ctx.rates.mu_max)
    fp = fluid.particles
    return Rates(dv, drho, fp["xsph"], fp["mu_max"])


class CrossTerms(NamedTuple):
    """Which of the fluid's pair terms (:data:`seawall.pairs.FLUID_TERMS`) act across a wall, as the
    0/1 flags a compiled wall loop reads (:meth:`WallModel.cross_terms`)."""

    continuity: int
    pressure: int
    tensile: int
    artificial_viscosity: int
    laminar_viscosity: int
    density_diffusion: int
    xsph: int
    shifting: int
    transport_velocity: int
    all_pairs: int          # the artificial viscosity acts on receding pairs too


class WallModel:
    """Base class of every wall treatment; subclasses implement update and interact.

    The contract a model declares (read by the simulation, the cases, the
    registry and the contract tests, so nothing is decided silently):

    ``layout``
        ``"layers"``: wall particles in layers continuing the fluid lattice
        (dummy, ghost, DBC); ``"surface"``: one row on the wall surface at
        spacing dx / ``beta`` (repulsive walls). The cases build the geometry
        the model asks for.
    :meth:`options`
        the keyword arguments of the constructor (``--set KEY=VALUE`` keys
        reach the model through its registry factory, see
        :func:`seawall.boundary.registry.boundary_options`).
    ``fluid_terms``
        the fluid's pair terms (:data:`seawall.pairs.FLUID_TERMS`) that act
        between a fluid particle and a wall particle.
    ``integrated_arrays``
        the wall particle arrays the model advances in time inside
        ``update`` (over the interval since its previous call, remembered
        by :meth:`state`); they and the state go into checkpoints.
    ``joins_summation_density``
        whether the wall's masses ``m`` count in a summation-density fluid's
        rho_i = sum_j m_j W_ij ([Li2022] eq. 7).
    :meth:`check`
        refuses a bad combination with the fluid in one line, before
        :meth:`prepare`.
    """

    #: name used on the command line and in reports
    name = "wall-model"
    #: "layers" (continuing the fluid lattice) or "surface" (one row at dx / beta)
    layout = "layers"
    #: the fluid's pair terms (names in :data:`seawall.pairs.FLUID_TERMS`) that act between a fluid
    #: particle and this wall's particles; a model may make it depend on its options (a property)
    fluid_terms = frozenset()
    #: names of the wall particle arrays advanced in time by ``update``
    integrated_arrays = ()
    #: whether the wall's masses join the fluid's summation density
    joins_summation_density = False
    #: None if the model works with a fluid whose pressure is its own variable (EDAC,
    #: seawall.fluid.edac): its wall state reads the fluid's pressure p, or no fluid state at all.
    #: Otherwise the reason it does not (one line), with which the simulation refuses the combination.
    edac_refusal = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        legacy = cls.__dict__.get("wall_layout")
        if isinstance(legacy, str):  # a model written before `layout` existed
            cls.layout = legacy

    @property
    def wall_layout(self):
        """Former name of :attr:`layout` (kept for code that reads it)."""
        return self.layout

    @classmethod
    def options(cls):
        """Names of the constructor's keyword arguments, in order."""
        return tuple(cls.option_defaults())

    @classmethod
    def option_defaults(cls):
        """The constructor's keyword arguments and their defaults, in order (name -> default;
        ``inspect.Parameter.empty`` for one without a default)."""
        import inspect

        params = inspect.signature(cls.__init__).parameters.values()
        return {p.name: p.default for p in params
                if p.name != "self" and p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}

    def cross_terms(self, physics):
        """:attr:`fluid_terms` as the :class:`CrossTerms` flags the compiled loops read."""
        from ..pairs import FLUID_TERMS

        terms = self.fluid_terms
        # the fluid's ArtificialViscosity(all_pairs=...) holds across the wall too
        return CrossTerms(*(int(name in terms) for name in FLUID_TERMS),
                          all_pairs=int(getattr(physics, "alpha_all_pairs", 0)))

    def check(self, fluid, physics):
        """Raise :class:`~seawall.errors.ParameterError` (one line) if this model cannot serve ``fluid``."""

    #: Does the wall push the fluid by one pair force per (fluid, wall) particle pair?
    #:
    #: True when the wall's contribution to fluid particle i's acceleration is a sum over wall
    #: particles b of terms f_ib / m_i, each depending only on the states of i and b (as set by
    #: ``update``): no normalisation over i's wall neighbourhood, no selection of one wall
    #: particle among several. Then each wall particle feels the reaction -f_ib, the reactions
    #: sum to the force the ``WallForce`` probe reports (minus the wall's share of the fluid's
    #: momentum change), and fluid + wall conserve linear momentum pair by pair (Newton's third
    #: law; [Huang2019] eq. 29 computes the wall force this way). Angular momentum is conserved too
    #: only when f_ib is also central (along r_ib); the normal-only push of Liu et al. (2015) is
    #: not. ``tests/contract`` checks the property for every model that declares True (the
    #: wall's push is additive over any split of its particles) and requires every model to
    #: declare it: ``None`` here means "not declared".
    pairwise_momentum = None

    def prepare(self, wall, fluid, physics):
        """Called once when the simulation is built: allocate and check the wall's arrays."""

    def update(self, wall, fluid, ctx):
        raise NotImplementedError

    def interact(self, fluid, wall, ctx, dv, drho):
        raise NotImplementedError

    def after_step(self, wall, fluid, sim):
        """Called after every time step with the step's final fluid state, before the removal
        guards (``seawall.health``); most models do nothing here."""

    def describe(self):
        """One line for summaries."""
        return self.name

    def state(self):
        """Scalars the model keeps between evaluations (saved in checkpoints); JSON-compatible."""
        return {}

    def set_state(self, state):
        """Restore what :meth:`state` returned."""


def noslip_viscosity(nu, physics):
    """Kinematic viscosity of a no-slip wall term: ``nu`` if given, else the fluid's laminar nu, else
    alpha h c0 / (2 d + 4) from its artificial viscosity (the equivalence given in [TrixiBoundary])."""
    if nu is not None:
        wall_nu = nu
    elif physics.nu > 0.0:
        wall_nu = physics.nu
    else:
        wall_nu = physics.alpha * physics.h * physics.c0 / (2 * physics.dim + 4)
    if wall_nu <= 0.0:
        raise ParameterError("slip='noslip' needs a viscosity: give nu or use a fluid with viscosity")
    return wall_nu


def check_contract(model):
    """Raise ParameterError if ``model`` declares something the core does not know (one line)."""
    from ..pairs import FLUID_TERMS

    if model.layout not in ("layers", "surface"):
        raise ParameterError(f"wall model {model.name!r}: layout must be 'layers' or 'surface', got {model.layout!r}")
    unknown = set(model.fluid_terms) - set(FLUID_TERMS)
    if unknown:
        raise ParameterError(f"wall model {model.name!r} declares unknown fluid term {sorted(unknown)[0]!r}; "
                             f"known: {', '.join(FLUID_TERMS)}")


class WallSystem:
    """Wall particles and the model that makes them act on the fluid.

    Parameters
    ----------
    shape : seawall.shapes.Shape
        Wall particle positions, spacing, normals and surface points (as
        produced by :func:`seawall.shapes.tank`).
    model : WallModel, optional
        The wall treatment; default dummy particles with Adami pressure
        extrapolation, free slip.
    velocity : array-like, optional
        Prescribed velocity of the wall particles [m/s] (constant), default 0.
    movement : seawall.boundary.movement.PrescribedMotion, optional
        Prescribed motion x(t) = x0 + f(t) of (some of) the particles.
    adhesion_coefficient : float
        beta of the Akinci et al. (2013) fluid-wall adhesion force ([TrixiBoundary];
        see :mod:`seawall.boundary.adhesion`), default 0 (none).
    name : str
        Used in messages and output file names.
    """

    def __init__(self, shape, *, model=None, velocity=None, movement=None, adhesion_coefficient=0.0,
                 name="wall"):
        from .dummy import DummyParticles  # the default model

        if shape is None or getattr(shape, "positions", None) is None:
            raise ParameterError("WallSystem needs a shape with positions (e.g. seawall.shapes.tank(...))")
        x = np.ascontiguousarray(shape.positions, dtype=np.float64)
        if x.ndim != 2 or x.shape[1] not in (2, 3) or x.shape[0] == 0:
            raise ParameterError(f"wall positions must be an (N, 2) or (N, 3) array with N > 0, got {x.shape}")
        self.name = str(name)
        self.adhesion_coefficient = require_nonnegative("adhesion_coefficient", adhesion_coefficient)
        self.dim = x.shape[1]
        self.spacing = float(shape.spacing)
        self.model = model if model is not None else DummyParticles()
        if not isinstance(self.model, WallModel):
            raise ParameterError(f"model must be a seawall wall model, got {type(self.model).__name__}")
        n = x.shape[0]
        self.particles = ParticleArrays(self.dim)
        self.particles.add("x", x)
        v = initial_velocity(velocity, n, self.dim)
        self.particles.add("v", v)
        self.particles.add("a", np.zeros((n, self.dim)))
        normals = getattr(shape, "normals", None)
        surface = getattr(shape, "surface_points", None)
        if normals is not None:
            self.particles.add("normal", np.ascontiguousarray(normals, dtype=np.float64))
        if surface is not None:
            self.particles.add("surface", np.ascontiguousarray(surface, dtype=np.float64))
        self.particles.add("id", np.arange(n, dtype=np.int64))
        self.cells = None
        self.movement = movement
        if movement is not None:
            movement.attach(self)

    @property
    def n(self):
        return self.particles.n

    @property
    def x(self):
        return self.particles["x"]

    def __repr__(self):
        return f"WallSystem({self.name!r}, n={self.n}, model={self.model.describe()})"
