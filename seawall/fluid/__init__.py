"""The weakly compressible fluid system and its constitutive models."""

from .edac import EDAC
from .models import ArtificialViscosity, DeltaSPH, LaminarViscosity, MolteniColagrossi, RiemannSolver
from .regularisation import ParticleShifting, TransportVelocity
from .system import FluidSystem

__all__ = ["FluidSystem", "EDAC", "ArtificialViscosity", "LaminarViscosity", "MolteniColagrossi", "DeltaSPH", "RiemannSolver",
           "ParticleShifting", "TransportVelocity"]
