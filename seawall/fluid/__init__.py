"""The weakly compressible fluid system and its constitutive models."""

from .models import ArtificialViscosity, DeltaSPH, LaminarViscosity, MolteniColagrossi, RiemannSolver
from .system import FluidSystem

__all__ = ["FluidSystem", "ArtificialViscosity", "LaminarViscosity", "MolteniColagrossi", "DeltaSPH", "RiemannSolver"]
