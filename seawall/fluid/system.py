"""The weakly compressible fluid: particles plus their constitutive choices."""

import numpy as np

from ..eos import EquationOfState
from ..errors import ParameterError, require_nonnegative, require_positive
from ..particles import ParticleArrays, initial_velocity
from .models import ArtificialViscosity, LaminarViscosity, MolteniColagrossi, RiemannSolver
from .edac import as_pressure_model
from .regularisation import as_shifting, as_transport_velocity

DENSITY_MODES = ("continuity", "summation")


class FluidSystem:
    """A body of weakly compressible fluid.

    Parameters
    ----------
    shape : seawall.shapes.Shape
        Initial particle positions and spacing (e.g. ``shapes.rectangle``).
    rho0 : float
        Reference density [kg/m^3], default 1000.
    eos : EquationOfState
        Default ``Tait(c0=...)`` must be given: the speed of sound sets the
        time step and is problem dependent (~10 x the largest flow speed).
    viscosity : ArtificialViscosity | LaminarViscosity | list of both | None
        Default ``ArtificialViscosity(alpha=0.02)`` (Marrone et al. 2011).
    density_diffusion : MolteniColagrossi | DeltaSPH | None
        Default None.
    density : {"continuity", "summation"}
        Density by the continuity equation ([Li2022] eq. 8, default) or by
        summation (eq. 7).
    tensile_correction : bool
        Monaghan (2000) tensile correction, [Li2022] eq. 20 (default off).
    xsph : float
        XSPH epsilon of [Li2022] eq. 10 (0 = off, the seed uses 0.5).
    riemann : RiemannSolver, optional
        Riemann formulation of the continuity and momentum terms ([Zhang2017]);
        default None (central terms). Excludes artificial viscosity and density diffusion.
    velocity : array-like, optional
        Initial velocity, a constant vector or an (N, d) array [m/s].
    pressure : callable or array, optional
        Initial pressure [Pa] as an (N,) array or a function of the (N, d)
        positions; the density follows from the inverse EOS. Default: zero
        pressure (reference density).
    shifting : None, "none", "sun2017", "lind2012" or ParticleShifting
        Particle shifting along the concentration gradient with the
        free-surface correction ([Sun2017], [Lind2012]; seawall.fluid.regularisation).
        Default None (off).
    transport_velocity : None, bool or TransportVelocity
        Transport-velocity formulation of [Adami2013] (background-pressure
        advection velocity and the extra stress); ``True`` = p_b = rho0 c0^2,
        no free-surface correction (internal flows). Default None (off).
    pressure_model : None, "eos", "edac" or EDAC
        How the pressure is found: None / "eos" (default) from the density by the equation of
        state; "edac" (or ``seawall.fluid.EDAC(alpha=...)``) as a particle variable evolved by the
        entropically damped artificial compressibility equation of [Ramachandran2019]
        (seawall.fluid.edac). The EOS then only gives c0 and the initial pressure.
    """

    def __init__(self, shape, *, rho0=1000.0, eos=None, viscosity="default",
                 density_diffusion=None, density="continuity", tensile_correction=False,
                 xsph=0.0, velocity=None, pressure=None, shifting=None, transport_velocity=None,
                 name="fluid", riemann=None, pressure_model=None):
        x = np.ascontiguousarray(getattr(shape, "positions", None), dtype=np.float64)
        if x.ndim != 2 or x.shape[1] not in (2, 3) or x.shape[0] == 0:
            raise ParameterError(f"fluid positions must be an (N, 2) or (N, 3) array with N > 0, got {x.shape}")
        self.name = str(name)
        self.dim = x.shape[1]
        self.spacing = require_positive("dx", shape.spacing)
        self.rho0 = require_positive("rho0", rho0)
        if eos is None:
            raise ParameterError("eos is required, e.g. eos=seawall.Tait(c0=20.0)")
        if not isinstance(eos, EquationOfState):
            raise ParameterError(f"eos must be seawall.Tait or seawall.Linear, got {type(eos).__name__}")
        self.eos = eos
        if viscosity == "default":
            viscosity = ArtificialViscosity(alpha=0.02)
        models = [] if viscosity is None else (list(viscosity) if isinstance(viscosity, (list, tuple)) else [viscosity])
        self.artificial_viscosity = None
        self.laminar_viscosity = None
        for vm in models:
            if isinstance(vm, ArtificialViscosity):
                self.artificial_viscosity = vm
            elif isinstance(vm, LaminarViscosity):
                self.laminar_viscosity = vm
            else:
                raise ParameterError(f"viscosity must be ArtificialViscosity, LaminarViscosity, a list of them or None; got {vm!r}")
        if density_diffusion is not None and not isinstance(density_diffusion, MolteniColagrossi):
            raise ParameterError(f"density_diffusion must be MolteniColagrossi, DeltaSPH or None; got {density_diffusion!r}")
        self.density_diffusion = density_diffusion
        if riemann is not None:
            if not isinstance(riemann, RiemannSolver):
                raise ParameterError(f"riemann must be RiemannSolver or None; got {riemann!r}")
            if self.artificial_viscosity is not None and self.artificial_viscosity.alpha > 0:
                raise ParameterError("riemann: the Riemann formulation replaces the artificial viscosity; "
                                     "pass viscosity=None (or a LaminarViscosity)")
            if density_diffusion is not None and density_diffusion.delta > 0:
                raise ParameterError("riemann: the Riemann formulation replaces density diffusion; "
                                     "pass density_diffusion=None")
        self.riemann = riemann
        if density not in DENSITY_MODES:
            raise ParameterError(f"density must be one of {', '.join(DENSITY_MODES)}; got {density!r}")
        self.density_mode = density
        self.tensile_correction = bool(tensile_correction)
        self.xsph = require_nonnegative("xsph", xsph)
        self.shifting = as_shifting(shifting)
        self.transport_velocity = as_transport_velocity(transport_velocity)

        n = x.shape[0]
        pa = ParticleArrays(self.dim)
        pa.add("x", x)
        v = initial_velocity(velocity, n, self.dim)
        pa.add("v", v)
        pa.add("m", np.full(n, self.rho0 * self.spacing ** self.dim))
        if pressure is None:
            p0 = np.zeros(n)
        elif callable(pressure):
            p0 = np.asarray(pressure(x.copy()), dtype=np.float64).reshape(n)
        else:
            p0 = np.asarray(pressure, dtype=np.float64).reshape(n)
        rho = np.asarray(eos.density(p0 + eos.background_pressure, self.rho0), dtype=np.float64)
        pa.add("rho", rho)
        pa.add("p", np.zeros(n))
        pa.add("c", np.zeros(n))
        pa.add("id", np.arange(n, dtype=np.int64))
        self.particles = pa
        self.initial_mass = float(pa["m"].sum())
        self.pressure_model = None
        self.set_pressure_model(pressure_model)

    def set_pressure_model(self, pressure_model):
        """Set the pressure model (as the constructor takes it), refusing the combinations that make no
        sense with EDAC in one line each."""
        model = as_pressure_model(pressure_model)
        if model is not None:
            if self.riemann is not None:
                raise ParameterError("pressure_model=edac: the Riemann formulation's interface pressure and its density "
                                     "dissipation are built on the equation of state; use one or the other")
            if self.density_diffusion is not None and self.density_diffusion.delta > 0:
                raise ParameterError("pressure_model=edac: density diffusion (delta-SPH) smooths the density, which "
                                     "no longer sets the pressure (EDAC damps the pressure itself); set delta=0 "
                                     "(density_diffusion=None)")
        if model is not None and self.pressure_model is None:
            # EDAC evolves p from the pressure of the start: the equation of state of the initial density
            # (which the constructor took from the given initial pressure)
            pa = self.particles
            pa["p"][:] = np.asarray(self.eos.pressure(pa["rho"], self.rho0), dtype=np.float64).reshape(pa.n)
        self.pressure_model = model
        return model

    @property
    def edac(self):
        """The :class:`~seawall.fluid.edac.EDAC` pressure model, or None (equation of state)."""
        return self.pressure_model

    @property
    def n(self):
        return self.particles.n

    def __repr__(self):
        return f"FluidSystem({self.name!r}, n={self.n}, rho0={self.rho0}, eos={self.eos!r})"
