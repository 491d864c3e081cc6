"""Couplings: parts of a simulation that act beside the fluid and the walls.

Some parts of a case are neither a fluid nor a wall model: a wall on a
spring whose motion follows the fluid's force, open inflow/outflow zones
that turn particles into fluid and back, a wave maker driven by a signal,
bodies integrated by their own equations. Each is a :class:`Coupling`
passed among the simulation's systems; the simulation calls its hooks at
fixed points of every step, so the core loop never learns about them:

``prepare(sim)``
    once, when the simulation is built (after the walls are prepared);
``add_rates(sim, ctx)``
    inside every evaluation of the rates, after the walls have acted:
    add accelerations to ``sim.fluid.particles["dv"]`` (and density rates
    to ``"drho"``); ``ctx`` is the walls' :class:`EvaluationContext`;
``after_step(sim, dt)``
    after the integrator advanced the fluid by ``dt`` and ``sim.time`` was
    updated, before the health check: may move walls, change the fluid's
    particle set (add or remove rows of every array at once), advance
    other bodies.

Whatever a coupling keeps between steps must be returned by ``state()``
(JSON-compatible scalars and lists) and ``arrays()`` (numpy arrays) so that
checkpoints continue a run bit for bit; ``summary()`` adds entries to the
run's ``summary.json`` under the coupling's name.
"""


class Coupling:
    """Base class of everything that takes part in a step beside the fluid and the walls."""

    #: unique name, used in checkpoints and in summary.json
    name = "coupling"
    #: None if the coupling works with a fluid whose pressure is its own variable (EDAC); otherwise the
    #: reason it does not, with which the simulation refuses the combination
    edac_refusal = None

    def prepare(self, sim):
        """Called once when the simulation is built."""

    def add_rates(self, sim, ctx):
        """Add to the fluid's rates during an evaluation (after the walls)."""

    def after_step(self, sim, dt):
        """Called after every step, once ``sim.time`` is the new time."""

    def state(self):
        """JSON-compatible scalars kept between steps (saved in checkpoints)."""
        return {}

    def set_state(self, state):
        """Restore what :meth:`state` returned."""

    def arrays(self):
        """Named numpy arrays kept between steps (saved in checkpoints)."""
        return {}

    def set_arrays(self, arrays):
        """Restore what :meth:`arrays` returned."""

    def mass_added(self):
        """Net mass this coupling put into the fluid's arrays so far (open boundaries) [kg];
        the run summary's mass drift discounts it."""
        return 0.0

    def summary(self):
        """Entries for summary.json (JSON-compatible)."""
        return {}

    def describe(self):
        return self.name
